//! Posing on the GPU: a compute pass that applies a rig's morph targets and linear blend
//! skinning and writes the posed positions and normals into the mesh's own vertex buffer,
//! so that every pass bound to that [`GpuMesh`] draws the pose without a copy (glTF 2.0,
//! §3.7.2.2 Morph Targets, §3.7.3 Skins).
//!
//! It speaks the pass contract ([`crate::pass`]) with `record` in place of `draw`:
//!
//! ```ignore
//! let posing = PosingPass::new(device);
//! let mut object = posing.create_object(device, &gpu_mesh, &rig, Some(&vertex_to_output))?;
//! // per frame
//! let prepared = posing.prepare(queue, &mut object, &PoseInput { frame, pose: &pose })?;
//! posing.record(&mut encoder, &object, &prepared)?; // before the passes that draw it
//! ```
//!
//! The CPU reference is [`npr_geometry::animation::Rig::pose_mesh`]; the WGSL is
//! `shaders/posing.wgsl` (`cs_pose`, `cs_normals`), whose functions name their Rust twins.

use crate::compute::{
    check_bindings, dispatch_size, group_entry as entry, pipeline,
    storage_layout_entry as compute_entry,
};
use crate::pass::{FrameId, PassId, Prepared, Slots};
use crate::{GpuError, GpuMesh};
use glam::Mat4;
use npr_geometry::animation::{Pose, Rig};

/// The compute pipelines of posing: one per device, shared by every posed object.
#[derive(Debug)]
pub struct PosingPass {
    id: PassId,
    device: wgpu::Device,
    pose_layout: wgpu::BindGroupLayout,
    normals_layout: wgpu::BindGroupLayout,
    pose_pipeline: wgpu::ComputePipeline,
    normals_pipeline: wgpu::ComputePipeline,
}

/// What one pose needs: the frame it is for and the rig's pose.
#[derive(Clone, Copy, Debug)]
pub struct PoseInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The pose, sampled from the rig the object was created with.
    pub pose: &'a Pose,
}

/// One rigged mesh on the GPU: its rig's constant data (bind positions and normals,
/// influences, morph deltas, the faces around each welded vertex) and the caller's
/// vertex buffer it writes.
#[derive(Debug)]
pub struct PosedObject {
    vertices: usize,
    palette_len: usize,
    /// Per skin, its first palette matrix and its joint count; then per instance, its
    /// node's palette matrix, its node and its first morph weight and weight count.
    skins: Vec<(usize, usize)>,
    instances: Vec<InstanceSlot>,
    weights_len: usize,
    base: wgpu::Buffer,
    info: wgpu::Buffer,
    influences: wgpu::Buffer,
    morphs: wgpu::Buffer,
    target: wgpu::Buffer,
    normals: Option<wgpu::BindGroup>,
    slots: Slots<PoseSlot>,
}

#[derive(Clone, Copy, Debug)]
struct InstanceSlot {
    palette: usize,
    node: usize,
    first_weight: usize,
    weights: usize,
}

#[derive(Debug)]
struct PoseSlot {
    palette: wgpu::Buffer,
    weights: wgpu::Buffer,
    group: wgpu::BindGroup,
}

/// The rig's constant data as the shader reads it (see `posing.wgsl`).
struct RigData {
    base: Vec<[f32; 4]>,
    info: Vec<[u32; 4]>,
    influences: Vec<[u32; 2]>,
    morphs: Vec<[f32; 4]>,
    skins: Vec<(usize, usize)>,
    instances: Vec<InstanceSlot>,
    palette_len: usize,
    weights_len: usize,
    /// Per rig vertex (only representatives have faces) into `faces`, and the faces'
    /// output vertices, one entry per corner in the welded vertex.
    offsets: Vec<u32>,
    faces: Vec<[u32; 4]>,
}

/// A storage buffer of `data` (at least one element).
fn storage<T: bytemuck::Pod + Default>(
    device: &wgpu::Device,
    label: &str,
    data: &[T],
) -> wgpu::Buffer {
    crate::compute::buffer_init(
        device,
        label,
        data,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    )
}

fn rig_data(rig: &Rig, order: &[u32]) -> RigData {
    let mut palette_len = 0;
    let skins: Vec<(usize, usize)> = rig
        .skins()
        .iter()
        .map(|s| {
            let first = palette_len;
            palette_len += s.joints.len();
            (first, s.joints.len())
        })
        .collect();
    let mut weights_len = 0;
    let mut instance_weights = vec![0usize; rig.instances().len()];
    for v in 0..rig.vertex_count() {
        if let Some(i) = rig.vertex_instance(v) {
            if let Some(w) = instance_weights.get_mut(i) {
                *w = (*w).max(rig.morph_deltas(v).0.len());
            }
        }
    }
    let instances: Vec<InstanceSlot> = rig
        .instances()
        .iter()
        .zip(&instance_weights)
        .map(|(inst, &weights)| {
            let slot = InstanceSlot {
                palette: palette_len,
                node: inst.node,
                first_weight: weights_len,
                weights,
            };
            palette_len += 1;
            weights_len += weights;
            slot
        })
        .collect();
    let identity = palette_len;
    palette_len += 1;
    let base_mesh = rig.base_mesh();
    let n = rig.vertex_count();
    let mut data = RigData {
        base: Vec::with_capacity(2 * n),
        info: Vec::with_capacity(2 * n),
        influences: Vec::new(),
        morphs: Vec::new(),
        skins,
        instances,
        palette_len,
        weights_len,
        offsets: Vec::new(),
        faces: Vec::new(),
    };
    for (v, &out) in order.iter().enumerate() {
        let p = base_mesh.positions.get(v).copied().unwrap_or_default();
        let nrm = base_mesh.normals.get(v).copied().unwrap_or(glam::Vec3::Z);
        data.base.push([p.x, p.y, p.z, 1.0]);
        data.base.push([nrm.x, nrm.y, nrm.z, 0.0]);
        let inst = rig
            .vertex_instance(v)
            .and_then(|i| data.instances.get(i).map(|s| (i, *s)));
        let first_influence = data.influences.len() as u32;
        match inst {
            Some((i, _)) if !rig.influences(v).is_empty() => {
                let skin = rig.instances()[i]
                    .skin
                    .and_then(|s| data.skins.get(s).copied());
                for &(j, w) in rig.influences(v) {
                    let m = match skin {
                        Some((first, count)) if usize::from(j) < count => first + usize::from(j),
                        _ => identity,
                    };
                    data.influences.push([m as u32, w.to_bits()]);
                }
            }
            Some((_, slot)) => data
                .influences
                .push([slot.palette as u32, 1.0f32.to_bits()]),
            None => data.influences.push([identity as u32, 1.0f32.to_bits()]),
        }
        let influence_count = data.influences.len() as u32 - first_influence;
        let (dp, dn) = rig.morph_deltas(v);
        let first_morph = (data.morphs.len() / 2) as u32;
        for (k, d) in dp.iter().enumerate() {
            let e = dn.get(k).copied().unwrap_or_default();
            data.morphs.push([d.x, d.y, d.z, 0.0]);
            data.morphs.push([e.x, e.y, e.z, 0.0]);
        }
        let (first_weight, weights) = inst.map_or((0, 0), |(_, s)| (s.first_weight, s.weights));
        let morph_count = dp.len().min(weights) as u32;
        data.info
            .push([first_influence, influence_count, first_morph, morph_count]);
        let rep = rig.weld_representative(v).min(n - 1) as u32;
        data.info.push([first_weight as u32, rep, out, 0]);
    }
    if rig.recomputes_normals() {
        let mut per_rep: Vec<Vec<[u32; 4]>> = vec![Vec::new(); n];
        for t in base_mesh.triangles() {
            if t.iter().any(|&i| i as usize >= n) {
                continue;
            }
            let face = [
                order[t[0] as usize],
                order[t[1] as usize],
                order[t[2] as usize],
                0,
            ];
            for &c in &t {
                per_rep[rig.weld_representative(c as usize).min(n - 1)].push(face);
            }
        }
        data.offsets.reserve(n + 1);
        for faces in per_rep {
            data.offsets.push(data.faces.len() as u32);
            data.faces.extend(faces);
        }
        data.offsets.push(data.faces.len() as u32);
    }
    data
}

impl PosingPass {
    /// The two compute pipelines (posing, and posed normals for rigs whose file had none).
    /// A compute pass draws into no target, so it takes no [`crate::TargetFormats`].
    pub fn new(device: &wgpu::Device) -> Self {
        let module = crate::shaders::POSING_FILE.module(device);
        let pose_entries: Vec<_> = (0..7).map(|b| compute_entry(b, b != 6)).collect();
        let pose_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr posing"),
            entries: &pose_entries,
        });
        let normals_entries: Vec<_> = (8..12).map(|b| compute_entry(b, b != 11)).collect();
        let normals_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr posed normals"),
            entries: &normals_entries,
        });
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            pose_pipeline: pipeline(device, &module, &pose_layout, "cs_pose"),
            normals_pipeline: pipeline(device, &module, &normals_layout, "cs_normals"),
            pose_layout,
            normals_layout,
        }
    }

    /// Uploads `rig`'s constant data for `mesh`, the rig's mesh as uploaded: `order[v]`
    /// is where the rig's vertex `v` sits in `mesh` (`None`: the same order). The object
    /// keeps `mesh`'s vertex buffer and writes it in [`PosingPass::record`]; uvs and
    /// triangles stay as uploaded.
    ///
    /// # Errors
    /// [`GpuError::InvalidMesh`] when the vertex counts differ or `order` is not a
    /// permutation of the mesh's vertices; [`GpuError::MeshTooLarge`] when a buffer
    /// would exceed the device's storage binding limit.
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        mesh: &GpuMesh,
        rig: &Rig,
        order: Option<&[u32]>,
    ) -> Result<PosedObject, GpuError> {
        let n = rig.vertex_count();
        let mesh_vertices = mesh.vertex_count as usize;
        if n == 0 || n != mesh_vertices {
            return Err(GpuError::InvalidMesh(format!(
                "a rig of {n} vertices cannot pose a mesh of {mesh_vertices}"
            )));
        }
        let identity: Vec<u32>;
        let order = match order {
            Some(o) => {
                check_permutation(o, n)?;
                o
            }
            None => {
                identity = (0..n as u32).collect();
                &identity
            }
        };
        let data = rig_data(rig, order);
        check_bindings(
            &[
                ("posing morph", data.morphs.len() as u64 * 16),
                ("posing influence", data.influences.len() as u64 * 8),
                ("posing normal face", data.faces.len() as u64 * 16),
                ("posing bind vertex", data.base.len() as u64 * 16),
                ("posing palette", data.palette_len as u64 * 64),
            ],
            device.limits().max_storage_buffer_binding_size,
        )?;
        let info = storage(device, "npr posing info", &data.info);
        let normals = rig.recomputes_normals().then(|| {
            let offsets = storage(device, "npr posing face offsets", &data.offsets);
            let faces = storage(device, "npr posing faces", &data.faces);
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("npr posed normals"),
                layout: &self.normals_layout,
                entries: &[
                    entry(8, &info),
                    entry(9, &offsets),
                    entry(10, &faces),
                    entry(11, &mesh.vertex_buffer),
                ],
            })
        });
        Ok(PosedObject {
            vertices: n,
            palette_len: data.palette_len,
            skins: data.skins,
            instances: data.instances,
            weights_len: data.weights_len,
            base: storage(device, "npr posing bind vertices", &data.base),
            influences: storage(device, "npr posing influences", &data.influences),
            morphs: storage(device, "npr posing morphs", &data.morphs),
            info,
            target: mesh.vertex_buffer.clone(),
            normals,
            slots: Slots::new(self.id),
        })
    }

    /// Writes `input.pose`'s joint matrices, node matrices and morph weights into a fresh
    /// slot of `object` (the only queue writes of posing).
    ///
    /// # Errors
    /// [`GpuError::Pass`] for a foreign object or too many prepares in one frame.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut PosedObject,
        input: &PoseInput<'_>,
    ) -> Result<Prepared, GpuError> {
        let mut palette = vec![Mat4::IDENTITY; object.palette_len];
        for (s, &(first, count)) in object.skins.iter().enumerate() {
            for (j, m) in input.pose.joint_matrices(s).iter().take(count).enumerate() {
                palette[first + j] = *m;
            }
        }
        let mut weights = vec![0.0f32; object.weights_len.max(1)];
        for (i, inst) in object.instances.iter().enumerate() {
            palette[inst.palette] = input.pose.node_global(inst.node).unwrap_or(Mat4::IDENTITY);
            for (k, &w) in input
                .pose
                .morph_weights(i)
                .iter()
                .take(inst.weights)
                .enumerate()
            {
                weights[inst.first_weight + k] = w;
            }
        }
        let device = &self.device;
        let (pose_layout, base, info, influences, morphs, target) = (
            &self.pose_layout,
            &object.base,
            &object.info,
            &object.influences,
            &object.morphs,
            &object.target,
        );
        let (prepared, slot) = object.slots.next(self.id, input.frame, || {
            let palette_buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("npr posing palette"),
                size: (palette.len() * 64) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let weights_buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("npr posing weights"),
                size: (weights.len() * 4) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("npr posing"),
                layout: pose_layout,
                entries: &[
                    entry(0, base),
                    entry(1, info),
                    entry(2, influences),
                    entry(3, morphs),
                    entry(4, &palette_buffer),
                    entry(5, &weights_buffer),
                    entry(6, target),
                ],
            });
            PoseSlot {
                palette: palette_buffer,
                weights: weights_buffer,
                group,
            }
        })?;
        queue.write_buffer(&slot.palette, 0, bytemuck::cast_slice(&palette));
        queue.write_buffer(&slot.weights, 0, bytemuck::cast_slice(&weights));
        Ok(prepared)
    }

    /// Records the pose `prepared` names into `encoder`: the posed positions and normals
    /// into the mesh's vertex buffer, then, for a rig whose file had no normals, the posed
    /// area-weighted normals. Passes recorded after it in the same encoder draw the pose;
    /// a second pose recorded later in the encoder replaces it for the passes after that.
    ///
    /// # Errors
    /// [`GpuError::Pass`] for a `prepared` of another pass, object or frame; nothing is
    /// recorded then.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: &PosedObject,
        prepared: &Prepared,
    ) -> Result<(), GpuError> {
        let slot = object.slots.get(self.id, prepared)?;
        let (x, y) = dispatch_size(
            object.vertices,
            self.device.limits().max_compute_workgroups_per_dimension,
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("npr posing"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pose_pipeline);
        pass.set_bind_group(0, &slot.group, &[]);
        pass.dispatch_workgroups(x, y, 1);
        if let Some(normals) = &object.normals {
            pass.set_pipeline(&self.normals_pipeline);
            pass.set_bind_group(0, normals, &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
        Ok(())
    }
}

impl PosedObject {
    /// The rig's vertex count (that of the mesh it poses).
    pub fn vertex_count(&self) -> usize {
        self.vertices
    }

    /// Whether [`PosingPass::record`] also recomputes the normals from the posed
    /// triangles (the file had none).
    pub fn recomputes_normals(&self) -> bool {
        self.normals.is_some()
    }
}

fn check_permutation(order: &[u32], n: usize) -> Result<(), GpuError> {
    if order.len() != n {
        return Err(GpuError::InvalidMesh(format!(
            "a vertex order of {} entries for {n} vertices",
            order.len()
        )));
    }
    let mut seen = vec![false; n];
    for &o in order {
        match seen.get_mut(o as usize) {
            Some(s) if !*s => *s = true,
            _ => {
                return Err(GpuError::InvalidMesh(format!(
                    "the vertex order maps two vertices to {o}, or past the mesh's {n}"
                )));
            }
        }
    }
    Ok(())
}
