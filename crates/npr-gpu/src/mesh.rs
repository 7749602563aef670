//! Mesh upload: interleaved vertices (position, normal, uv) and `u32` indices.

use crate::GpuError;
use npr_geometry::Mesh;
use wgpu::util::DeviceExt;

/// One interleaved render vertex as the base shaders read it (`@location(0..2)`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// Object-space position.
    pub position: [f32; 3],
    /// Object-space unit normal.
    pub normal: [f32; 3],
    /// Texture coordinate.
    pub uv: [f32; 2],
}

impl Vertex {
    /// Attributes: position at location 0, normal at 1, uv at 2.
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 3] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2];

    /// The vertex buffer layout for [`Vertex`].
    pub fn layout() -> wgpu::VertexBufferLayout<'static> {
        wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as wgpu::BufferAddress,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &Self::ATTRIBUTES,
        }
    }
}

/// A mesh resident on the GPU. Cloning shares the buffers (no copy).
#[derive(Clone, Debug)]
pub struct GpuMesh {
    /// Interleaved [`Vertex`] buffer.
    pub vertex_buffer: wgpu::Buffer,
    /// `u32` triangle-list index buffer (also usable as a storage buffer).
    pub index_buffer: wgpu::Buffer,
    /// Number of indices.
    pub index_count: u32,
    /// Number of vertices.
    pub vertex_count: u32,
}

/// Checks that the vertex and index buffers of a mesh with `vertex_count` vertices and
/// `index_count` indices fit `limits`: `max_buffer_size` for both, and
/// `max_storage_buffer_binding_size` for both (the specular and warping passes bind
/// them whole as storage buffers). Pure, so it can be tested with made-up limits.
///
/// # Errors
/// [`GpuError::MeshTooLarge`] naming the buffer, its size, the limit and its value.
pub fn check_mesh_limits(
    vertex_count: usize,
    index_count: usize,
    limits: &wgpu::Limits,
) -> Result<(), GpuError> {
    let vertex_bytes = (vertex_count as u64).saturating_mul(std::mem::size_of::<Vertex>() as u64);
    let index_bytes = (index_count as u64).saturating_mul(4);
    for (buffer, size) in [("vertex", vertex_bytes), ("index", index_bytes)] {
        for (limit_name, limit) in [
            ("max_buffer_size", limits.max_buffer_size),
            (
                "max_storage_buffer_binding_size",
                limits.max_storage_buffer_binding_size,
            ),
        ] {
            if size > limit {
                return Err(GpuError::MeshTooLarge {
                    buffer,
                    size,
                    limit_name,
                    limit,
                });
            }
        }
    }
    Ok(())
}

/// `mesh`'s vertices as the vertex buffer holds them (uvs 0 where the mesh has none).
fn vertices(mesh: &Mesh) -> Vec<Vertex> {
    (0..mesh.positions.len())
        .map(|i| Vertex {
            position: mesh.positions[i].to_array(),
            normal: mesh.normals[i].to_array(),
            uv: mesh.uvs.get(i).map_or([0.0; 2], |uv| uv.to_array()),
        })
        .collect()
}

impl GpuMesh {
    /// Uploads `mesh`.
    ///
    /// # Errors
    /// [`GpuError::InvalidMesh`] when the mesh has no triangles, its attribute arrays differ
    /// in length, its index count is not a multiple of 3, or an index is out of range;
    /// [`GpuError::MeshTooLarge`] when a buffer would exceed the device's limits
    /// ([`check_mesh_limits`]).
    pub fn upload(device: &wgpu::Device, mesh: &Mesh) -> Result<Self, GpuError> {
        let n = mesh.positions.len();
        if mesh.indices.is_empty() || !mesh.indices.len().is_multiple_of(3) {
            return Err(GpuError::InvalidMesh(format!(
                "{} indices: need a positive multiple of 3",
                mesh.indices.len()
            )));
        }
        if mesh.normals.len() != n || (mesh.uvs.len() != n && !mesh.uvs.is_empty()) {
            return Err(GpuError::InvalidMesh(format!(
                "{n} positions but {} normals and {} uvs",
                mesh.normals.len(),
                mesh.uvs.len()
            )));
        }
        if let Some(bad) = mesh.indices.iter().find(|&&i| i as usize >= n) {
            return Err(GpuError::InvalidMesh(format!(
                "index {bad} out of range for {n} vertices"
            )));
        }
        check_mesh_limits(n, mesh.indices.len(), &device.limits())?;
        let vertices = vertices(mesh);
        Ok(Self {
            vertex_buffer: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("npr mesh vertices"),
                contents: bytemuck::cast_slice(&vertices),
                // STORAGE: the posing pass writes a pose here; COPY_SRC: read it back.
                usage: wgpu::BufferUsages::VERTEX
                    | wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
            }),
            index_buffer: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("npr mesh indices"),
                contents: bytemuck::cast_slice(&mesh.indices),
                usage: wgpu::BufferUsages::INDEX
                    | wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST,
            }),
            index_count: mesh.indices.len() as u32,
            vertex_count: n as u32,
        })
    }

    /// Writes `mesh`'s vertices into the uploaded buffer in place (a new pose of the same
    /// mesh): everything bound to this mesh stays valid and draws the new positions,
    /// normals and uvs. The triangles stay as uploaded.
    ///
    /// # Errors
    /// [`GpuError::InvalidMesh`] when `mesh` has another vertex count or attribute arrays
    /// of different lengths.
    pub fn write_vertices(&self, queue: &wgpu::Queue, mesh: &Mesh) -> Result<(), GpuError> {
        let n = mesh.positions.len();
        if n != self.vertex_count as usize
            || mesh.normals.len() != n
            || (mesh.uvs.len() != n && !mesh.uvs.is_empty())
        {
            return Err(GpuError::InvalidMesh(format!(
                "a pose of {n} positions, {} normals and {} uvs for a mesh of {} vertices",
                mesh.normals.len(),
                mesh.uvs.len(),
                self.vertex_count
            )));
        }
        let vertices = vertices(mesh);
        queue.write_buffer(&self.vertex_buffer, 0, bytemuck::cast_slice(&vertices));
        Ok(())
    }

    /// Binds the vertex buffer at slot 0 and the index buffer, and draws every triangle.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
        pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn mesh_limits_name_the_limit_and_the_size() {
        let limits = wgpu::Limits {
            max_buffer_size: 1000,
            max_storage_buffer_binding_size: 600,
            ..wgpu::Limits::default()
        };
        // 18 vertices = 576 bytes, 150 indices = 600 bytes: fits exactly.
        assert!(check_mesh_limits(18, 150, &limits).is_ok());
        let e = check_mesh_limits(19, 3, &limits).unwrap_err();
        assert!(matches!(
            e,
            GpuError::MeshTooLarge {
                buffer: "vertex",
                size: 608,
                limit_name: "max_storage_buffer_binding_size",
                limit: 600
            }
        ));
        let msg = e.to_string();
        assert!(msg.contains("608") && msg.contains("max_storage_buffer_binding_size"));
        let e = check_mesh_limits(3, 300, &limits).unwrap_err();
        assert!(matches!(
            e,
            GpuError::MeshTooLarge {
                buffer: "index",
                size: 1200,
                limit_name: "max_buffer_size",
                limit: 1000
            }
        ));
        // Sizes past u64 saturate instead of wrapping to a small number.
        assert!(check_mesh_limits(usize::MAX, 3, &limits).is_err());
    }
}
