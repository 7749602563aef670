//! The highlight render pass (§5 of the specular paper): draws every highlight's
//! receiver triangles with its projected texture, alpha-blended over any base shading,
//! in one draw call. WGSL: `shaders/specular_highlight.wgsl` ([`crate::shaders`]).
//!
//! Use: draw the base shading into a colour + depth target, then, in the same render pass
//! (or a later one that loads that depth), call [`HighlightPass::draw`]. The pass tests
//! depth with `LessEqual` and does not write it; the vertex transform is the base
//! shader's expression, marked `@invariant`, so receivers land on exactly the base
//! surface's depth.

use crate::setup::frame::Source;
use crate::{HighlightSet, HighlightShape, SpecularError};
use npr_gpu::pass::{FrameId, PassId, Prepared, Slots};
use npr_gpu::render::{self, PipelineBuilder};
use npr_gpu::{FrameUniforms, GpuMesh, ObjectUniforms, TargetFormats, layout};
use wgpu::util::DeviceExt;

/// One projector as the shader reads it (`Projector` in WGSL, 160 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ProjectorGpu {
    /// Eq. (9) world → texture.
    pub tex_from_world: [[f32; 4]; 4],
    /// World u axis; w = the falloff's zero-alpha cosine ([`crate::Highlight::falloff_cos`] x).
    pub axis_u: [f32; 4],
    /// World up axis; w = the falloff's full-alpha cosine ([`crate::Highlight::falloff_cos`] y).
    pub axis_v: [f32; 4],
    /// Normal at the centre, w unused.
    pub normal: [f32; 4],
    /// Linear tint, a = opacity.
    pub tint: [f32; 4],
    /// x = layer, y = normal-map flag, z = Blinn exponent, w unused.
    pub params: [f32; 4],
    /// Indices of the highlights this one shares its region with
    /// ([`crate::Highlight::shared_with`]); `u32::MAX` for none.
    pub neighbours: [u32; 4],
}

/// One draw's per-frame input to [`HighlightPass::prepare`].
///
/// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
/// own renderer.
#[derive(Clone, Copy, Debug)]
pub struct HighlightInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The frame's highlights ([`crate::HighlightSetup::record`], or
    /// [`crate::HighlightFrame::of_set`] for a set the caller updated); made for `frame`.
    pub highlights: &'a crate::HighlightFrame<'a>,
    /// Camera and light.
    pub view: &'a FrameUniforms,
    /// Object transform (must equal the base pass's, for matching depth).
    pub object: &'a ObjectUniforms,
}

/// The highlight pass's settings: plain data, keyed by value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct HighlightSettings {
    /// Side in texels of each built-in texture ([`HighlightShape::ALL`]). Default 128.
    pub texture_size: u32,
}

impl Default for HighlightSettings {
    fn default() -> Self {
        Self { texture_size: 128 }
    }
}

/// The GPU record of one highlight (texture `layer`, shaded as a normal map when
/// `normal_map`). Non-finite values cannot occur for highlights from
/// [`HighlightSet::update`]; they are zeroed here all the same, so no NaN reaches a
/// uniform.
pub fn projector_gpu(h: &crate::Highlight, layer: u32, normal_map: bool) -> ProjectorGpu {
    let p = &h.projector;
    let finite4 = |v: [f32; 4]| v.map(|x| if x.is_finite() { x } else { 0.0 });
    ProjectorGpu {
        tex_from_world: p.tex_from_world.to_cols_array_2d().map(finite4),
        axis_u: finite4(p.axis_u.extend(h.falloff_cos.x).to_array()),
        axis_v: finite4(p.axis_v.extend(h.falloff_cos.y).to_array()),
        normal: finite4(p.normal.extend(0.0).to_array()),
        tint: finite4(h.controls.tint.extend(h.opacity.clamp(0.0, 1.0)).to_array()),
        params: finite4([
            layer as f32,
            if normal_map { 1.0 } else { 0.0 },
            h.controls.shininess,
            0.0,
        ]),
        neighbours: h.shared_with,
    }
}

/// One prepare's GPU state: uniforms, draw list, projectors and normals.
#[derive(Debug)]
struct HighlightSlot {
    frame: wgpu::Buffer,
    object: wgpu::Buffer,
    draw_list: wgpu::Buffer,
    projectors: wgpu::Buffer,
    frame_group: wgpu::BindGroup,
    object_group: wgpu::BindGroup,
    storage_group: wgpu::BindGroup,
    /// Per render vertex: the normal at the set's scale (w = 1), or zero (the shader
    /// then takes the mesh's own normal).
    normals: wgpu::Buffer,
    /// [`HighlightSet::normals_id`] of the normals uploaded.
    normals_id: Option<u64>,
    vertex_count: u32,
    capacity: (u64, u64),
    /// The receiver pass's stream drawn indirectly, when prepared with it: its bind
    /// group and the draw's arguments.
    gpu_stream: Option<(wgpu::BindGroup, wgpu::Buffer)>,
}

/// One mesh's highlights on the GPU: the caller's mesh (its vertex buffer is read as
/// storage, not copied) and the per-frame slots [`HighlightPass::prepare`] fills.
#[derive(Debug)]
pub struct HighlightObject {
    mesh: GpuMesh,
    slots: Slots<HighlightSlot>,
}

/// The highlight pipeline and its texture array. Create once per device and formats.
///
/// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
/// own renderer.
#[derive(Debug)]
pub struct HighlightPass {
    id: PassId,
    device: wgpu::Device,
    pipeline: wgpu::RenderPipeline,
    uniform_layout: wgpu::BindGroupLayout,
    storage_layout: wgpu::BindGroupLayout,
    texture_group: wgpu::BindGroup,
    normal_map_layers: Vec<bool>,
}

impl HighlightPass {
    /// Builds the pass for render passes over targets of `formats` (it tests their depth
    /// and does not write it) with the built-in textures ([`HighlightShape::ALL`],
    /// `settings.texture_size`² each).
    ///
    /// # Errors
    /// As [`HighlightPass::with_textures`].
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        formats: TargetFormats,
        settings: &HighlightSettings,
    ) -> Result<Self, SpecularError> {
        let layers = crate::textures::builtin_set(settings.texture_size.max(1));
        let normal: Vec<bool> = HighlightShape::ALL
            .iter()
            .map(|s| s.is_normal_map())
            .collect();
        Self::with_textures(device, queue, formats, &layers, &normal)
    }

    /// Builds the pass with caller textures (all the same square size; layer i is a normal
    /// map when `normal_map[i]`).
    ///
    /// # Errors
    /// [`SpecularError::TextureSet`] for an empty set, mixed sizes, or more layers than the
    /// device allows.
    pub fn with_textures(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        formats: TargetFormats,
        layers: &[image::RgbaImage],
        normal_map: &[bool],
    ) -> Result<Self, SpecularError> {
        let Some(first) = layers.first() else {
            return Err(SpecularError::TextureSet("no textures".into()));
        };
        let (w, h) = first.dimensions();
        if layers.iter().any(|l| l.dimensions() != (w, h)) {
            return Err(SpecularError::TextureSet("textures differ in size".into()));
        }
        if layers.len() as u32 > device.limits().max_texture_array_layers {
            return Err(SpecularError::TextureSet(format!(
                "{} layers exceed the device limit",
                layers.len()
            )));
        }
        let data: Vec<u8> = layers
            .iter()
            .flat_map(|l| l.as_raw().iter().copied())
            .collect();
        let texture = device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some("npr highlight textures"),
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: layers.len() as u32,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba8Unorm,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &data,
        );
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("npr highlight sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let uniform_layout = layout::uniform_layout(device, "npr highlight uniform");
        let storage_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr highlight storage"),
            entries: &[
                layout::storage_entry(0),
                layout::storage_entry(1),
                layout::storage_entry(2),
                layout::storage_entry(3),
            ],
        });
        let texture_layout = layout::texture_sampler_layout(
            device,
            "npr highlight textures",
            wgpu::TextureViewDimension::D2Array,
        );
        let texture_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr highlight textures"),
            layout: &texture_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&sampler),
                },
            ],
        });
        let module = crate::shaders::SPECULAR_HIGHLIGHT.module(device);
        let layout = render::pipeline_layout(
            device,
            "npr highlight",
            &[
                &uniform_layout,
                &uniform_layout,
                &storage_layout,
                &texture_layout,
            ],
        );
        let pipeline = PipelineBuilder::new(
            "npr highlight",
            &layout,
            &module,
            "vs_highlight",
            "fs_highlight",
        )
        .cull(Some(wgpu::Face::Back))
        .depth(formats.depth, false, wgpu::CompareFunction::LessEqual)
        .samples(formats.samples)
        .targets(&[Some(wgpu::ColorTargetState {
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            ..formats.color.into()
        })])
        .build(device);
        let mut normal_map_layers = normal_map.to_vec();
        normal_map_layers.resize(layers.len(), false);
        Ok(Self {
            id: PassId::fresh(),
            device: device.clone(),
            pipeline,
            uniform_layout,
            storage_layout,
            texture_group,
            normal_map_layers,
        })
    }

    /// Per texture layer, whether it is a normal map.
    pub fn normal_map_layers(&self) -> &[bool] {
        &self.normal_map_layers
    }

    /// The GPU form of the set's current highlights.
    pub fn projectors(&self, set: &HighlightSet) -> Vec<ProjectorGpu> {
        let last = self.normal_map_layers.len().saturating_sub(1) as u32;
        set.highlights()
            .iter()
            .map(|h| {
                let layer = h.controls.texture_layer.min(last);
                let normal_map = self
                    .normal_map_layers
                    .get(layer as usize)
                    .copied()
                    .unwrap_or(false);
                projector_gpu(h, layer, normal_map)
            })
            .collect()
    }

    /// The vertex stream: (render vertex, projector) for each receiver triangle corner.
    /// `indices` are the render mesh's triangle indices (faces in topology order).
    pub fn draw_list(set: &HighlightSet, indices: &[u32]) -> Vec<[u32; 2]> {
        let faces = set.receiver_faces();
        let mut out = Vec::with_capacity(faces.len() * 3);
        for (k, h) in set.highlights().iter().enumerate() {
            for &f in &faces[h.receivers.clone()] {
                let base = f as usize * 3;
                if let Some(tri) = indices.get(base..base + 3) {
                    out.extend(tri.iter().map(|&v| [v, k as u32]));
                }
            }
        }
        out
    }

    /// The vertex stream without the §4.2 restriction: every face of the mesh is a
    /// receiver of every highlight, so a projector textures all the surface inside its
    /// frustum — the wrong projection of the specular paper's Fig. 5(a), for figures and
    /// comparisons. Draw it with [`crate::HighlightFrame::with_list`].
    pub fn draw_list_unrestricted(set: &HighlightSet, indices: &[u32]) -> Vec<[u32; 2]> {
        let faces = indices.len() / 3;
        let mut out = Vec::with_capacity(faces * 3 * set.highlights().len());
        for k in 0..set.highlights().len() {
            out.extend(indices[..faces * 3].iter().map(|&v| [v, k as u32]));
        }
        out
    }

    /// An object for `mesh` (its vertex buffer is read as storage, shared with the
    /// caller, not copied).
    pub fn create_object(&self, _device: &wgpu::Device, mesh: &GpuMesh) -> HighlightObject {
        HighlightObject {
            mesh: mesh.clone(),
            slots: Slots::new(self.id),
        }
    }

    fn create_slot(&self, mesh: &GpuMesh) -> HighlightSlot {
        let device = &self.device;
        let uniform = |label, size| render::uniform_buffer(device, label, size);
        let frame = uniform("npr highlight frame", std::mem::size_of::<FrameUniforms>());
        let object = uniform(
            "npr highlight object",
            std::mem::size_of::<ObjectUniforms>(),
        );
        let group = |buffer: &wgpu::Buffer| {
            render::uniform_group(
                device,
                "npr highlight uniform",
                &self.uniform_layout,
                buffer,
            )
        };
        let frame_group = group(&frame);
        let object_group = group(&object);
        let normals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("npr highlight surface normals"),
            size: u64::from(mesh.vertex_count.max(1)) * 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (draw_list, projectors, storage_group) = self.storage(mesh, &normals, 1024, 16);
        HighlightSlot {
            normals,
            normals_id: None,
            frame,
            object,
            draw_list,
            projectors,
            frame_group,
            object_group,
            storage_group,
            vertex_count: 0,
            capacity: (1024, 16),
            gpu_stream: None,
        }
    }

    fn storage(
        &self,
        mesh: &GpuMesh,
        normals: &wgpu::Buffer,
        list_capacity: u64,
        projector_capacity: u64,
    ) -> (wgpu::Buffer, wgpu::Buffer, wgpu::BindGroup) {
        let device = &self.device;
        let make = |label, size: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let list = make("npr highlight draw list", list_capacity * 8);
        let projectors = make(
            "npr highlight projectors",
            projector_capacity * std::mem::size_of::<ProjectorGpu>() as u64,
        );
        let group = self.storage_group(mesh, normals, &list, projectors.as_entire_binding());
        (list, projectors, group)
    }

    fn storage_group(
        &self,
        mesh: &GpuMesh,
        normals: &wgpu::Buffer,
        list: &wgpu::Buffer,
        projectors: wgpu::BindingResource<'_>,
    ) -> wgpu::BindGroup {
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr highlight storage"),
            layout: &self.storage_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: mesh.vertex_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: list.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: projectors,
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: normals.as_entire_binding(),
                },
            ],
        })
    }

    /// Writes one draw's camera/light, object transform and highlights into a fresh slot
    /// of `object` (growing its buffers when needed). A frame the CPU made uploads its
    /// projectors and receiver list; one the GPU made is drawn where it lies (its stream
    /// indirectly), nothing of it written here.
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for an object of another pass, too many prepares in one
    /// frame, or highlights made for another frame.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut HighlightObject,
        input: &HighlightInput<'_>,
    ) -> Result<Prepared, SpecularError> {
        let highlights = input.highlights;
        highlights.check(input.frame)?;
        let set = highlights.set();
        let own;
        let (list, stream, gpu) = match highlights.source {
            Source::Set {
                list: Some(list), ..
            } => (list, None, None),
            Source::Set { indices, .. } => {
                own = Self::draw_list(set, indices);
                (&own[..], None, None)
            }
            Source::Gpu {
                stream, projectors, ..
            } => (&[][..], Some(stream), Some(projectors)),
        };
        let mesh = &object.mesh;
        let (prepared, slot) = object
            .slots
            .next(self.id, input.frame, || self.create_slot(mesh))?;
        queue.write_buffer(&slot.frame, 0, bytemuck::bytes_of(input.view));
        queue.write_buffer(&slot.object, 0, bytemuck::bytes_of(input.object));
        let projectors = match gpu {
            Some(_) => Vec::new(),
            None => self.projectors(set),
        };
        let need = (list.len() as u64, projectors.len() as u64);
        if need.0 > slot.capacity.0 || need.1 > slot.capacity.1 {
            let cap = (
                need.0.next_power_of_two().max(slot.capacity.0),
                need.1.next_power_of_two().max(slot.capacity.1),
            );
            let (l, p, g) = self.storage(mesh, &slot.normals, cap.0, cap.1);
            (slot.draw_list, slot.projectors, slot.storage_group) = (l, p, g);
            slot.capacity = cap;
        }
        if !list.is_empty() {
            queue.write_buffer(&slot.draw_list, 0, bytemuck::cast_slice(list));
        }
        if !projectors.is_empty() {
            queue.write_buffer(&slot.projectors, 0, bytemuck::cast_slice(&projectors));
        }
        if slot.normals_id != Some(set.normals_id()) {
            let data = surface_normals(set, mesh.vertex_count as usize);
            if !data.is_empty() {
                queue.write_buffer(&slot.normals, 0, bytemuck::cast_slice(&data));
            }
            slot.normals_id = Some(set.normals_id());
        }
        slot.vertex_count = list.len() as u32;
        slot.gpu_stream = stream.zip(gpu).map(|((list, args), g)| {
            // A pose made on the GPU brings its own normals.
            let normals = g.posed_normals.as_ref().unwrap_or(&slot.normals);
            let group = self.storage_group(mesh, normals, list, g.projector_binding());
            (group, args.clone())
        });
        Ok(prepared)
    }

    /// Records the highlight draw (one call for all highlights) into the caller's render
    /// pass, which must have the base shading's depth attachment.
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a `prepared` of another object, pass or frame; nothing
    /// is recorded then.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        object: &HighlightObject,
        prepared: &Prepared,
    ) -> Result<(), SpecularError> {
        let slot = object.slots.get(self.id, prepared)?;
        if slot.vertex_count == 0 && slot.gpu_stream.is_none() {
            return Ok(());
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &slot.frame_group, &[]);
        pass.set_bind_group(1, &slot.object_group, &[]);
        pass.set_bind_group(3, &self.texture_group, &[]);
        match &slot.gpu_stream {
            Some((group, args)) => {
                pass.set_bind_group(2, group, &[]);
                pass.draw_indirect(args, 0);
            }
            None => {
                pass.set_bind_group(2, &slot.storage_group, &[]);
                pass.draw(0..slot.vertex_count, 0..1);
            }
        }
        Ok(())
    }
}

npr_gpu::impl_pass!(
    HighlightPass,
    HighlightObject,
    HighlightInput,
    SpecularError
);

/// The set's normals (at its abstraction scale) where they fit the mesh, else zero: the
/// shader then falls back to the mesh's own.
fn surface_normals(set: &HighlightSet, count: usize) -> Vec<[f32; 4]> {
    let normals = set.render_normals();
    if normals.len() != count {
        return vec![[0.0; 4]; count];
    }
    normals
        .iter()
        .map(|n| {
            if n.is_finite() {
                n.extend(1.0).to_array()
            } else {
                [0.0; 4]
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unrestricted_list_covers_every_face_for_every_highlight() {
        let mesh = npr_geometry::generate::icosphere(3, 1.0);
        let mut set = HighlightSet::new(&mesh, &npr_geometry::CurvatureOptions::default())
            .expect("sphere set");
        let d = glam::Vec3::new(0.3, 0.4, 1.0).normalize();
        set.update(
            npr_geometry::LightEye::Directions {
                to_light: d,
                to_eye: d,
            },
            glam::Mat4::IDENTITY,
        );
        let highlights = set.highlights().len();
        assert!(highlights > 0, "the sphere has a highlight");
        let restricted = HighlightPass::draw_list(&set, &mesh.indices);
        let all = HighlightPass::draw_list_unrestricted(&set, &mesh.indices);
        assert_eq!(all.len(), mesh.indices.len() * highlights);
        assert!(restricted.len() < all.len(), "§4.2 restricts the receivers");
        // Every restricted entry is in the unrestricted list (same projector index).
        let set_all: std::collections::HashSet<[u32; 2]> = all.iter().copied().collect();
        assert!(restricted.iter().all(|e| set_all.contains(e)));
    }

    #[test]
    fn projector_layout_matches_wgsl() {
        // Size and member offsets of the storage array's element, read by naga.
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            ProjectorGpu,
            "Projector",
            [
                tex_from_world,
                axis_u,
                axis_v,
                normal,
                tint,
                params,
                neighbours
            ]
        );
    }
}
