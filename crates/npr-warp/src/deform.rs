//! Warping a deforming model (ours; the paper's §3.3.1 proxy is rigid): the proxy is
//! posed with the full mesh ([`Proxy::posed`]), re-binned by its posed normals
//! ([`WarpObject::repose`], §3.3.2), and each reference keeps a snapshot of the proxy's
//! vertices as they stood when it was rendered ([`ReferenceFrame::keep_proxy_pose`]).
//! `vs_warp` projects a reference onto the snapshot's vertex and draws the current one,
//! so the texels a reference shows stay on the surface point they show as the body moves,
//! as a surface's stroke anchors do in npr-hatching.

use crate::bins::NormalBins;
use crate::pass::WarpObject;
use crate::reference::ReferenceFrame;
use crate::{Proxy, WarpError};

/// A reference's copy of one object's proxy vertices ([`ReferenceFrame::keep_proxy_pose`]).
#[derive(Clone, Debug)]
pub(crate) struct Snapshot {
    buffer: wgpu::Buffer,
    /// The [`WarpObject`] it is of (a pair may be drawn with several objects).
    object: u64,
}

static NEXT_OBJECT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// A new [`WarpObject`] identity.
pub(crate) fn fresh_object_id() -> u64 {
    NEXT_OBJECT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// `Ok` when a slot prepared at `poses` reposes of `object` may still be drawn: its plan's
/// bin ranges are of the object's current index order.
///
/// # Errors
/// [`WarpError::PoseMismatch`] when the object was reposed since (prepare again).
pub(crate) fn check_pose(object: &WarpObject, poses: u64) -> Result<(), WarpError> {
    if poses == object.poses {
        Ok(())
    } else {
        Err(WarpError::PoseMismatch(format!(
            "prepared at the proxy's pose {poses}, drawn at its pose {}: prepare again",
            object.poses
        )))
    }
}

/// The vertex attributes of reference 0's proxy snapshot (`vs_warp`'s locations 3 and 4:
/// position and normal, laid out as [`npr_gpu::Vertex`]).
const SNAPSHOT0: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![3 => Float32x3, 4 => Float32x3];
/// Reference 1's (locations 5 and 6).
const SNAPSHOT1: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![5 => Float32x3, 6 => Float32x3];

/// The vertex buffer layouts of the warp pipelines: the current proxy, then reference 0's
/// and reference 1's snapshots (the current proxy again when a reference has none).
pub(crate) fn vertex_layouts() -> [Option<wgpu::VertexBufferLayout<'static>>; 3] {
    let snapshot = |attributes: &'static [wgpu::VertexAttribute]| wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<npr_gpu::Vertex>() as wgpu::BufferAddress,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes,
    };
    [
        Some(npr_gpu::Vertex::layout()),
        Some(snapshot(&SNAPSHOT0)),
        Some(snapshot(&SNAPSHOT1)),
    ]
}

/// Binds the warp's three vertex buffers: the current proxy at slot 0, each reference's
/// snapshot (or the current proxy) at slots 1 and 2.
pub(crate) fn bind_vertices(
    pass: &mut wgpu::RenderPass<'_>,
    object: &WarpObject,
    snapshots: &[Option<Snapshot>; 2],
) {
    let current = &object.mesh.vertex_buffer;
    pass.set_vertex_buffer(0, current.slice(..));
    for (i, s) in snapshots.iter().enumerate() {
        let buffer = match s {
            Some(s) if s.object == object.id && s.buffer.size() == current.size() => &s.buffer,
            _ => current,
        };
        pass.set_vertex_buffer(1 + i as u32, buffer.slice(..));
    }
}

impl WarpObject {
    /// Poses the proxy as `posed` ([`Proxy::posed`] of the proxy this object was created
    /// from): inflates it by the object's inflation along the posed normals, bins its faces
    /// by their posed normals (§3.3.2) and writes its vertices and sorted indices. From
    /// then on the object deforms: references record a snapshot of it
    /// ([`ReferenceFrame::keep_proxy_pose`], done by [`crate::Warper`]). Bins culled for
    /// the current camera use the current normals; a reference's ramp weight (§3.3.3) uses
    /// them too, an approximation where the body turned between the reference and now
    /// that the depth test corrects per fragment.
    ///
    /// # Errors
    /// [`WarpError::PoseMismatch`] for another vertex or triangle count;
    /// as [`NormalBins::build`] otherwise.
    pub fn repose(&mut self, queue: &wgpu::Queue, posed: &Proxy) -> Result<(), WarpError> {
        let mesh = posed.inflated(self.inflation);
        if mesh.positions.len() != self.mesh.vertex_count as usize
            || mesh.indices.len() != self.bins.indices.len()
        {
            return Err(WarpError::PoseMismatch(format!(
                "a proxy of {} vertices and {} triangles for an object of {} and {}",
                mesh.positions.len(),
                mesh.indices.len() / 3,
                self.mesh.vertex_count,
                self.bins.indices.len() / 3
            )));
        }
        let bins = NormalBins::build(&mesh, self.bins.per_axis)?;
        self.mesh.write_vertices(queue, &mesh)?;
        queue.write_buffer(
            &self.mesh.index_buffer,
            0,
            bytemuck::cast_slice(&bins.indices),
        );
        self.bins = bins;
        self.poses += 1;
        Ok(())
    }

    /// `true` once [`WarpObject::repose`] has posed it.
    pub fn deforms(&self) -> bool {
        self.poses > 0
    }
}

impl ReferenceFrame {
    /// Records into `encoder` a copy of `object`'s current proxy vertices as this
    /// reference's snapshot, which warps of `object` bound with this reference project it
    /// through (see the module docs; other objects drawn with the same pair use their
    /// current vertices). Call after [`ReferenceFrame::record`], with the object posed at
    /// the reference's pose; a rigid object needs none. Recording the reference again
    /// drops the snapshot until this is called again.
    pub fn keep_proxy_pose(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        object: &WarpObject,
    ) {
        let source = &object.mesh.vertex_buffer;
        let fits = self
            .proxy_pose
            .as_ref()
            .is_some_and(|s| s.buffer.size() == source.size());
        if !fits {
            self.proxy_pose = Some(Snapshot {
                buffer: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("npr-warp reference proxy pose"),
                    size: source.size(),
                    usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                object: object.id,
            });
        }
        if let Some(snapshot) = &mut self.proxy_pose {
            snapshot.object = object.id;
            encoder.copy_buffer_to_buffer(source, 0, &snapshot.buffer, 0, source.size());
            self.proxy_pose_valid = true;
        }
    }

    /// Drops the proxy snapshot (the reference then projects through the current proxy).
    pub fn forget_proxy_pose(&mut self) {
        self.proxy_pose_valid = false;
    }

    /// The snapshot a pair bound now carries: the last one kept, if taken since the last
    /// record.
    pub(crate) fn snapshot(&self) -> Option<Snapshot> {
        self.proxy_pose.clone().filter(|_| self.proxy_pose_valid)
    }
}
