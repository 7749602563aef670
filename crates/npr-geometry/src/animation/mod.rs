//! Skeletal and morph-target animation read from glTF 2.0: the node tree, skins, morph
//! targets and clips of a file ([`Rig`]), the animation sampler ([`Sampler`]), poses
//! ([`Pose`]) and a CPU reference of posing ([`Rig::pose_mesh`]: morph targets first,
//! then linear blend skinning).
//!
//! [`crate::io::load`] fills [`crate::io::Loaded::rig`] when a glTF file has a skin, a
//! morph target or an animation. The rig keeps the render-vertex layout of the loaded
//! mesh: [`Rig::pose_mesh`] returns a mesh with the same vertices, in the same order,
//! and the same triangles, so a [`crate::Topology`] built once from the loaded mesh stays
//! valid for every pose ([`crate::weld()`] of a posed mesh gives the same map as of the
//! loaded one: render vertices that shared a position at load share it in every pose).
//! [`Rig::file_vertex`] maps each render vertex back to the file.
//!
//! ```no_run
//! let loaded = npr_geometry::io::load("fixtures/meshes/Fox.glb").unwrap();
//! let rig = loaded.rig.as_ref().unwrap();
//! let walk = rig.clip_named("Walk").unwrap();
//! let pose = rig.sample(walk, 0.25 * walk.duration());
//! let posed = rig.pose_mesh(&pose);
//! assert_eq!(posed.indices, loaded.mesh.indices);
//! ```

mod error;
mod pose;
mod sampler;
mod skin;
#[cfg(test)]
mod tests;

use glam::{Mat4, Quat, Vec3};

pub use error::AnimationError;
pub use pose::Pose;
pub(crate) use pose::morph;
pub use sampler::{Interpolation, Sampler};
pub use skin::Skin;

use crate::Mesh;

/// A local transform as translation, rotation and scale; its matrix is `T · R · S`
/// (glTF 2.0, §3.5.3 Transformations).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trs {
    /// Translation.
    pub translation: Vec3,
    /// Rotation, a unit quaternion.
    pub rotation: Quat,
    /// Scale per axis.
    pub scale: Vec3,
}

impl Default for Trs {
    fn default() -> Self {
        Self {
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
        }
    }
}

impl Trs {
    /// `T · R · S`.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// A node of the file's hierarchy.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Node {
    /// The node's name in the file, if any.
    pub name: Option<String>,
    /// The parent node, `None` for a root.
    pub parent: Option<usize>,
    /// The rest transform as TRS (decomposed from `matrix` when the file gives one);
    /// animation channels replace its parts.
    pub rest: Trs,
    /// The file's `matrix`, when it gives one: used as it is while no channel targets
    /// the node (glTF 2.0, §3.5.3: an animated node must use TRS).
    pub matrix: Option<Mat4>,
}

impl Node {
    /// The local matrix at rest.
    pub fn rest_matrix(&self) -> Mat4 {
        self.matrix.unwrap_or_else(|| self.rest.matrix())
    }
}

/// What an animation channel drives (glTF 2.0, §3.11, `animation.channel.target.path`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Property {
    /// The node's translation (3 components).
    Translation,
    /// The node's rotation (4 components, `x, y, z, w`).
    Rotation,
    /// The node's scale (3 components).
    Scale,
    /// The morph target weights of the node's mesh (one component per target).
    Weights,
}

impl Property {
    /// The glTF path name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Translation => "translation",
            Self::Rotation => "rotation",
            Self::Scale => "scale",
            Self::Weights => "weights",
        }
    }
}

/// One animation channel: a sampler driving one property of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The target node (an index into [`Rig::nodes`]).
    pub node: usize,
    /// The property.
    pub property: Property,
    /// The keys.
    pub sampler: Sampler,
}

/// An animation clip: channels played together.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Clip {
    name: Option<String>,
    channels: Vec<Channel>,
}

impl Clip {
    /// A clip of `channels`.
    pub fn new(name: Option<String>, channels: Vec<Channel>) -> Self {
        Self { name, channels }
    }

    /// The clip's name in the file, if any.
    pub fn name(&self) -> Option<&str> {
        self.name.as_deref()
    }

    /// The channels.
    pub fn channels(&self) -> &[Channel] {
        &self.channels
    }

    /// The earliest key time of any channel (0 for a clip without channels).
    pub fn start(&self) -> f32 {
        self.channels
            .iter()
            .map(|c| c.sampler.start())
            .reduce(f32::min)
            .unwrap_or(0.0)
    }

    /// The clip's length in seconds: its last key time (glTF clips start at time 0;
    /// sampling before [`Clip::start`] holds the first keys).
    pub fn duration(&self) -> f32 {
        self.channels
            .iter()
            .map(|c| c.sampler.end())
            .reduce(f32::max)
            .unwrap_or(0.0)
    }
}

/// Where a render vertex of the loaded mesh comes from in the file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct FileVertex {
    /// The node that instances the mesh.
    pub node: u32,
    /// The glTF mesh.
    pub mesh: u32,
    /// The primitive within the mesh.
    pub primitive: u32,
    /// The vertex within the primitive (an index into its attribute accessors).
    pub vertex: u32,
}

/// A mesh instance: a node with a mesh, skinned or placed by the node.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Instance {
    /// The node (an index into [`Rig::nodes`]).
    pub node: usize,
    /// The skin (an index into [`Rig::skins`]); a skinned instance ignores its node's
    /// transform (glTF 2.0, §3.7.3: only the joints place its vertices).
    pub skin: Option<usize>,
    /// The default morph target weights: the node's `weights`, else the mesh's, else
    /// zeros (glTF 2.0, §3.7.2.2 Morph Targets).
    pub weights: Vec<f32>,
}

/// The animation data of a loaded file, tied to the render vertices of its mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rig {
    pub(crate) nodes: Vec<Node>,
    /// Nodes, parents before children.
    pub(crate) order: Vec<usize>,
    pub(crate) skins: Vec<Skin>,
    pub(crate) instances: Vec<Instance>,
    pub(crate) clips: Vec<Clip>,
    /// Unmorphed, unposed positions and normals (bind space for skinned vertices, the
    /// node's local space for the others), with the loaded mesh's uvs and triangles.
    pub(crate) base: Mesh,
    /// Per render vertex.
    pub(crate) source: Vec<FileVertex>,
    pub(crate) vertex_instance: Vec<u32>,
    /// `influences[influence_offsets[v]..influence_offsets[v + 1]]`: (joint, weight),
    /// weights summing to 1; empty for a vertex placed by its node.
    pub(crate) influence_offsets: Vec<u32>,
    pub(crate) influences: Vec<(u16, f32)>,
    /// `morph_*[morph_offsets[v]..morph_offsets[v + 1]]`: one delta per target.
    pub(crate) morph_offsets: Vec<u32>,
    pub(crate) morph_positions: Vec<Vec3>,
    pub(crate) morph_normals: Vec<Vec3>,
    /// Whether posed normals are recomputed from the triangles (the file had none).
    pub(crate) recompute_normals: bool,
    /// For each render vertex, the first render vertex at the same loaded position.
    pub(crate) weld_rep: Vec<u32>,
}

impl Rig {
    /// The node tree.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The skins.
    pub fn skins(&self) -> &[Skin] {
        &self.skins
    }

    /// The mesh instances.
    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// The clips, in file order.
    pub fn clips(&self) -> &[Clip] {
        &self.clips
    }

    /// The first clip named `name`.
    pub fn clip_named(&self, name: &str) -> Option<&Clip> {
        self.clips.iter().find(|c| c.name() == Some(name))
    }

    /// The render vertex count (that of the loaded mesh).
    pub fn vertex_count(&self) -> usize {
        self.source.len()
    }

    /// Where render vertex `v` comes from in the file.
    pub fn file_vertex(&self, v: usize) -> Option<FileVertex> {
        self.source.get(v).copied()
    }

    /// The file vertex of every render vertex.
    pub fn file_vertices(&self) -> &[FileVertex] {
        &self.source
    }

    /// The instance render vertex `v` belongs to (an index into [`Rig::instances`]).
    pub fn vertex_instance(&self, v: usize) -> Option<usize> {
        self.vertex_instance.get(v).map(|&i| i as usize)
    }

    /// Render vertex `v`'s joints (indices into its instance's skin's joints) and
    /// weights, normalised to sum to 1; empty for a vertex its node places.
    pub fn influences(&self, v: usize) -> &[(u16, f32)] {
        range(&self.influence_offsets, v)
            .and_then(|r| self.influences.get(r))
            .unwrap_or(&[])
    }

    /// Render vertex `v`'s morph deltas, one per target: (position, normal).
    pub fn morph_deltas(&self, v: usize) -> (&[Vec3], &[Vec3]) {
        let r = range(&self.morph_offsets, v);
        (
            r.clone()
                .and_then(|r| self.morph_positions.get(r))
                .unwrap_or(&[]),
            r.and_then(|r| self.morph_normals.get(r)).unwrap_or(&[]),
        )
    }

    /// The first render vertex at render vertex `v`'s loaded position (`v` itself for
    /// the first): [`Rig::pose_mesh`] gives every render vertex its representative's
    /// posed position, so seam duplicates stay welded in every pose.
    pub fn weld_representative(&self, v: usize) -> usize {
        self.weld_rep.get(v).map_or(v, |&r| r as usize)
    }

    /// The unposed, unmorphed mesh: bind-space positions of skinned vertices,
    /// node-local positions of the others; the loaded mesh's uvs and triangles.
    pub fn base_mesh(&self) -> &Mesh {
        &self.base
    }

    /// Whether [`Rig::pose_mesh`] recomputes normals from the posed triangles (the file
    /// had none, or not for every primitive).
    pub fn recomputes_normals(&self) -> bool {
        self.recompute_normals
    }
}

impl Rig {
    /// The rig of one mesh skinned by one skin (the procedural models of
    /// [`crate::generate`]): `nodes[0]` holds the mesh, `influences` has one list of
    /// (joint, weight) per vertex of `mesh`, weights summing to 1.
    pub(crate) fn skinned(
        mesh: &Mesh,
        nodes: Vec<Node>,
        skin: Skin,
        influences: &[Vec<(u16, f32)>],
        clips: Vec<Clip>,
    ) -> Self {
        let n = mesh.vertex_count();
        let mut influence_offsets = vec![0u32];
        let mut flat = Vec::new();
        for v in 0..n {
            flat.extend_from_slice(influences.get(v).map_or(&[][..], Vec::as_slice));
            influence_offsets.push(flat.len() as u32);
        }
        Self {
            order: node_order(&nodes),
            nodes,
            skins: vec![skin],
            instances: vec![Instance {
                node: 0,
                skin: Some(0),
                weights: Vec::new(),
            }],
            clips,
            base: mesh.clone(),
            source: (0..n as u32)
                .map(|v| FileVertex {
                    vertex: v,
                    ..FileVertex::default()
                })
                .collect(),
            vertex_instance: vec![0; n],
            influence_offsets,
            influences: flat,
            morph_offsets: vec![0; n + 1],
            morph_positions: Vec::new(),
            morph_normals: Vec::new(),
            recompute_normals: false,
            weld_rep: weld_representatives(mesh),
        }
    }
}

/// Nodes with parents before children (depth first from the roots); nodes on a cycle
/// are left out.
pub(crate) fn node_order(nodes: &[Node]) -> Vec<usize> {
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
    for (i, n) in nodes.iter().enumerate() {
        if let Some(c) = n.parent.and_then(|p| children.get_mut(p)) {
            c.push(i);
        }
    }
    let mut order = Vec::with_capacity(nodes.len());
    let mut stack: Vec<usize> = (0..nodes.len())
        .filter(|&i| nodes[i].parent.is_none_or(|p| p >= nodes.len()))
        .rev()
        .collect();
    while let Some(i) = stack.pop() {
        order.push(i);
        stack.extend(children[i].iter().rev());
    }
    order
}

/// For each render vertex of `mesh`, the first render vertex with the same position
/// (the representative of its welded vertex).
pub(crate) fn weld_representatives(mesh: &Mesh) -> Vec<u32> {
    let welded = crate::weld(mesh);
    let mut first = vec![u32::MAX; welded.positions.len()];
    welded
        .render_to_welded
        .iter()
        .enumerate()
        .map(|(v, &w)| match first.get_mut(w as usize) {
            Some(f) => {
                if *f == u32::MAX {
                    *f = v as u32;
                }
                *f
            }
            None => v as u32,
        })
        .collect()
}

fn range(offsets: &[u32], v: usize) -> Option<std::ops::Range<usize>> {
    let a = *offsets.get(v)? as usize;
    let b = *offsets.get(v + 1)? as usize;
    (a <= b).then_some(a..b)
}
