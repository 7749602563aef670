//! The GPU hatching pass of Yongjin Kim and Seungyong Lee, "Real-time Image-space
//! Hatching" (실시간 영상 공간 해칭), Journal of the Korea Computer Graphics Society, 2008:
//! one fragment shader (`shaders/hatching.wgsl`, `fs_hatch`) over a full-screen triangle,
//! Eq. (1) (§3.1), Eq. (2)–(3) (§3.2) and §3.3, reading a tone/θ G-buffer and the tonal
//! art map. Its CPU twin is [`crate::CpuHatcher`].
//!
//! The pass follows the pass contract ([`npr_gpu::pass`]) and records into the caller's
//! encoder and target; only the helper named for it ([`hatch_image_gpu`]) submits and
//! reads back.

use crate::inputs::pixel_count;
use crate::{HatchError, HatchInputs, HatchParams, HatchUniforms, TonalArtMap};
use npr_gpu::TargetFormats;
use npr_gpu::pass::{FrameId, PassId, Prepared, Slots};
use npr_gpu::render::{self, PipelineBuilder};
use std::sync::OnceLock;

/// Format of the G-buffer: r = tone, g = θ, b = weight of the second surface anchor,
/// a = 1 + the stroke direction's turn rate (rad/pixel) on surfaces, 0 on the background, full 32-bit floats (so θ's bin and the
/// tone's slice are decided on exactly the values the CPU reference sees).
pub const GBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Format of the surface anchors: xy = anchor 0, zw = anchor 1, in pixels
/// ([`crate::StrokeSpace::Surface`]).
pub const ANCHOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Bytes per texel of [`GBUFFER_FORMAT`] and [`ANCHOR_FORMAT`].
const TEXEL_BYTES: u32 = 16;

/// A tone/θ G-buffer ([`GBUFFER_FORMAT`]) with its surface anchors ([`ANCHOR_FORMAT`])
/// and depth buffer ([`npr_gpu::DEPTH_FORMAT`]), written by
/// [`crate::ScenePasses::record_gbuffer`] or uploaded from CPU images with
/// [`GBuffer::from_inputs`].
///
/// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
/// own renderer.
#[derive(Debug)]
pub struct GBuffer {
    /// The [`GBUFFER_FORMAT`] texture (render attachment, texture binding, copy
    /// source/dest).
    pub texture: wgpu::Texture,
    /// Its default view.
    pub view: wgpu::TextureView,
    /// The [`ANCHOR_FORMAT`] texture (same usages).
    pub anchors: wgpu::Texture,
    /// Its default view.
    pub anchors_view: wgpu::TextureView,
    /// Depth texture for drawing the scene into it.
    pub depth: wgpu::Texture,
    /// View of `depth`.
    pub depth_view: wgpu::TextureView,
}

impl GBuffer {
    /// An empty G-buffer of `width × height`.
    ///
    /// # Errors
    /// [`HatchError::InvalidSize`] for a zero size or one past the device's 2-D limit.
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> Result<Self, HatchError> {
        pixel_count(width, height)?;
        let max = device.limits().max_texture_dimension_2d;
        if width > max || height > max {
            return Err(HatchError::InvalidSize {
                width,
                height,
                reason: "larger than the device's max_texture_dimension_2d",
            });
        }
        let make =
            |label, format, usage| npr_gpu::texture_2d(device, label, width, height, format, usage);
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST;
        let texture = make("npr hatching g-buffer", GBUFFER_FORMAT, usage);
        let anchors = make("npr hatching anchors", ANCHOR_FORMAT, usage);
        let depth = make(
            "npr hatching g-buffer depth",
            npr_gpu::DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        Ok(Self {
            view: texture.create_view(&wgpu::TextureViewDescriptor::default()),
            anchors_view: anchors.create_view(&wgpu::TextureViewDescriptor::default()),
            anchors,
            depth_view: depth.create_view(&wgpu::TextureViewDescriptor::default()),
            texture,
            depth,
        })
    }

    /// A G-buffer holding caller-supplied tone and direction images (2-D use, e.g. flow
    /// fields): the texture is written with `queue.write_texture`.
    ///
    /// # Errors
    /// As [`GBuffer::new`].
    pub fn from_inputs(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        inputs: &HatchInputs,
    ) -> Result<Self, HatchError> {
        let g = Self::new(device, inputs.width(), inputs.height())?;
        g.write(queue, inputs);
        Ok(g)
    }

    /// Overwrites the G-buffer with `inputs` (which must have its size; a different size
    /// writes the overlapping part only). Inputs without anchors get each pixel's centre
    /// as both anchors ([`crate::Anchor::fixed`]): they hatch as in screen space.
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    pub fn write(&self, queue: &wgpu::Queue, inputs: &HatchInputs) {
        let width = inputs.width().min(self.width());
        let height = inputs.height().min(self.height());
        let w = inputs.width() as usize;
        let anchor = |i: usize| match inputs.anchors().and_then(|a| a.get(i)) {
            Some(a) => *a,
            None => crate::Anchor::fixed((i % w) as f32 + 0.5, (i / w) as f32 + 0.5),
        };
        let main: Vec<[f32; 4]> = inputs
            .interleaved()
            .iter()
            .enumerate()
            .map(|(i, &[t, a])| {
                let turn = inputs.turn().and_then(|v| v.get(i)).copied().unwrap_or(0.0);
                [t, a, anchor(i).weight_b, 1.0 + turn]
            })
            .collect();
        let anchors: Vec<[f32; 4]> = (0..main.len())
            .map(|i| {
                let an = anchor(i);
                [an.a[0], an.a[1], an.b[0], an.b[1]]
            })
            .collect();
        for (texture, data) in [(&self.texture, &main), (&self.anchors, &anchors)] {
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                bytemuck::cast_slice(data),
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(inputs.width() * TEXEL_BYTES),
                    rows_per_image: Some(inputs.height()),
                },
                wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
            );
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.texture.width()
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.texture.height()
    }

    /// Reads the G-buffer back as [`HatchInputs`] with its surface anchors (submits and
    /// waits: outside a frame; native only, see [`GBuffer::start_read`] for the browser).
    ///
    /// # Errors
    /// [`HatchError::Gpu`] when readback fails.
    pub fn read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<HatchInputs, HatchError> {
        let main = npr_gpu::readback_texture(device, queue, &self.texture)?;
        let anchors = npr_gpu::readback_texture(device, queue, &self.anchors)?;
        inputs_from(self.width(), self.height(), &main, &anchors)
    }

    /// Reads back the depth buffer (`[0, 1]` device depth, rows top to bottom; 1 where
    /// nothing was drawn; submits and waits), for the pen plotter's hidden-line removal
    /// ([`crate::pen::OutlineView`]).
    ///
    /// # Errors
    /// [`HatchError::Gpu`] when readback fails.
    pub fn read_depth(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<f32>, HatchError> {
        Ok(depth_from(&npr_gpu::readback_texture(
            device,
            queue,
            &self.depth,
        )?))
    }

    /// Reads back which pixels a surface covers (the G-buffer's alpha; submits and waits).
    ///
    /// # Errors
    /// [`HatchError::Gpu`] when readback fails.
    pub fn read_surface_mask(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<bool>, HatchError> {
        Ok(mask_from(&npr_gpu::readback_texture(
            device,
            queue,
            &self.texture,
        )?))
    }

    /// Starts reading back everything the pen plotter traces from ([`GBufferContents`]):
    /// the copies are submitted now, and [`GBufferReadback::try_take`] hands the contents
    /// over once they have reached the CPU, without blocking. This is how the browser
    /// reads back (its maps complete between animation frames); natively,
    /// [`GBufferReadback::wait`] blocks instead.
    ///
    /// # Errors
    /// [`HatchError::Gpu`] when a copy cannot be set up.
    pub fn start_read(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<GBufferReadback, HatchError> {
        let start = |t: &wgpu::Texture| npr_gpu::TextureReadback::start(device, queue, t);
        Ok(GBufferReadback {
            size: (self.width(), self.height()),
            pending: [
                Some(start(&self.texture)?),
                Some(start(&self.anchors)?),
                Some(start(&self.depth)?),
            ],
            bytes: Default::default(),
        })
    }
}

/// What a [`GBuffer`] holds, on the CPU: the inputs of the raster hatching, which pixels a
/// surface covers, and the depth ([`GBuffer::start_read`]).
#[derive(Clone, Debug)]
pub struct GBufferContents {
    /// [`GBuffer::read`].
    pub inputs: HatchInputs,
    /// [`GBuffer::read_surface_mask`].
    pub mask: Vec<bool>,
    /// [`GBuffer::read_depth`].
    pub depth: Vec<f32>,
}

/// A [`GBuffer`] readback in flight ([`GBuffer::start_read`]).
#[derive(Debug)]
pub struct GBufferReadback {
    size: (u32, u32),
    /// The main texture, the anchors and the depth, until each has arrived.
    pending: [Option<npr_gpu::TextureReadback>; 3],
    bytes: [Option<Vec<u8>>; 3],
}

impl GBufferReadback {
    /// The contents once every copy has reached the CPU; `None` while one has not.
    ///
    /// # Errors
    /// [`HatchError::Gpu`] when a map failed, or the inputs' errors for contents that do
    /// not fit the size.
    pub fn try_take(&mut self) -> Option<Result<GBufferContents, HatchError>> {
        for (pending, bytes) in self.pending.iter_mut().zip(&mut self.bytes) {
            if let Some(p) = pending {
                match p.try_take()? {
                    Ok(b) => *bytes = Some(b),
                    Err(e) => return Some(Err(e.into())),
                }
                *pending = None;
            }
        }
        let [Some(main), Some(anchors), Some(depth)] = std::mem::take(&mut self.bytes) else {
            return Some(Err(HatchError::Gpu(npr_gpu::GpuError::Readback(
                "the G-buffer readback was already taken".into(),
            ))));
        };
        let (w, h) = self.size;
        Some(
            inputs_from(w, h, &main, &anchors).map(|inputs| GBufferContents {
                inputs,
                mask: mask_from(&main),
                depth: depth_from(&depth),
            }),
        )
    }

    /// Blocks until the contents have reached the CPU (native: polls `device`).
    ///
    /// # Errors
    /// As [`GBufferReadback::try_take`], or [`HatchError::Gpu`] when polling fails.
    pub fn wait(mut self, device: &wgpu::Device) -> Result<GBufferContents, HatchError> {
        for (pending, bytes) in self.pending.iter_mut().zip(&mut self.bytes) {
            if let Some(p) = pending.take() {
                *bytes = Some(p.wait(device)?);
            }
        }
        self.try_take().unwrap_or_else(|| {
            Err(HatchError::Gpu(npr_gpu::GpuError::Readback(
                "the G-buffer maps had not completed after the device went idle".into(),
            )))
        })
    }
}

/// The G-buffer's `Rgba32Float` texels.
fn texels(bytes: &[u8]) -> impl Iterator<Item = [f32; 4]> + '_ {
    bytes.chunks_exact(TEXEL_BYTES as usize).map(|c| {
        let f = |o: usize| f32::from_le_bytes([c[o], c[o + 1], c[o + 2], c[o + 3]]);
        [f(0), f(4), f(8), f(12)]
    })
}

/// [`HatchInputs`] with anchors from the main texture's and the anchors' bytes.
fn inputs_from(w: u32, h: u32, main: &[u8], anchors: &[u8]) -> Result<HatchInputs, HatchError> {
    let main: Vec<[f32; 4]> = texels(main).collect();
    let pairs: Vec<[f32; 2]> = main.iter().map(|m| [m[0], m[1]]).collect();
    let anchors = main
        .iter()
        .zip(texels(anchors))
        .map(|(m, a)| crate::Anchor {
            a: [a[0], a[1]],
            b: [a[2], a[3]],
            weight_b: m[2],
        })
        .collect();
    let turn = main.iter().map(|m| (m[3] - 1.0).max(0.0)).collect();
    HatchInputs::from_interleaved(w, h, &pairs)?
        .with_anchors(anchors)?
        .with_turn(turn)
}

/// Which pixels a surface covers: the main texture's alpha.
fn mask_from(main: &[u8]) -> Vec<bool> {
    texels(main).map(|t| t[3] > 0.5).collect()
}

/// The depth texture's `Depth32Float` values.
fn depth_from(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// The hatching pass's settings: the tonal art map, uploaded once by [`HatchPass::new`]
/// (a new style is a new pass).
#[derive(Clone, Debug)]
pub struct HatchSettings {
    /// The tonal art map (pen or pencil style).
    pub tam: TonalArtMap,
}

/// One draw's per-frame input to [`HatchPass::prepare`].
#[derive(Clone, Copy, Debug)]
pub struct HatchInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// Bin count, stroke scale, mode and colours.
    pub params: &'a HatchParams,
    /// The weight of surface anchor 1 that the G-buffer holds on every pixel, when it is
    /// the same everywhere ([`crate::ScenePasses::anchor_weight`] for a G-buffer that
    /// [`crate::ScenePasses::record_gbuffer`] wrote): outside the anchors' cross-fade a
    /// variant then reads one anchor only. `None`: read each pixel's weight.
    pub anchor_weight: Option<f32>,
}

/// A G-buffer bound for the hatching pass ([`HatchPass::create_object`]), with the
/// per-frame slots its [`HatchPass::prepare`] fills.
#[derive(Debug)]
pub struct HatchSource {
    gbuffer: wgpu::TextureView,
    anchors: wgpu::TextureView,
    depth: wgpu::TextureView,
    slots: Slots<HatchSlot>,
}

#[derive(Debug)]
struct HatchSlot {
    uniforms: wgpu::Buffer,
    group: wgpu::BindGroup,
    params: HatchParams,
    anchor_weight: Option<f32>,
}

/// The hatching pass: its pipelines and the tonal art map on the GPU, on the pass
/// contract ([`npr_gpu::pass`]): [`HatchPass::new`], [`HatchPass::create_object`] (a
/// G-buffer), [`HatchPass::prepare`], then [`HatchPass::draw`] into the caller's pass or
/// [`HatchPass::record`] (a scene frame's own pass, which skips the background).
///
/// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
/// own renderer.
#[derive(Debug)]
pub struct HatchPass {
    id: PassId,
    /// Pipeline variants by [`Variant::index`], compiled on first use (a software
    /// adapter compiles each in tens of milliseconds; a frame uses one or two).
    pipelines: Vec<OnceLock<wgpu::RenderPipeline>>,
    device: wgpu::Device,
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    target_format: wgpu::TextureFormat,
    layout: wgpu::BindGroupLayout,
    tam_view: wgpu::TextureView,
    /// Bilinear, wrapping: the surface variants' reads of the map.
    tam_sampler: wgpu::Sampler,
    tam: TonalArtMap,
}

impl HatchPass {
    /// Builds the pass drawing into targets of `formats.color` (linear colour is written;
    /// an sRGB format encodes it) and uploads the settings' tonal art map.
    ///
    /// # Errors
    /// [`HatchError::InvalidParams`] for a map without levels.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        formats: TargetFormats,
        settings: &HatchSettings,
    ) -> Result<Self, HatchError> {
        let tam = &settings.tam;
        HatchUniforms::new(&HatchParams::default(), tam)?;
        let module = crate::shaders::HATCHING.module(device);
        use npr_gpu::layout::{FILTERABLE, UNFILTERABLE, sampler_entry, uniform_entry};
        let texture_entry = |binding, view_dimension| {
            npr_gpu::layout::texture_entry(binding, view_dimension, UNFILTERABLE)
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr hatching"),
            entries: &[
                uniform_entry(0),
                npr_gpu::layout::texture_entry(1, wgpu::TextureViewDimension::D2Array, FILTERABLE),
                texture_entry(2, wgpu::TextureViewDimension::D2),
                texture_entry(3, wgpu::TextureViewDimension::D2),
                sampler_entry(4),
            ],
        });
        let pipeline_layout = render::pipeline_layout(device, "npr hatching", &[&layout]);
        let tam_view =
            tam.upload_tone_pairs(device, queue)
                .create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2Array),
                    ..Default::default()
                });
        // Surface-anchored strokes move by fractions of a texel from frame to frame: the
        // surface variants read the map filtered (bilinear, wrapping), so that a stroke's
        // edge slides instead of snapping from texel to texel.
        let tam_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("npr hatching tonal art map"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Ok(Self {
            id: PassId::fresh(),
            tam_sampler,
            pipelines: (0..Variant::COUNT).map(|_| OnceLock::new()).collect(),
            device: device.clone(),
            module,
            pipeline_layout,
            target_format: formats.color,
            layout,
            tam_view,
            tam: tam.clone(),
        })
    }

    /// The tonal art map in use.
    pub fn tam(&self) -> &TonalArtMap {
        &self.tam
    }

    /// Binds `gbuffer` (its tone/θ texture, its surface anchors and its depth).
    pub fn create_object(&self, _device: &wgpu::Device, gbuffer: &GBuffer) -> HatchSource {
        HatchSource {
            gbuffer: gbuffer.view.clone(),
            anchors: gbuffer.anchors_view.clone(),
            depth: gbuffer.depth_view.clone(),
            slots: Slots::new(self.id),
        }
    }

    /// Writes one draw's parameters into a fresh slot of `source`.
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    ///
    /// # Errors
    /// [`HatchError::InvalidParams`] when `input.params` fails [`HatchParams::validate`]
    /// (nothing is written); [`HatchError::Pass`] for a source of another pass.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        source: &mut HatchSource,
        input: &HatchInput<'_>,
    ) -> Result<Prepared, HatchError> {
        let u = HatchUniforms::new(input.params, &self.tam)?;
        let device = &self.device;
        let (gbuffer, anchors) = (source.gbuffer.clone(), source.anchors.clone());
        let (prepared, slot) = source.slots.next(self.id, input.frame, || {
            let uniforms = render::uniform_buffer(
                device,
                "npr hatching uniforms",
                std::mem::size_of::<HatchUniforms>(),
            );
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("npr hatching"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: uniforms.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&self.tam_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(&gbuffer),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(&anchors),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::Sampler(&self.tam_sampler),
                    },
                ],
            });
            HatchSlot {
                uniforms,
                group,
                params: *input.params,
                anchor_weight: None,
            }
        })?;
        queue.write_buffer(&slot.uniforms, 0, bytemuck::bytes_of(&u));
        slot.params = *input.params;
        slot.anchor_weight = input.anchor_weight;
        Ok(prepared)
    }

    /// The pipeline of `variant`, compiled the first time it is asked for.
    fn pipeline(&self, variant: Variant) -> Option<&wgpu::RenderPipeline> {
        let cell = self.pipelines.get(variant.index())?;
        Some(cell.get_or_init(|| {
            let constants = [
                ("SURFACE", f64::from(u8::from(variant.surface))),
                ("SHORT_STROKES", f64::from(u8::from(variant.short))),
                ("ANCHORS", f64::from(variant.anchors)),
                ("MODE", f64::from(variant.mode)),
            ];
            let targets = [Some(self.target_format.into())];
            let vs = if variant.masked {
                "vs_fullscreen_far"
            } else {
                "vs_fullscreen"
            };
            let builder = PipelineBuilder::new(
                "npr hatching fs_hatch",
                &self.pipeline_layout,
                &self.module,
                vs,
                "fs_hatch",
            )
            .constants(&constants)
            .targets(&targets);
            if variant.masked {
                builder
                    .depth(npr_gpu::DEPTH_FORMAT, false, wgpu::CompareFunction::Greater)
                    .build(&self.device)
            } else {
                builder.build(&self.device)
            }
        }))
    }

    /// The variant for a slot's parameters and anchor weight, and the depth mask.
    fn variant(slot: &HatchSlot, masked: bool) -> Variant {
        let surface = slot.params.space == crate::StrokeSpace::Surface;
        let anchors = match slot.anchor_weight {
            Some(w) if surface && w == 0.0 => 0,
            Some(w) if surface && w == 1.0 => 1,
            _ => 2,
        };
        let mode = match slot.params.mode {
            crate::BlendMode::CutAndPaste => 0,
            crate::BlendMode::Blended => 1,
            crate::BlendMode::OffsetPartition => 2,
        };
        Variant {
            surface,
            short: slot.params.stroke_length.is_some(),
            anchors,
            masked,
            mode,
        }
    }

    /// Records the full-screen hatching draw into the caller's render pass (whose colour
    /// target has the format given to [`HatchPass::new`] and the G-buffer's size). Every
    /// pixel is shaded, the background as paper.
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    ///
    /// # Errors
    /// [`HatchError::Pass`] for a `prepared` of another source, pass or frame.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        source: &HatchSource,
        prepared: &Prepared,
    ) -> Result<(), HatchError> {
        let slot = source.slots.get(self.id, prepared)?;
        self.draw_variant(pass, &slot.group, Self::variant(slot, false));
        Ok(())
    }

    fn draw_variant(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        bind_group: &wgpu::BindGroup,
        variant: Variant,
    ) {
        let Some(pipeline) = self.pipeline(variant) else {
            return;
        };
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Records the hatching pass of a scene frame into its own render pass over `target`
    /// (the G-buffer's size), for a G-buffer written by
    /// [`crate::ScenePasses::record_gbuffer`] earlier in the same encoder. The image
    /// equals [`HatchPass::draw`]'s, at less cost:
    /// - the background is not shaded: the draw sits at the far plane and tests `Greater`
    ///   against the G-buffer's depth (cleared to 1), and the pass clears `target` to the
    ///   paper colour, which is what the shader writes where there is no ink;
    /// - outside the cross-fade ([`HatchInput::anchor_weight`] 0 or 1) a variant reads
    ///   only the weighted anchor (lavapipe runs both sides of a per-pixel branch, so the
    ///   choice is made here).
    ///
    /// # Errors
    /// [`HatchError::Pass`] for a `prepared` of another source, pass or frame.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        source: &HatchSource,
        prepared: &Prepared,
    ) -> Result<(), HatchError> {
        let slot = source.slots.get(self.id, prepared)?;
        let [r, g, b] = slot.params.paper;
        let mut pass = render::begin_pass(
            encoder,
            "npr hatching (scene)",
            &[Some(render::color_attachment(
                target,
                render::clear_color([f64::from(r), f64::from(g), f64::from(b), 1.0]),
            ))],
            Some(wgpu::RenderPassDepthStencilAttachment {
                view: &source.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
        );
        self.draw_variant(&mut pass, &slot.group, Self::variant(slot, true));
        Ok(())
    }
}

npr_gpu::impl_pass!(HatchPass, HatchSource, HatchInput, HatchError);

/// One compiled form of the hatching shader: its pipeline-overridable constants (see
/// `shaders/hatching.wgsl`) and whether it draws at the far plane against a depth buffer.
#[derive(Clone, Copy, Debug)]
struct Variant {
    surface: bool,
    short: bool,
    /// 0 or 1: that anchor alone; 2: both, cross-faded.
    anchors: u8,
    masked: bool,
    /// The blend mode (`HatchUniforms::config[1]`: 0 cut-and-paste, 1 blended, 2 offset
    /// partition).
    mode: u8,
}

impl Variant {
    const COUNT: usize = 2 * 2 * 3 * 2 * 3;

    fn index(self) -> usize {
        (((usize::from(self.surface) * 2 + usize::from(self.short)) * 3
            + usize::from(self.anchors.min(2)))
            * 2
            + usize::from(self.masked))
            * 3
            + usize::from(self.mode.min(2))
    }
}

/// One-call GPU hatching of CPU images: uploads `inputs`, hatches into an
/// [`npr_gpu::COLOR_FORMAT`] target, submits, waits and reads back the sRGB image. For
/// tests, tools and 2-D use; a renderer records [`HatchPass`] itself.
///
/// # Errors
/// [`HatchError::InvalidParams`], [`HatchError::InvalidSize`], or [`HatchError::Gpu`] when
/// readback fails.
pub fn hatch_image_gpu(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    inputs: &HatchInputs,
    tam: &TonalArtMap,
    params: &HatchParams,
) -> Result<image::RgbaImage, HatchError> {
    let formats = TargetFormats::new(npr_gpu::COLOR_FORMAT, npr_gpu::DEPTH_FORMAT);
    let settings = HatchSettings { tam: tam.clone() };
    let pass = HatchPass::new(device, queue, formats, &settings)?;
    let gbuffer = GBuffer::from_inputs(device, queue, inputs)?;
    let target = npr_gpu::OffscreenTarget::new(device, inputs.width(), inputs.height())?;
    let mut source = pass.create_object(device, &gbuffer);
    let input = HatchInput {
        frame: FrameId::default(),
        params,
        anchor_weight: None,
    };
    let prepared = pass.prepare(queue, &mut source, &input)?;
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("npr hatch_image_gpu"),
    });
    {
        let mut rpass = render::begin_color_pass(
            &mut encoder,
            "npr hatching",
            &target.color_view,
            wgpu::LoadOp::Clear(wgpu::Color::WHITE),
        );
        pass.draw(&mut rpass, &source, &prepared)?;
    }
    queue.submit(Some(encoder.finish()));
    Ok(npr_gpu::readback_rgba(device, queue, &target.color)?)
}
