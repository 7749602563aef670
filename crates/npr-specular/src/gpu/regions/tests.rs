//! The region pass's record layouts and seeds.

use super::records::*;
use super::*;

#[test]
fn records_match_wgsl() {
    // `RegionParams` and `Seed` are bound inside `RegionFrameData`: their sizes and
    // the seeds' offset are checked there, their fields here.
    npr_gpu::assert_wgsl_layout!(
        crate::shaders::ALL,
        FrameData,
        "RegionFrameData",
        [params, seeds]
    );
    assert_eq!(
        [
            std::mem::offset_of!(Params, normal_from_object),
            std::mem::offset_of!(Params, light),
            std::mem::offset_of!(Params, eye),
            std::mem::offset_of!(Params, seed_count),
            std::mem::offset_of!(Params, capacity),
        ],
        [64, 128, 144, 160, 172]
    );
    assert_eq!(
        [
            std::mem::offset_of!(SeedRecord, n),
            std::mem::offset_of!(SeedRecord, start),
            std::mem::size_of::<SeedRecord>(),
        ],
        [16, 64, 80]
    );
    npr_gpu::assert_wgsl_layout!(
        crate::shaders::ALL,
        VertexRecord,
        "RegionVertex",
        [position, normal]
    );
    npr_gpu::assert_wgsl_layout!(crate::shaders::ALL, FaceRecord, "RegionFace", [tri, normal]);
    npr_gpu::assert_wgsl_layout!(
        crate::shaders::ALL,
        FitRecord,
        "RegionFit",
        [moments, second, ellipse, fit, flags, piece_count, pieces]
    );
    // `RegionPiece` is bound only inside `RegionFit`: its array's offset and size are
    // checked there, its two fields here.
    assert_eq!(std::mem::size_of::<PieceRecord>(), 32);
}

#[test]
fn a_seed_on_an_earlier_seeds_face_is_covered() {
    use glam::Vec3;
    let centre = |face| HighlightCentre {
        face,
        alpha: 0.3,
        beta: 0.3,
        position_object: Vec3::ZERO,
        position_world: Vec3::ZERO,
        normal_object: Vec3::Z,
        normal_world: Vec3::Z,
        dir_kappa_max: Vec3::X,
        dir_kappa_min: Vec3::Y,
        kappa_max: 1.0,
        kappa_min: 0.5,
    };
    let seeds = [(centre(3), 0.9), (centre(5), 0.9), (centre(3), 0.9)];
    let records = seed_records(&seeds, 10);
    let covered: Vec<u32> = records.iter().map(|r| r.start[1]).collect();
    assert_eq!(covered, [0, 0, 1]);
    // A seed with no frame grows nothing and covers nothing.
    let flat = HighlightCentre {
        normal_world: Vec3::ZERO,
        ..centre(7)
    };
    let records = seed_records(&[(flat, 0.9), (centre(7), 0.9)], 10);
    assert_eq!(records[0].start[0], u32::MAX);
    assert_eq!(records[1].start[1], 0);
}

#[test]
fn the_tracking_table_matches_wgsl() {
    use super::tracked::{TrackData, TrackParams, TrackedRecord};
    npr_gpu::assert_wgsl_layout!(
        crate::shaders::ALL,
        TrackData,
        "TrackData",
        [params, previous]
    );
    // `TrackParams` and `TrackedHighlight` are bound inside `TrackData`.
    assert_eq!(
        [
            std::mem::offset_of!(TrackParams, room),
            std::mem::offset_of!(TrackParams, sigma),
            std::mem::offset_of!(TrackParams, next_id),
            std::mem::offset_of!(TrackParams, status),
            std::mem::size_of::<TrackParams>(),
            std::mem::offset_of!(TrackedRecord, sigma),
            std::mem::offset_of!(TrackedRecord, centre),
            std::mem::offset_of!(TrackedRecord, footprint),
            std::mem::offset_of!(TrackedRecord, state),
            std::mem::size_of::<TrackedRecord>(),
        ],
        [4, 8, 16, 28, 32, 16, 32, 144, 176, 208]
    );
}
