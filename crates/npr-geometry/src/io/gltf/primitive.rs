//! Mesh instances' triangle primitives: positions, indices, normals and uvs, merged.

use std::collections::BTreeMap;

use glam::{Mat3, Mat4, Vec2, Vec3};
use gltf::mesh::{Mode, Semantic};

use super::Ctx;
use super::buffers::{read_accessor, vec3s};
use super::rig::{self, AnimVertices};
use crate::animation::{FileVertex, Instance, morph};
use crate::io::{LoadError, LoadNote, Raw, fan};

/// What a primitive needs to know of the instance it belongs to.
struct InstanceInfo<'w> {
    node: u32,
    mesh: u32,
    /// Index into [`Merged::instances`].
    instance: u32,
    /// The skin's joint count, when the instance is skinned.
    joints: Option<usize>,
    /// Default morph weights.
    weights: &'w [f32],
}

/// A mesh instance's world transform, for points, normals and winding.
struct Placement {
    /// Positions: the node's world matrix.
    world: Mat4,
    /// Normals: the inverse-transpose of the world matrix's linear part.
    normal: Mat3,
    /// Whether the transform mirrors, so triangles must be rewound.
    flip: bool,
}

impl Placement {
    /// The placement for a node's world matrix.
    fn new(world: Mat4) -> Self {
        Self {
            world,
            normal: Mat3::from_mat4(world).inverse().transpose(),
            flip: Mat3::from_mat4(world).determinant() < 0.0,
        }
    }
}

/// The triangle primitives of every instance merged so far, and what the report says.
#[derive(Default)]
pub(super) struct Merged {
    raw: Raw,
    /// Whether some primitive has NORMAL.
    any_normals: bool,
    /// Whether some primitive lacks NORMAL.
    some_without_normals: bool,
    /// Whether some primitive has TEXCOORD_0.
    any_uvs: bool,
    /// Point and line primitives skipped, by mode.
    skipped: BTreeMap<String, usize>,
    /// Strip and fan primitives converted.
    strips: usize,
    /// Instances with a transform other than the identity.
    placed: usize,
    /// Per-vertex animation data, when the file has a skin, morph or animation.
    anim: Option<AnimVertices>,
    /// The instances (filled with `anim`).
    instances: Vec<Instance>,
    /// Skinned instances whose node transform was not the identity.
    skinned_ignored: usize,
}

impl Merged {
    /// An empty merge; `animated`: also collect what a rig needs.
    pub(super) fn new(animated: bool) -> Self {
        Self {
            anim: animated.then(AnimVertices::default),
            ..Self::default()
        }
    }

    /// Adds every triangle primitive of `mesh`, instanced by `node` and placed by
    /// `world`; a skinned instance ignores `world` (glTF 2.0, §3.7.3), and morph targets
    /// are applied with the instance's default weights.
    pub(super) fn instance(
        &mut self,
        mesh: &gltf::Mesh<'_>,
        node: Option<&gltf::Node<'_>>,
        world: Mat4,
        buffers: &[Vec<u8>],
        c: &Ctx<'_>,
    ) -> Result<(), LoadError> {
        let skin = node.and_then(gltf::Node::skin);
        let world = match skin {
            Some(_) => {
                if world != Mat4::IDENTITY {
                    self.skinned_ignored += 1;
                }
                Mat4::IDENTITY
            }
            None => world,
        };
        if world != Mat4::IDENTITY {
            self.placed += 1;
        }
        let weights = rig::default_weights(node, mesh, c)?;
        let node_index = node.map_or(usize::MAX, gltf::Node::index);
        let info = InstanceInfo {
            node: node_index as u32,
            mesh: mesh.index() as u32,
            instance: self.instances.len() as u32,
            joints: skin.as_ref().map(|s| s.joints().count()),
            weights: &weights,
        };
        let place = Placement::new(world);
        for prim in mesh.primitives() {
            let at = format!("mesh {} primitive {}", mesh.index(), prim.index());
            let mode = prim.mode();
            if !matches!(
                mode,
                Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
            ) {
                *self.skipped.entry(format!("{mode:?}")).or_insert(0usize) += 1;
                continue;
            }
            self.primitive(&prim, &at, &place, &info, buffers, c)?;
        }
        if self.anim.is_some() {
            self.instances.push(Instance {
                node: node_index,
                skin: skin.map(|s| s.index()),
                weights,
            });
        }
        Ok(())
    }

    /// Adds one triangle primitive: positions, triangles, normals and uvs.
    fn primitive(
        &mut self,
        prim: &gltf::Primitive<'_>,
        at: &str,
        place: &Placement,
        info: &InstanceInfo<'_>,
        buffers: &[Vec<u8>],
        c: &Ctx<'_>,
    ) -> Result<(), LoadError> {
        let positions = primitive_positions(prim, at, buffers, c)?;
        let n = positions.len();
        let targets = rig::morph_targets(prim, n, at, buffers, c)?;
        if !targets.is_empty() && targets.len() != info.weights.len() {
            return Err(c.anim(
                at,
                crate::animation::AnimationError::MorphTarget {
                    target: targets.len().min(info.weights.len()),
                    reason: format!(
                        "{} targets, the mesh has {} weights",
                        targets.len(),
                        info.weights.len()
                    ),
                },
            ));
        }
        let deltas = |v: usize, normal: bool| -> Vec<Vec3> {
            targets
                .iter()
                .map(|(p, n)| if normal { n[v] } else { p[v] })
                .collect()
        };
        let ids = primitive_indices(prim, n, at, buffers, c)?;
        let mode = prim.mode();
        if matches!(mode, Mode::TriangleStrip | Mode::TriangleFan) {
            self.strips += 1;
        }
        let mut tris = triangle_list(mode, &ids);
        if place.flip {
            for t in &mut tris {
                t.swap(1, 2);
            }
        }
        let raw = &mut self.raw;
        let base = raw.positions.len() as u32;
        raw.triangles
            .extend(tris.iter().map(|t| t.map(|i| i + base)));
        raw.positions
            .extend(positions.iter().enumerate().map(|(v, &p)| {
                let p = if targets.is_empty() {
                    p
                } else {
                    morph(p, info.weights, &deltas(v, false))
                };
                place.world.transform_point3(p)
            }));
        let normals = self.normals(prim, n, buffers, c)?;
        match &normals {
            Some(file) => self
                .raw
                .normals
                .extend(file.iter().enumerate().map(|(v, &nv)| {
                    let nv = if targets.is_empty() {
                        nv
                    } else {
                        morph(nv, info.weights, &deltas(v, true))
                    };
                    (place.normal * nv).normalize_or_zero()
                })),
            None => self.raw.normals.extend(std::iter::repeat_n(Vec3::ZERO, n)),
        }
        self.uvs(prim, n, buffers, c)?;
        let Some(anim) = &mut self.anim else {
            return Ok(());
        };
        anim.base_positions.extend_from_slice(&positions);
        match normals {
            Some(file) => anim.base_normals.extend(file),
            None => anim.base_normals.extend(std::iter::repeat_n(Vec3::ZERO, n)),
        }
        anim.source.extend((0..n as u32).map(|v| FileVertex {
            node: info.node,
            mesh: info.mesh,
            primitive: prim.index() as u32,
            vertex: v,
        }));
        anim.instance.extend(std::iter::repeat_n(info.instance, n));
        match info.joints {
            Some(joints) => {
                let (inf, normalised) = rig::skin_influences(prim, n, joints, at, buffers, c)?;
                anim.normalised += normalised;
                anim.influences.extend(inf);
            }
            None => anim.influences.extend(std::iter::repeat_n(Vec::new(), n)),
        }
        anim.morphs.extend((0..n).map(|v| {
            targets
                .iter()
                .map(|(p, nn)| (p[v], nn[v]))
                .collect::<Vec<_>>()
        }));
        Ok(())
    }

    /// The primitive's NORMALs as the file has them, or `None` when it has none.
    fn normals(
        &mut self,
        prim: &gltf::Primitive<'_>,
        n: usize,
        buffers: &[Vec<u8>],
        c: &Ctx<'_>,
    ) -> Result<Option<Vec<Vec3>>, LoadError> {
        match prim.get(&Semantic::Normals) {
            Some(acc) => {
                self.any_normals = true;
                let normals = vec3s(&acc, buffers, c)?;
                if normals.len() != n {
                    return Err(c.parse(
                        format!("accessor {}", acc.index()),
                        format!("{} normals for {n} positions", normals.len()),
                    ));
                }
                Ok(Some(normals))
            }
            None => {
                self.some_without_normals = true;
                Ok(None)
            }
        }
    }

    /// Appends the primitive's TEXCOORD_0, or zeros when it has none.
    fn uvs(
        &mut self,
        prim: &gltf::Primitive<'_>,
        n: usize,
        buffers: &[Vec<u8>],
        c: &Ctx<'_>,
    ) -> Result<(), LoadError> {
        match prim.get(&Semantic::TexCoords(0)) {
            Some(acc) => {
                self.any_uvs = true;
                let (v, dims) = read_accessor(&acc, buffers, c)?;
                if dims != 2 || v.len() != 2 * n {
                    return Err(c.parse(
                        format!("accessor {}", acc.index()),
                        format!("TEXCOORD_0 must be {n} VEC2"),
                    ));
                }
                self.raw.uvs.extend(
                    v.chunks_exact(2)
                        .map(|p| Vec2::new(p[0] as f32, p[1] as f32)),
                );
            }
            None => self.raw.uvs.extend(std::iter::repeat_n(Vec2::ZERO, n)),
        }
        Ok(())
    }

    /// The merged mesh with its notes, and the rig's instances and per-vertex data when
    /// collected; `instances` is how many the scene placed.
    pub(super) fn into_raw(self, instances: usize) -> (Raw, Option<(Vec<Instance>, AnimVertices)>) {
        let mut raw = self.raw;
        if self.some_without_normals {
            if self.any_normals {
                raw.normals_incomplete = Some("some glTF primitives have no NORMAL");
            }
            raw.normals.clear();
        }
        if !self.any_uvs {
            raw.uvs.clear();
        }
        let skipped_total: usize = self.skipped.values().sum();
        for (mode, count) in &self.skipped {
            raw.notes.push(LoadNote::Skipped {
                what: format!("glTF primitives of mode {mode}"),
                count: *count,
            });
        }
        if self.strips > 0 {
            raw.notes.push(LoadNote::StripsConverted {
                primitives: self.strips,
            });
        }
        if self.placed > 0 {
            raw.notes.push(LoadNote::TransformsApplied {
                instances: self.placed,
            });
        }
        if self.skinned_ignored > 0 {
            raw.notes.push(LoadNote::SkinnedTransformIgnored {
                instances: self.skinned_ignored,
            });
        }
        let normalised = self.anim.as_ref().map_or(0, |a| a.normalised);
        if normalised > 0 {
            raw.notes.push(LoadNote::WeightsNormalised {
                vertices: normalised,
            });
        }
        raw.found = format!(
            "{instances} mesh instance(s) in the scene, {skipped_total} point/line primitive(s)"
        );
        (raw, self.anim.map(|a| (self.instances, a)))
    }
}

/// The primitive's POSITIONs (untransformed), every one finite.
fn primitive_positions(
    prim: &gltf::Primitive<'_>,
    at: &str,
    buffers: &[Vec<u8>],
    c: &Ctx<'_>,
) -> Result<Vec<Vec3>, LoadError> {
    let pos = prim
        .get(&Semantic::Positions)
        .ok_or_else(|| c.parse(at, "no POSITION attribute"))?;
    let positions = vec3s(&pos, buffers, c)?;
    if let Some(k) = positions.iter().position(|p| !p.is_finite()) {
        return Err(LoadError::NonFinite {
            file: c.file.to_string(),
            at: format!("{at}, POSITION element {k}"),
            what: format!("position {:?}", positions[k].to_array()),
        });
    }
    Ok(positions)
}

/// The primitive's vertex indices, each below `n`; `0..n` when it has no indices.
fn primitive_indices(
    prim: &gltf::Primitive<'_>,
    n: usize,
    at: &str,
    buffers: &[Vec<u8>],
    c: &Ctx<'_>,
) -> Result<Vec<u32>, LoadError> {
    let Some(acc) = prim.indices() else {
        return Ok((0..n as u32).collect());
    };
    let (v, _) = read_accessor(&acc, buffers, c)?;
    let mut ids = Vec::with_capacity(v.len());
    for x in v {
        if !(x >= 0.0 && (x as usize) < n) {
            return Err(LoadError::IndexOutOfRange {
                file: c.file.to_string(),
                at: format!("{at} (indices accessor {})", acc.index()),
                index: x as i64,
                count: n,
            });
        }
        ids.push(x as u32);
    }
    Ok(ids)
}

/// The triangles of a triangle list, strip or fan, all wound like the first one.
fn triangle_list(mode: Mode, ids: &[u32]) -> Vec<[u32; 3]> {
    // Strips: every other triangle has its first two vertices swapped.
    match mode {
        Mode::TriangleStrip => ids
            .windows(3)
            .enumerate()
            .map(|(k, w)| {
                if k % 2 == 0 {
                    [w[0], w[1], w[2]]
                } else {
                    [w[1], w[0], w[2]]
                }
            })
            .collect(),
        Mode::TriangleFan => {
            let mut t = Vec::new();
            fan(ids, &mut t);
            t
        }
        _ => ids.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect(),
    }
}
