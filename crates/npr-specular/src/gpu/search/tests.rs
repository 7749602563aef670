//! The search pass's layouts, readback decoding and row folding.

use super::readback::decode;
use super::*;

/// More listed clusters than a row of the indirect dispatch holds (over 4.19M faces at
/// the default limit) fold into more rows: rows of 3 here, on a torus under a light
/// whose highlights fall in several clusters, give the centres of one row.
#[test]
fn listed_clusters_fold_into_rows() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("listed_clusters_fold_into_rows") else {
        return;
    };
    let mesh = npr_geometry::generate::torus(1.0, 0.35, 64, 32);
    let set = crate::HighlightSet::new(&mesh, &npr_geometry::CurvatureOptions::default())
        .expect("a torus");
    let light_eye = npr_geometry::LightEye::Directions {
        to_light: glam::Vec3::new(0.3, 0.8, 0.5).normalize(),
        to_eye: glam::Vec3::Z,
    };
    let search = |row: u32| {
        let mut pass = CentreSearchPass::new(&ctx.device);
        pass.row = row;
        let mut object = pass.create_object(&ctx.device, set.search()).expect("fits");
        let input = SearchInput {
            frame: FrameId(1),
            search: set.search(),
            light_eye,
            world_from_object: Mat4::IDENTITY,
        };
        let solved = pass
            .search_now(&ctx.device, &ctx.queue, &mut object, &input)
            .expect("searched");
        let mut faces: Vec<u32> = solved.faces.iter().map(|f| f.face).collect();
        faces.sort_unstable();
        (faces, solved.clusters_solved)
    };
    let (folded, listed) = search(3);
    let (whole, listed_whole) = search(65_535);
    assert!(listed > 3, "{listed} clusters listed: fewer than a row");
    assert_eq!((folded, listed), (whole, listed_whole));
}

#[test]
fn a_list_decodes_its_entries_and_knows_when_it_overflowed() {
    let list = [(7u32, 0.25f32, 0.5f32), (9, 0.1, 0.2)];
    // Header (accepted, clusters, merged), `capacity` entries, then the centre records:
    // record k at the point (k, 2k, 3k), valid for even k.
    let bytes = |accepted: u32, merged: u32, capacity: usize| {
        let mut b = Vec::new();
        let mut put = |w: u32| b.extend_from_slice(&w.to_le_bytes());
        for w in [accepted, 5, merged, 2] {
            put(w);
        }
        for k in 0..capacity {
            let (face, a, c) = list[k % 2];
            for w in [face, a.to_bits(), c.to_bits(), 0] {
                put(w);
            }
        }
        for k in 0..MAX_MERGED {
            let x = k as f32;
            let valid = if k % 2 == 0 { 1.0f32 } else { 0.0 };
            let floats = [
                [x, 2.0 * x, 3.0 * x, valid],
                [x + 1.0, 0.0, 0.0, 1.0],
                [0.0, 0.0, 1.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [1.0, 0.0, 0.0, 0.0],
                [2.5, -0.5, 0.0, 0.0],
            ];
            for w in floats.iter().flatten() {
                put(w.to_bits());
            }
            for w in [100 + k as u32, 0.25f32.to_bits(), 0.5f32.to_bits(), 0] {
                put(w);
            }
        }
        b
    };
    assert_eq!(
        bytes(0, 0, 2).len() as u64,
        super::readback::readback_bytes(2)
    );
    let s = decode(&bytes(3, 1, 2), 2, Some(0.9));
    assert_eq!((s.accepted, s.clusters_solved), (3, 5));
    assert!(!s.complete());
    assert_eq!(s.centres, None, "an overflowed list is not merged");
    let whole = |(face, alpha, beta): (u32, f32, f32)| FaceSolution { face, alpha, beta };
    assert_eq!(s.faces, list.map(whole).to_vec());
    let s = decode(&bytes(2, 4, 2), 2, Some(0.9));
    assert!(s.complete());
    // The two records after the merged four are the peaks: the even one valid.
    let peaks = s.peaks.expect("looked for");
    assert_eq!(peaks.iter().map(|c| c.face).collect::<Vec<_>>(), [104]);
    assert_eq!(
        decode(&bytes(2, 4, 2), 2, None).peaks,
        None,
        "not looked for"
    );
    let centres = s.centres.expect("merged");
    // Records 0 and 2 of 4: the odd ones have no centre.
    assert_eq!(
        centres.iter().map(|c| c.face).collect::<Vec<_>>(),
        [100, 102]
    );
    let c = centres[1];
    assert_eq!(
        (c.alpha, c.beta, c.position_object, c.position_world),
        (
            0.25,
            0.5,
            glam::Vec3::new(2.0, 4.0, 6.0),
            glam::Vec3::new(3.0, 0.0, 0.0)
        )
    );
    assert_eq!(
        (c.normal_object, c.normal_world),
        (glam::Vec3::Z, glam::Vec3::Y)
    );
    assert_eq!(
        (c.dir_kappa_max, c.dir_kappa_min),
        (glam::Vec3::X, -glam::Vec3::Z)
    );
    assert_eq!((c.kappa_max, c.kappa_min), (2.5, -0.5));
    let s = decode(&bytes(2, NO_MERGE, 2), 2, Some(0.9));
    assert_eq!(s.centres, None, "more centres than the merge keeps");
    assert_eq!(s.peaks, None, "no peaks without merged centres");
    assert!(decode(&bytes(0, 0, 0)[..16], 0, None).faces.is_empty());
}
