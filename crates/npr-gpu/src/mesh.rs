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

/// A mesh resident on the GPU.
#[derive(Debug)]
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

impl GpuMesh {
    /// Uploads `mesh`.
    ///
    /// # Errors
    /// [`GpuError::InvalidMesh`] when the mesh has no triangles, its attribute arrays differ
    /// in length, its index count is not a multiple of 3, or an index is out of range.
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
        let vertices: Vec<Vertex> = (0..n)
            .map(|i| Vertex {
                position: mesh.positions[i].to_array(),
                normal: mesh.normals[i].to_array(),
                uv: mesh.uvs.get(i).map_or([0.0; 2], |uv| uv.to_array()),
            })
            .collect();
        Ok(Self {
            vertex_buffer: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("npr mesh vertices"),
                contents: bytemuck::cast_slice(&vertices),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
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

    /// Binds the vertex buffer at slot 0 and the index buffer, and draws every triangle.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
        pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }
}
