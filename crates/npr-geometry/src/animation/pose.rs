//! Poses: node transforms, joint matrices and morph weights at one time of a clip, and
//! the CPU reference of posing a mesh (morph targets, then linear blend skinning).

use glam::{Mat4, Vec3};

use super::skin::{blend, transform_normal};
use super::{Clip, Property, Rig, Trs};
use crate::Mesh;

/// The state of a rig at one instant.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pose {
    /// Per node, its global (world) matrix.
    pub(crate) globals: Vec<Mat4>,
    /// Per skin, per joint: global joint matrix × inverse bind matrix.
    pub(crate) joints: Vec<Vec<Mat4>>,
    /// Per mesh instance, its morph target weights.
    pub(crate) weights: Vec<Vec<f32>>,
}

impl Pose {
    /// The bind pose of `rig`: every joint matrix the identity (skinned vertices stay
    /// where the file puts them), every node at its rest transform, the default morph
    /// weights. Posing it gives the loaded mesh.
    pub fn bind(rig: &Rig) -> Self {
        let mut pose = rig.rest_pose();
        for (j, skin) in pose.joints.iter_mut().zip(&rig.skins) {
            *j = vec![Mat4::IDENTITY; skin.joints.len()];
        }
        pose
    }

    /// Node `node`'s global matrix.
    pub fn node_global(&self, node: usize) -> Option<Mat4> {
        self.globals.get(node).copied()
    }

    /// Skin `skin`'s joint matrices (global joint transform × inverse bind matrix), one
    /// per joint; empty for a skin the rig does not have.
    pub fn joint_matrices(&self, skin: usize) -> &[Mat4] {
        self.joints.get(skin).map_or(&[], Vec::as_slice)
    }

    /// Instance `instance`'s morph weights; empty for an instance the rig does not have.
    pub fn morph_weights(&self, instance: usize) -> &[f32] {
        self.weights.get(instance).map_or(&[], Vec::as_slice)
    }

    /// Sets instance `instance`'s morph weights (as many as it has targets; extra
    /// values are ignored, missing ones keep their value). Returns whether the instance
    /// exists.
    pub fn set_morph_weights(&mut self, instance: usize, weights: &[f32]) -> bool {
        match self.weights.get_mut(instance) {
            Some(w) => {
                for (a, b) in w.iter_mut().zip(weights) {
                    *a = *b;
                }
                true
            }
            None => false,
        }
    }
}

/// `p + Σ wₖ dₖ` (glTF 2.0, §3.7.2.2 Morph Targets), weights past `w` read as zero.
pub(crate) fn morph(p: Vec3, w: &[f32], deltas: &[Vec3]) -> Vec3 {
    deltas
        .iter()
        .zip(w.iter().chain(std::iter::repeat(&0.0)))
        .fold(p, |acc, (d, &wk)| acc + wk * *d)
}

impl Rig {
    /// The bind pose ([`Pose::bind`]).
    pub fn bind_pose(&self) -> Pose {
        Pose::bind(self)
    }

    /// The rest pose: every node at the transform the file gives it, no animation, the
    /// default morph weights. For most files this is the bind pose too.
    pub fn rest_pose(&self) -> Pose {
        let locals: Vec<Mat4> = self.nodes.iter().map(|n| n.rest_matrix()).collect();
        let weights = self.instances.iter().map(|i| i.weights.clone()).collect();
        self.pose_from(&locals, weights)
    }

    /// The pose of `clip` at time `t` seconds (glTF 2.0, §3.11 Animations): each channel's
    /// sampler replaces its node's translation, rotation or scale, or its mesh's morph
    /// weights; untargeted properties keep their rest values. `t` outside the keys holds
    /// the end values (wrap `t` by [`Clip::duration`] to loop). A channel naming a node
    /// this rig lacks is ignored.
    pub fn sample(&self, clip: &Clip, t: f32) -> Pose {
        let mut trs: Vec<Trs> = self.nodes.iter().map(|n| n.rest).collect();
        let mut animated = vec![false; self.nodes.len()];
        let mut weights: Vec<Vec<f32>> = self.instances.iter().map(|i| i.weights.clone()).collect();
        for ch in clip.channels() {
            let Some(node) = trs.get_mut(ch.node) else {
                continue;
            };
            let s = &ch.sampler;
            let v3 = |v: Vec<f32>| Vec3::new(v[0], v[1], v[2]);
            match ch.property {
                Property::Translation if s.width() == 3 => node.translation = v3(s.sample(t)),
                Property::Scale if s.width() == 3 => node.scale = v3(s.sample(t)),
                Property::Rotation if s.width() == 4 => node.rotation = s.sample_rotation(t),
                Property::Weights => {
                    let w = s.sample(t);
                    for (inst, iw) in self.instances.iter().zip(&mut weights) {
                        if inst.node == ch.node {
                            for (a, b) in iw.iter_mut().zip(&w) {
                                *a = *b;
                            }
                        }
                    }
                    continue;
                }
                _ => continue,
            }
            animated[ch.node] = true;
        }
        let locals: Vec<Mat4> = self
            .nodes
            .iter()
            .zip(&trs)
            .zip(&animated)
            .map(|((n, t), &a)| if a { t.matrix() } else { n.rest_matrix() })
            .collect();
        self.pose_from(&locals, weights)
    }

    /// Globals from local matrices (parents first), then the joint matrices.
    fn pose_from(&self, locals: &[Mat4], weights: Vec<Vec<f32>>) -> Pose {
        let mut globals = vec![Mat4::IDENTITY; self.nodes.len()];
        for &n in &self.order {
            let local = locals.get(n).copied().unwrap_or(Mat4::IDENTITY);
            let parent = self.nodes[n]
                .parent
                .and_then(|p| globals.get(p).copied())
                .unwrap_or(Mat4::IDENTITY);
            globals[n] = parent * local;
        }
        let joints = self
            .skins
            .iter()
            .map(|s| {
                s.joints
                    .iter()
                    .zip(&s.inverse_bind)
                    .map(|(&j, ibm)| globals.get(j).copied().unwrap_or(Mat4::IDENTITY) * *ibm)
                    .collect()
            })
            .collect();
        Pose {
            globals,
            joints,
            weights,
        }
    }

    /// The mesh in `pose`: per render vertex, morph targets first (position and normal
    /// deltas by the pose's weights), then linear blend skinning `Σ wᵢ Jᵢ` for a skinned
    /// vertex, or its node's global matrix for the others; normals by the
    /// inverse-transpose. Normals are recomputed from the triangles when the file had
    /// none ([`Rig::recomputes_normals`]). Same vertices, order, uvs and triangles as
    /// the loaded mesh; render vertices that shared a position when loaded share it here.
    pub fn pose_mesh(&self, pose: &Pose) -> Mesh {
        let mut mesh = self.base.clone();
        let transforms = self.vertex_transforms(pose);
        for (v, &m) in transforms.iter().enumerate() {
            let inst = self.vertex_instance.get(v).map_or(0, |&i| i as usize);
            let w = pose.morph_weights(inst);
            let (dp, dn) = self.morph_deltas(v);
            let p = morph(mesh.positions[v], w, dp);
            let n = morph(mesh.normals[v], w, dn);
            mesh.positions[v] = m.transform_point3(p);
            mesh.normals[v] = transform_normal(m, n);
        }
        for v in 0..mesh.positions.len() {
            let r = self.weld_rep.get(v).map_or(v, |&r| r as usize);
            if r < v {
                mesh.positions[v] = mesh.positions[r];
            }
        }
        if self.recompute_normals {
            mesh.recompute_normals();
        }
        mesh
    }

    /// Per render vertex, the matrix that places it in `pose` after its morphs: linear
    /// blend skinning `Σ wᵢ Jᵢ` for a skinned vertex, its node's global matrix for the
    /// others ([`Rig::pose_mesh`]). A tangent direction of the unposed surface carried by
    /// it follows the surface where the vertex moves rigidly.
    pub fn vertex_transforms(&self, pose: &Pose) -> Vec<Mat4> {
        (0..self.base.positions.len())
            .map(|v| {
                let inst = self.vertex_instance.get(v).map_or(0, |&i| i as usize);
                let inf = self.influences(v);
                match self.instances.get(inst) {
                    Some(i) if !inf.is_empty() => {
                        blend(inf, pose.joint_matrices(i.skin.unwrap_or(usize::MAX)))
                    }
                    Some(i) => pose.node_global(i.node).unwrap_or(Mat4::IDENTITY),
                    None => Mat4::IDENTITY,
                }
            })
            .collect()
    }

    /// The axis-aligned bounds `(min, max)` of the posed mesh over `clip`, sampled at
    /// `samples` evenly spaced times from 0 to [`Clip::duration`] (at least 2), so a
    /// camera framing the whole clip can hold still.
    pub fn clip_bounds(&self, clip: &Clip, samples: usize) -> (Vec3, Vec3) {
        let n = samples.max(2);
        let d = clip.duration();
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for k in 0..n {
            let t = d * k as f32 / (n - 1) as f32;
            let m = self.pose_mesh(&self.sample(clip, t));
            for p in &m.positions {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
        }
        (lo, hi)
    }
}
