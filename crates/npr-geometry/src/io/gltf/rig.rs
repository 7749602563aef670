//! Skins, morph targets, the node tree and animations: what a [`Rig`] needs, read with
//! the same checked accessor reader as the geometry.

use glam::{Mat4, Quat, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::animation::Property as GltfProperty;
use gltf::mesh::Semantic;

use super::Ctx;
use super::buffers::{read_accessor, vec3s};
use crate::animation::{
    AnimationError, Channel, Clip, FileVertex, Instance, Interpolation, Node, Property, Rig,
    Sampler, Skin, Trs,
};
use crate::io::{LoadError, Loaded};

impl Ctx<'_> {
    pub(super) fn anim(&self, at: impl Into<String>, error: AnimationError) -> LoadError {
        LoadError::Animation {
            file: self.file.to_string(),
            at: at.into(),
            error: Box::new(error),
        }
    }
}

/// Per raw vertex (in the order the merged mesh has them before cleaning): what posing
/// needs. Filled only for files that have a skin, a morph target or an animation.
#[derive(Default)]
pub(crate) struct AnimVertices {
    pub base_positions: Vec<Vec3>,
    pub base_normals: Vec<Vec3>,
    pub source: Vec<FileVertex>,
    pub instance: Vec<u32>,
    /// Per vertex, its (joint, weight) pairs; empty for vertices a node places.
    pub influences: Vec<Vec<(u16, f32)>>,
    /// Per vertex, one (position, normal) delta per morph target.
    pub morphs: Vec<Vec<(Vec3, Vec3)>>,
    /// Vertices whose weights were normalised.
    pub normalised: usize,
}

/// The parts of a [`Rig`] read from the document, before the mesh is cleaned.
pub(crate) struct RigParts {
    pub nodes: Vec<Node>,
    pub order: Vec<usize>,
    pub skins: Vec<Skin>,
    pub instances: Vec<Instance>,
    pub clips: Vec<Clip>,
    pub vertices: AnimVertices,
}

impl RigParts {
    /// The rig of `loaded`, whose vertex `v` was raw vertex `kept[v]`.
    pub(crate) fn into_rig(self, kept: &[u32], loaded: &Loaded) -> Rig {
        let a = self.vertices;
        let pick = |i: &u32| *i as usize;
        let mut base = loaded.mesh.clone();
        base.positions = kept.iter().map(|i| a.base_positions[pick(i)]).collect();
        base.normals = kept.iter().map(|i| a.base_normals[pick(i)]).collect();
        let mut influence_offsets = vec![0u32];
        let mut influences = Vec::new();
        let mut morph_offsets = vec![0u32];
        let (mut morph_positions, mut morph_normals) = (Vec::new(), Vec::new());
        for i in kept {
            influences.extend_from_slice(&a.influences[pick(i)]);
            influence_offsets.push(influences.len() as u32);
            for &(p, n) in &a.morphs[pick(i)] {
                morph_positions.push(p);
                morph_normals.push(n);
            }
            morph_offsets.push(morph_positions.len() as u32);
        }
        let recompute_normals = loaded
            .report
            .iter()
            .any(|n| matches!(n, crate::io::LoadNote::NormalsRecomputed { .. }));
        let weld_rep = crate::animation::weld_representatives(&loaded.mesh);
        Rig {
            nodes: self.nodes,
            order: self.order,
            skins: self.skins,
            instances: self.instances,
            clips: self.clips,
            base,
            source: kept.iter().map(|i| a.source[pick(i)]).collect(),
            vertex_instance: kept.iter().map(|i| a.instance[pick(i)]).collect(),
            influence_offsets,
            influences,
            morph_offsets,
            morph_positions,
            morph_normals,
            recompute_normals,
            weld_rep,
        }
    }
}

/// Whether the document has anything a rig holds.
pub(super) fn has_animation(doc: &gltf::Document) -> bool {
    doc.skins().next().is_some()
        || doc.animations().next().is_some()
        || doc
            .meshes()
            .any(|m| m.primitives().any(|p| p.morph_targets().next().is_some()))
}

/// The default morph weights of `node`'s instance of `mesh` (glTF 2.0, §3.7.2.2: the
/// node's `weights` override the mesh's; zeros when neither gives any).
pub(super) fn default_weights(
    node: Option<&gltf::Node<'_>>,
    mesh: &gltf::Mesh<'_>,
    c: &Ctx<'_>,
) -> Result<Vec<f32>, LoadError> {
    let targets = mesh
        .primitives()
        .map(|p| p.morph_targets().count())
        .max()
        .unwrap_or(0);
    let w = node
        .and_then(|n| n.weights())
        .or_else(|| mesh.weights())
        .map_or_else(|| vec![0.0; targets], <[f32]>::to_vec);
    let at = format!("mesh {}", mesh.index());
    if w.len() != targets {
        return Err(c.anim(
            at,
            AnimationError::MorphTarget {
                target: w.len().min(targets),
                reason: format!("{} default weights for {targets} targets", w.len()),
            },
        ));
    }
    if let Some(k) = w.iter().position(|x| !x.is_finite()) {
        return Err(c.anim(
            at,
            AnimationError::MorphTarget {
                target: k,
                reason: "non-finite default weight".into(),
            },
        ));
    }
    Ok(w)
}

/// Per morph target, its POSITION and NORMAL deltas.
pub(super) type Targets = Vec<(Vec<Vec3>, Vec<Vec3>)>;

/// Per vertex, its (joint, weight) pairs.
pub(super) type Influences = Vec<Vec<(u16, f32)>>;

/// The primitive's morph targets: per target, POSITION and NORMAL deltas, `n` each
/// (zeros for an attribute the target lacks).
pub(super) fn morph_targets(
    prim: &gltf::Primitive<'_>,
    n: usize,
    at: &str,
    buffers: &[Vec<u8>],
    c: &Ctx<'_>,
) -> Result<Targets, LoadError> {
    let read = |acc: Option<gltf::Accessor<'_>>, k: usize, what: &str| {
        let Some(acc) = acc else {
            return Ok(vec![Vec3::ZERO; n]);
        };
        // No bufferView and no sparse: all zeros (glTF 2.0, §3.6.2.1).
        let v = if acc.view().is_none() && acc.sparse().is_none() {
            vec![Vec3::ZERO; acc.count()]
        } else {
            vec3s(&acc, buffers, c)?
        };
        if v.len() != n {
            return Err(c.anim(
                at,
                AnimationError::MorphTarget {
                    target: k,
                    reason: format!("{} {what} deltas for {n} vertices", v.len()),
                },
            ));
        }
        if let Some(i) = v.iter().position(|d| !d.is_finite()) {
            return Err(c.anim(
                at,
                AnimationError::MorphTarget {
                    target: k,
                    reason: format!("non-finite {what} delta at vertex {i}"),
                },
            ));
        }
        Ok(v)
    };
    prim.morph_targets()
        .enumerate()
        .map(|(k, t)| {
            Ok((
                read(t.positions(), k, "POSITION")?,
                read(t.normals(), k, "NORMAL")?,
            ))
        })
        .collect()
}

/// Per vertex of the primitive, its (joint, weight) pairs from `JOINTS_n` / `WEIGHTS_n`:
/// zero weights dropped, the rest normalised to sum to 1. Also returns how many vertices
/// had weights off 1 by more than rounding.
pub(super) fn skin_influences(
    prim: &gltf::Primitive<'_>,
    n: usize,
    joints: usize,
    at: &str,
    buffers: &[Vec<u8>],
    c: &Ctx<'_>,
) -> Result<(Influences, usize), LoadError> {
    let mut out: Vec<Vec<(u16, f32)>> = vec![Vec::new(); n];
    for set in 0u32.. {
        let (Some(j_acc), w_acc) = (
            prim.get(&Semantic::Joints(set)),
            prim.get(&Semantic::Weights(set)),
        ) else {
            if set == 0 {
                return Err(c.anim(
                    at,
                    AnimationError::MissingSkinAttribute {
                        attribute: "JOINTS_0",
                    },
                ));
            }
            break;
        };
        let Some(w_acc) = w_acc else {
            return Err(c.anim(
                at,
                AnimationError::MissingSkinAttribute {
                    attribute: if set == 0 { "WEIGHTS_0" } else { "WEIGHTS_n" },
                },
            ));
        };
        check_skin_types(&j_acc, &w_acc, set, at, c)?;
        let (j, _) = read_accessor(&j_acc, buffers, c)?;
        let (w, _) = read_accessor(&w_acc, buffers, c)?;
        if j.len() != 4 * n || w.len() != 4 * n {
            return Err(c.parse(
                at,
                format!(
                    "JOINTS_{set}/WEIGHTS_{set} have {}/{} elements for {n} vertices",
                    j.len() / 4,
                    w.len() / 4
                ),
            ));
        }
        for v in 0..n {
            for k in 0..4 {
                let (joint, weight) = (j[4 * v + k], w[4 * v + k] as f32);
                if !(weight >= 0.0 && weight.is_finite()) {
                    return Err(c.anim(
                        at,
                        AnimationError::BadWeights {
                            vertex: v,
                            reason: format!("weight {weight}"),
                        },
                    ));
                }
                if weight == 0.0 {
                    continue;
                }
                if joint as usize >= joints {
                    return Err(c.anim(
                        at,
                        AnimationError::JointOutOfRange {
                            vertex: v,
                            joint: joint as u32,
                            joints,
                        },
                    ));
                }
                out[v].push((joint as u16, weight));
            }
        }
    }
    let normalised = normalise_weights(&mut out, at, c)?;
    Ok((out, normalised))
}

/// `JOINTS_n` must be a VEC4 of unsigned bytes or shorts; `WEIGHTS_n` a VEC4 of floats or
/// of normalised unsigned bytes or shorts (glTF 2.0, "Skinned Mesh Attributes").
fn check_skin_types(
    j_acc: &gltf::Accessor<'_>,
    w_acc: &gltf::Accessor<'_>,
    set: u32,
    at: &str,
    c: &Ctx<'_>,
) -> Result<(), LoadError> {
    let type_name = |a: &gltf::Accessor<'_>| {
        format!(
            "{:?} {:?}{}",
            a.dimensions(),
            a.data_type(),
            if a.normalized() { " normalized" } else { "" }
        )
    };
    if !(matches!(j_acc.data_type(), DataType::U8 | DataType::U16)
        && !j_acc.normalized()
        && j_acc.dimensions() == Dimensions::Vec4)
    {
        return Err(c.anim(
            at,
            AnimationError::AttributeType {
                attribute: format!("JOINTS_{set}"),
                allowed: "VEC4 of unsigned byte or unsigned short",
                found: type_name(j_acc),
            },
        ));
    }
    let w_ok = match w_acc.data_type() {
        DataType::F32 => true,
        DataType::U8 | DataType::U16 => w_acc.normalized(),
        _ => false,
    };
    if !(w_ok && w_acc.dimensions() == Dimensions::Vec4) {
        return Err(c.anim(
            at,
            AnimationError::AttributeType {
                attribute: format!("WEIGHTS_{set}"),
                allowed: "VEC4 of float, or normalised unsigned byte or short",
                found: type_name(w_acc),
            },
        ));
    }
    Ok(())
}

/// Scales each vertex's weights to sum to 1; returns how many were off by more than
/// quantisation.
fn normalise_weights(
    out: &mut [Vec<(u16, f32)>],
    at: &str,
    c: &Ctx<'_>,
) -> Result<usize, LoadError> {
    let mut normalised = 0;
    for (v, inf) in out.iter_mut().enumerate() {
        let sum: f64 = inf.iter().map(|&(_, w)| f64::from(w)).sum();
        if !(sum > 0.0) {
            return Err(c.anim(
                at,
                AnimationError::BadWeights {
                    vertex: v,
                    reason: "every weight is zero".into(),
                },
            ));
        }
        // Quantised weights (one unit of a byte is 0.0039) count; float rounding does not.
        if (sum - 1.0).abs() > 2e-3 {
            normalised += 1;
        }
        for (_, w) in inf.iter_mut() {
            *w = (f64::from(*w) / sum) as f32;
        }
    }
    Ok(normalised)
}

/// Every node of the document: name, parent, rest transform; and an order with parents
/// before children.
fn nodes(doc: &gltf::Document, c: &Ctx<'_>) -> Result<(Vec<Node>, Vec<usize>), LoadError> {
    let count = doc.nodes().len();
    let mut nodes: Vec<Node> = Vec::with_capacity(count);
    for n in doc.nodes() {
        let (rest, matrix) = match n.transform() {
            gltf::scene::Transform::Matrix { matrix } => {
                let m = Mat4::from_cols_array_2d(&matrix);
                if !m.is_finite() {
                    return Err(LoadError::NonFinite {
                        file: c.file.to_string(),
                        at: format!("node {}", n.index()),
                        what: "matrix".into(),
                    });
                }
                // A singular matrix (a zero scale hides a node) has no rotation to
                // decompose: it stays exact as `matrix` and animates from identity TRS.
                let (scale, rotation, translation) = m.to_scale_rotation_translation();
                let trs = Trs {
                    translation,
                    rotation,
                    scale,
                };
                let finite = translation.is_finite() && rotation.is_finite() && scale.is_finite();
                (if finite { trs } else { Trs::default() }, Some(m))
            }
            gltf::scene::Transform::Decomposed {
                translation,
                rotation,
                scale,
            } => (
                Trs {
                    translation: Vec3::from(translation),
                    // A zero quaternion (invalid, but harmless before) reads as none.
                    rotation: {
                        let q = Quat::from_array(rotation);
                        if q.length_squared() > 0.0 {
                            q.normalize()
                        } else {
                            Quat::IDENTITY
                        }
                    },
                    scale: Vec3::from(scale),
                },
                None,
            ),
        };
        if !(rest.translation.is_finite() && rest.rotation.is_finite() && rest.scale.is_finite()) {
            return Err(LoadError::NonFinite {
                file: c.file.to_string(),
                at: format!("node {}", n.index()),
                what: "transform".into(),
            });
        }
        nodes.push(Node {
            name: n.name().map(str::to_string),
            parent: None,
            rest,
            matrix,
        });
    }
    let hierarchy = |reason: String| c.anim("nodes", AnimationError::Hierarchy { reason });
    for n in doc.nodes() {
        for ch in n.children() {
            let node = &mut nodes[ch.index()];
            if let Some(p) = node.parent {
                return Err(hierarchy(format!(
                    "node {} is a child of nodes {p} and {}",
                    ch.index(),
                    n.index()
                )));
            }
            node.parent = Some(n.index());
        }
    }
    let mut order = Vec::with_capacity(count);
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); count];
    for (i, n) in nodes.iter().enumerate() {
        if let Some(p) = n.parent {
            children[p].push(i);
        }
    }
    let mut stack: Vec<usize> = (0..count).filter(|&i| nodes[i].parent.is_none()).collect();
    while let Some(i) = stack.pop() {
        order.push(i);
        stack.extend(children[i].iter().rev());
    }
    if order.len() != count {
        return Err(hierarchy("a cycle of nodes".into()));
    }
    Ok((nodes, order))
}

/// The document's skins, with their inverse bind matrices (identity when absent).
fn skins(doc: &gltf::Document, buffers: &[Vec<u8>], c: &Ctx<'_>) -> Result<Vec<Skin>, LoadError> {
    doc.skins()
        .map(|s| {
            let at = format!("skin {}", s.index());
            let joints: Vec<usize> = s.joints().map(|j| j.index()).collect();
            let inverse_bind = match s.inverse_bind_matrices() {
                None => vec![Mat4::IDENTITY; joints.len()],
                Some(acc) => {
                    if acc.dimensions() != Dimensions::Mat4 || acc.data_type() != DataType::F32 {
                        return Err(c.anim(
                            at,
                            AnimationError::AttributeType {
                                attribute: "inverseBindMatrices".into(),
                                allowed: "MAT4 of float",
                                found: format!("{:?} {:?}", acc.dimensions(), acc.data_type()),
                            },
                        ));
                    }
                    let (v, _) = read_accessor(&acc, buffers, c)?;
                    if v.len() != 16 * joints.len() {
                        return Err(c.parse(
                            at,
                            format!(
                                "{} inverse bind matrices for {} joints",
                                v.len() / 16,
                                joints.len()
                            ),
                        ));
                    }
                    if v.iter().any(|x| !x.is_finite()) {
                        return Err(LoadError::NonFinite {
                            file: c.file.to_string(),
                            at,
                            what: "inverse bind matrix".into(),
                        });
                    }
                    v.chunks_exact(16)
                        .map(|m| {
                            let a: [f32; 16] = std::array::from_fn(|k| m[k] as f32);
                            Mat4::from_cols_array(&a)
                        })
                        .collect()
                }
            };
            Ok(Skin {
                name: s.name().map(str::to_string),
                joints,
                inverse_bind,
            })
        })
        .collect()
}

/// The document's animations as clips; every sampler checked ([`Sampler::new`]).
fn clips(doc: &gltf::Document, buffers: &[Vec<u8>], c: &Ctx<'_>) -> Result<Vec<Clip>, LoadError> {
    let mut out = Vec::new();
    for a in doc.animations() {
        let mut channels = Vec::new();
        for ch in a.channels() {
            let at = format!(
                "animation {} channel {} (sampler {})",
                a.index(),
                ch.index(),
                ch.sampler().index()
            );
            let target = ch.target();
            let node = target.node();
            let (property, width) = match target.property() {
                GltfProperty::Translation => (Property::Translation, 3),
                GltfProperty::Rotation => (Property::Rotation, 4),
                GltfProperty::Scale => (Property::Scale, 3),
                GltfProperty::MorphTargetWeights => {
                    let targets = node
                        .mesh()
                        .and_then(|m| m.primitives().map(|p| p.morph_targets().count()).max())
                        .unwrap_or(0);
                    if targets == 0 {
                        return Err(c.anim(
                            at,
                            AnimationError::MorphTarget {
                                target: 0,
                                reason: format!(
                                    "a weights channel targets node {}, which has no morph targets",
                                    node.index()
                                ),
                            },
                        ));
                    }
                    (Property::Weights, targets)
                }
            };
            let s = ch.sampler();
            let interpolation = match s.interpolation() {
                gltf::animation::Interpolation::Step => Interpolation::Step,
                gltf::animation::Interpolation::Linear => Interpolation::Linear,
                gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
            };
            let (times, tdims) = read_accessor(&s.input(), buffers, c)?;
            if tdims != 1 {
                return Err(c.parse(at, "sampler input must be SCALAR"));
            }
            let (values, vdims) = read_accessor(&s.output(), buffers, c)?;
            let expected = if property == Property::Weights {
                1
            } else {
                width
            };
            if vdims != expected {
                return Err(c.anim(
                    at,
                    AnimationError::OutputWidth {
                        target: property.name(),
                        expected,
                        found: vdims,
                    },
                ));
            }
            let sampler = Sampler::new(
                interpolation,
                times.iter().map(|&t| t as f32).collect(),
                values.iter().map(|&v| v as f32).collect(),
                width,
            )
            .map_err(|e| c.anim(at, e))?;
            channels.push(Channel {
                node: node.index(),
                property,
                sampler,
            });
        }
        out.push(Clip::new(a.name().map(str::to_string), channels));
    }
    Ok(out)
}

/// The rig parts of the document; `instances` and `vertices` come from the merge.
pub(super) fn read(
    doc: &gltf::Document,
    buffers: &[Vec<u8>],
    instances: Vec<Instance>,
    vertices: AnimVertices,
    c: &Ctx<'_>,
) -> Result<RigParts, LoadError> {
    let (nodes, order) = nodes(doc, c)?;
    Ok(RigParts {
        nodes,
        order,
        skins: skins(doc, buffers, c)?,
        instances,
        clips: clips(doc, buffers, c)?,
        vertices,
    })
}
