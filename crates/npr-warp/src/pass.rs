//! The warp pass (§3.3.1–§3.3.3): the proxy drawn at the current pose with both reference
//! images projected onto it, per normal bin with one reference or two blended, plus the
//! reference depth test (beyond the paper). WGSL: `shaders/warp.wgsl`.
//!
//! Texture matrices: for reference i, `tex_from_object_i = TEX_FROM_CLIP ·
//! clip_from_world_i · world_from_object_i` ([`npr_gpu::projective::tex_from_world`], the
//! paper's §2.2 bias/scale × reference view-projection), applied to the proxy's
//! object-space points; the object may move, the camera may move, or both.

use crate::bins::{BinPlan, DrawKind, NormalBins, PlanSettings};
use crate::msaa::Antialiasing;
use crate::reference::{ObjectView, ReferenceFrame};
use crate::{Proxy, WarpError};
use glam::{Mat4, Vec4};
use npr_gpu::pass::{FrameId, PassId, Prepared, Slots};
use npr_gpu::render::{self, PipelineBuilder};
use npr_gpu::{GpuMesh, TargetFormats, projective};
use wgpu::util::DeviceExt;

/// The `WarpObject` uniform block of `warp.wgsl` (272 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct WarpObjectUniforms {
    /// Object → clip of the current camera and pose.
    pub clip_from_object: [[f32; 4]; 4],
    /// Object → texture space of reference 0 (§2.2).
    pub tex_from_object0: [[f32; 4]; 4],
    /// Object → texture space of reference 1.
    pub tex_from_object1: [[f32; 4]; 4],
    /// near, far of reference 0, then of reference 1.
    pub ref_near_far: [f32; 4],
    /// x = depth tolerance (world units), y, z = reference width and height, w = surface
    /// slack (world units).
    pub params: [f32; 4],
    /// Reference 0's eye in object space; w = the angle one of its texels subtends.
    pub eye0_object: [f32; 4],
    /// Reference 1's eye in object space; w = the angle one of its texels subtends.
    pub eye1_object: [f32; 4],
    /// Linear colour of the fill shader and of wireframes.
    pub fill_color: [f32; 4],
}

/// What the warp pass draws with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum WarpMode {
    /// The warp with the reference depth test (ours): hidden texels fall back to the other
    /// reference, background texels are discarded.
    DepthTested,
    /// The paper's pass as published (§3.3.1): the reference images projected as they are,
    /// no depth test; texels outside the object project the (transparent) background.
    Paper,
    /// The paper's pass with each lookup divided by the reference's coverage (alpha), so
    /// silhouette pixels average only the object's texels (ours, no depth test).
    PaperCoverage,
    /// The proxy with a constant colour: the fill floor of any warp pass.
    Fill,
}

/// Settings of one warped object.
///
/// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
/// own renderer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WarpSettings {
    /// §3.3.2–§3.3.3 decisions.
    pub plan: PlanSettings,
    /// Depth-test tolerance in world units: the constant part of how far, along the
    /// reference ray, the stored surface may lie from a proxy point and still be its surface.
    pub depth_tolerance_world: f32,
    /// How far the proxy may lie off the true surface, world units (its error plus its
    /// inflation). The full tolerance for a point seen by a reference at angle `cos` is
    /// `depth_tolerance_world + (surface_slack_world + 1.5 texel) / max(cos, 0.05)`, with
    /// `texel` the reference texel's size at the point: nearer by more, the point is hidden
    /// in that reference; farther by more, it floats in empty space.
    pub surface_slack_world: f32,
    /// Colour of [`WarpMode::Fill`] and wireframes (linear RGBA).
    pub fill_color: [f32; 4],
}

impl WarpSettings {
    /// Settings for `proxy` inflated by `inflation_object`, drawn with a transform that
    /// scales object units by `world_per_object`: tolerance = 2 × (error + inflation)
    /// + 1 % of the proxy's radius, slack = error + inflation (all in world units).
    pub fn for_proxy(proxy: &Proxy, inflation_object: f32, world_per_object: f32) -> Self {
        Self {
            depth_tolerance_world: proxy.suggested_depth_tolerance(inflation_object)
                * world_per_object,
            surface_slack_world: (proxy.error_object + inflation_object) * world_per_object,
            ..Default::default()
        }
    }
}

impl WarpSettings {
    /// Checks every setting's range: tolerances finite and non-negative, the fill colour
    /// finite, the plan's ([`PlanSettings::validate`]).
    ///
    /// # Errors
    /// [`WarpError::InvalidSetting`] naming the bad value.
    pub fn validate(&self) -> Result<(), WarpError> {
        self.plan.validate()?;
        for (name, v) in [
            ("depth_tolerance_world", self.depth_tolerance_world),
            ("surface_slack_world", self.surface_slack_world),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(WarpError::InvalidSetting(format!(
                    "{name} {v} is not a finite non-negative distance"
                )));
            }
        }
        if !self.fill_color.iter().all(|c| c.is_finite()) {
            return Err(WarpError::InvalidSetting(format!(
                "fill_color {:?} is not finite",
                self.fill_color
            )));
        }
        Ok(())
    }
}

impl Default for WarpSettings {
    fn default() -> Self {
        Self {
            plan: PlanSettings::default(),
            depth_tolerance_world: 0.02,
            surface_slack_world: 0.02,
            fill_color: [0.8, 0.2, 0.1, 1.0],
        }
    }
}

/// View distance of a WebGPU (0..1) perspective depth with planes `near`, `far`; `far`
/// (the background) when the planes coincide or the division is not finite.
pub fn distance_of_depth(depth: f32, near: f32, far: f32) -> f32 {
    let d = near * far / (far - depth * (far - near));
    if d.is_finite() { d } else { far }
}

fn in_frame(uv: glam::Vec2) -> bool {
    uv.cmpge(glam::Vec2::ZERO).all() && uv.cmple(glam::Vec2::ONE).all()
}

/// CPU twin of the WGSL `look` (the reference depth test, beyond the paper's §3.4):
/// reference i sees the proxy point whose reference-camera clip w is `w_ref` when the
/// surface stored at its texel (`stored_depth`, 0..1) lies within `tolerance` of it along
/// the reference ray (nearer by more: the point is hidden; farther by more: it floats in
/// empty space).
pub fn reference_sees(
    w_ref: f32,
    uv: glam::Vec2,
    stored_depth: f32,
    near: f32,
    far: f32,
    tolerance: f32,
) -> bool {
    if !in_frame(uv) || stored_depth >= 1.0 {
        return false;
    }
    (w_ref - distance_of_depth(stored_depth, near, far)).abs() <= tolerance
}

/// CPU twin of the WGSL `look`'s `empty`: the reference finds no surface near the point
/// (its texel is background, or the stored surface is more than `tolerance` behind it).
pub fn reference_empty(
    w_ref: f32,
    uv: glam::Vec2,
    stored_depth: f32,
    near: f32,
    far: f32,
    tolerance: f32,
) -> bool {
    if !in_frame(uv) {
        return false;
    }
    stored_depth >= 1.0 || distance_of_depth(stored_depth, near, far) - w_ref > tolerance
}

/// Two references bound together for the warp (§3.3: reference images 1 and 2).
#[derive(Debug)]
pub struct ReferencePair {
    bind_group: wgpu::BindGroup,
    /// Poses of reference 0 and 1 (copied when bound; rebind after re-rendering a slot).
    pub poses: [ObjectView; 2],
    /// `clip_from_world` of reference 0 and 1.
    pub clip_from_world: [Mat4; 2],
    size: [u32; 2],
    /// The references' proxy snapshots of a deforming object ([`crate::deform`]).
    proxy_poses: [Option<crate::deform::Snapshot>; 2],
}

/// One prepare's GPU state: the object's uniforms, bin weights, the pair it warps from
/// and the plan of draws.
#[derive(Debug)]
struct WarpSlot {
    uniforms: wgpu::Buffer,
    weights: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    pair_group: Option<wgpu::BindGroup>,
    proxy_poses: [Option<crate::deform::Snapshot>; 2],
    /// The object's [`WarpObject::repose`] count when prepared (the plan's bin ranges are
    /// of that index order).
    poses: u64,
    plan: BinPlan,
    mode: WarpMode,
}

/// A proxy on the GPU, binned (§3.3.2), with its per-frame slots (uniforms and bin
/// weights) that [`WarpPass::prepare`] fills.
#[derive(Debug)]
pub struct WarpObject {
    /// The binned proxy (CPU side: ranges and representative normals).
    pub bins: NormalBins,
    /// The proxy with its index buffer in bin order.
    pub mesh: GpuMesh,
    edges: Option<(wgpu::Buffer, u32)>,
    slots: Slots<WarpSlot>,
    /// The inflation it was created with (object units), kept for [`WarpObject::repose`].
    pub(crate) inflation: f32,
    /// Poses written by [`WarpObject::repose`] (0: as created).
    pub(crate) poses: u64,
    /// This object's identity, which its references' proxy snapshots carry.
    pub(crate) id: u64,
}

impl WarpObject {
    /// The line-list index count of the wireframe (0 when built without one).
    pub fn edge_index_count(&self) -> u32 {
        self.edges.as_ref().map_or(0, |e| e.1)
    }

    /// The plan of draws (§3.3.2–§3.3.3) that `prepared` decided.
    ///
    /// # Errors
    /// [`WarpError::Pass`] for a ticket of another object or frame.
    pub fn plan(&self, pass: &WarpPass, prepared: &Prepared) -> Result<&BinPlan, WarpError> {
        Ok(&self.slots.get(pass.id, prepared)?.plan)
    }
}

/// One draw's per-frame input to [`WarpPass::prepare`].
#[derive(Clone, Copy, Debug)]
pub struct WarpInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The two references warped from.
    pub pair: &'a ReferencePair,
    /// The object drawn now: its own camera and pose.
    pub now: &'a ObjectView,
    /// The frame's position between the two references, `s ∈ [0, 1]`.
    pub s: f32,
    /// The plan settings and tolerances.
    pub settings: &'a WarpSettings,
    /// The fragment shader.
    pub mode: WarpMode,
}

/// The warp pass's settings: the antialiasing (the references' and the warp target's
/// sample counts).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct WarpPassSettings {
    /// References and warped frames: one sample each, or 4-sample references.
    pub antialiasing: Antialiasing,
}

/// The warp pipelines. Create once per device; record with [`WarpPass::draw`].
///
/// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
/// own renderer.
#[derive(Debug)]
pub struct WarpPass {
    id: PassId,
    device: wgpu::Device,
    single: [wgpu::RenderPipeline; 2],
    blend: wgpu::RenderPipeline,
    single_paper: [wgpu::RenderPipeline; 2],
    blend_paper: wgpu::RenderPipeline,
    single_coverage: [wgpu::RenderPipeline; 2],
    blend_coverage: wgpu::RenderPipeline,
    color_format: wgpu::TextureFormat,
    depth_format: wgpu::TextureFormat,
    antialiasing: Antialiasing,
    fill: wgpu::RenderPipeline,
    wire: wgpu::RenderPipeline,
    ref_layout: wgpu::BindGroupLayout,
    object_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
}

impl WarpPass {
    /// Builds the pipelines that warp references (drawn into targets of `formats`' colour
    /// and depth formats at the antialiasing's reference sample count) into the caller's
    /// targets of `formats`: colour `formats.color` (linear colour is written; an sRGB
    /// format encodes it) with `formats.depth` depth (less-equal, write), at
    /// `formats.samples`, which must be the antialiasing's warp sample count.
    ///
    /// The antialiasing ([`WarpPassSettings::antialiasing`]): with one sample each, the
    /// paper's warp. With 4-sample references and a 1-sample
    /// target ([`Antialiasing::Msaa4Blend`]) the depth-tested warp blends its rim by the
    /// references' coverage (premultiplied alpha). With 4 samples each
    /// ([`Antialiasing::Msaa4`]), the depth-tested warp ([`WarpMode::DepthTested`]) writes a
    /// sample mask from the references' coverage (`warp.wgsl`, `coverage_mask`), so the
    /// warped silhouette is antialiased as a multisampled full render's is. The paper's
    /// shaders are the paper's, multisampled only at the proxy's edges.
    ///
    /// # Errors
    /// [`WarpError::InvalidSetting`] when `target.depth` has no depth aspect,
    /// `target.color` is not a renderable colour format, or the sample counts are not a
    /// pair the warp supports.
    pub fn new(
        device: &wgpu::Device,
        _queue: &wgpu::Queue,
        formats: TargetFormats,
        settings: &WarpPassSettings,
    ) -> Result<Self, WarpError> {
        let target = formats;
        let antialiasing =
            Antialiasing::from_samples(settings.antialiasing.sample_count(), target.samples)?;
        let (color_format, depth_format) = (target.color, target.depth);
        crate::msaa::check_formats(color_format, depth_format)?;
        let module = crate::shaders::WARP.module(device);
        use npr_gpu::layout::{
            FILTERABLE, sampler_entry, storage_entry, texture_entry, uniform_entry,
        };
        let texture = |binding, sample_type| {
            texture_entry(binding, wgpu::TextureViewDimension::D2, sample_type)
        };
        let depth = wgpu::TextureSampleType::Depth;
        let ref_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr-warp references"),
            entries: &[
                texture(0, FILTERABLE),
                texture(1, depth),
                texture(2, FILTERABLE),
                texture(3, depth),
                sampler_entry(4),
            ],
        });
        let object_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr-warp object"),
            entries: &[uniform_entry(0), storage_entry(1)],
        });
        let layout = render::pipeline_layout(device, "npr-warp", &[&ref_layout, &object_layout]);
        let buffers = crate::deform::vertex_layouts();
        let pipeline = |fs: &str,
                        topology: wgpu::PrimitiveTopology,
                        blend: Option<wgpu::BlendState>| {
            let targets = [Some(wgpu::ColorTargetState {
                blend,
                ..color_format.into()
            })];
            PipelineBuilder::new(fs, &layout, &module, "vs_warp", fs)
                .buffers(&buffers)
                .topology(topology)
                .cull(
                    (topology == wgpu::PrimitiveTopology::TriangleList).then_some(wgpu::Face::Back),
                )
                .depth(depth_format, true, wgpu::CompareFunction::LessEqual)
                .samples(target.samples)
                .targets(&targets)
                .build(device)
        };
        let tri = wgpu::PrimitiveTopology::TriangleList;
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("npr-warp reference sampler"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        // The depth-tested shaders: one-sample, sample-masked, or one-sample with the rim
        // blended over the background by the references' coverage (premultiplied alpha).
        let tested = |fs: [&'static str; 3]| match antialiasing {
            Antialiasing::None => pipeline(fs[0], tri, None),
            Antialiasing::Msaa4 => pipeline(fs[1], tri, None),
            Antialiasing::Msaa4Blend => pipeline(
                fs[2],
                tri,
                Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
            ),
        };
        Ok(Self {
            id: PassId::fresh(),
            device: device.clone(),
            single: [
                tested(["fs_single0", "fs_single0_msaa", "fs_single0_cover"]),
                tested(["fs_single1", "fs_single1_msaa", "fs_single1_cover"]),
            ],
            blend: tested(["fs_blend", "fs_blend_msaa", "fs_blend_cover"]),
            single_paper: [
                pipeline("fs_single0_paper", tri, None),
                pipeline("fs_single1_paper", tri, None),
            ],
            blend_paper: pipeline("fs_blend_paper", tri, None),
            single_coverage: [
                pipeline("fs_single0_coverage", tri, None),
                pipeline("fs_single1_coverage", tri, None),
            ],
            blend_coverage: pipeline("fs_blend_coverage", tri, None),
            fill: pipeline("fs_fill", tri, None),
            wire: pipeline("fs_fill", wgpu::PrimitiveTopology::LineList, None),
            ref_layout,
            object_layout,
            sampler,
            color_format,
            depth_format,
            antialiasing,
        })
    }

    /// The formats and sample count of the targets the pipelines draw into.
    pub fn target_formats(&self) -> TargetFormats {
        TargetFormats::new(self.color_format, self.depth_format)
            .with_samples(self.antialiasing.warp_sample_count())
    }

    /// The antialiasing the pipelines draw with.
    pub fn antialiasing(&self) -> Antialiasing {
        self.antialiasing
    }

    /// Binds two rendered references as the pair a warp interpolates between. Rebind after
    /// re-rendering either slot (the pair copies their poses).
    pub fn bind_pair(
        &self,
        device: &wgpu::Device,
        references: [&ReferenceFrame; 2],
    ) -> ReferencePair {
        let (d0, d1) = (
            &references[0].depth_sample_view,
            &references[1].depth_sample_view,
        );
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr-warp references"),
            layout: &self.ref_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&references[0].color_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(d0),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&references[1].color_view),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(d1),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::Sampler(&self.sampler),
                },
            ],
        });
        ReferencePair {
            bind_group,
            poses: [references[0].pose, references[1].pose],
            clip_from_world: [references[0].clip_from_world, references[1].clip_from_world],
            size: [references[0].width, references[0].height],
            proxy_poses: [references[0].snapshot(), references[1].snapshot()],
        }
    }

    /// Uploads a proxy binned with `bins_per_axis` (§3.3.2), inflated by
    /// `inflate_object` along its normals (see [`Proxy::inflated`]); with `wireframe`, also
    /// a line-list index buffer of its edges (for pictures: lavapipe lacks line polygon mode).
    ///
    /// # Errors
    /// As [`NormalBins::build`]; [`WarpError::Gpu`] when the upload fails.
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        proxy: &Proxy,
        bins_per_axis: u32,
        inflate_object: f32,
        wireframe: bool,
    ) -> Result<WarpObject, WarpError> {
        let mesh = proxy.inflated(inflate_object);
        let bins = NormalBins::build(&mesh, bins_per_axis)?;
        let gpu = GpuMesh::upload(device, &bins.sorted_mesh(&mesh))?;
        let edges = wireframe.then(|| {
            let lines = edge_lines(&bins.indices);
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("npr-warp wireframe"),
                contents: bytemuck::cast_slice(&lines),
                usage: wgpu::BufferUsages::INDEX,
            });
            (buffer, lines.len() as u32)
        });
        Ok(WarpObject {
            bins,
            mesh: gpu,
            edges,
            slots: Slots::new(self.id),
            inflation: inflate_object,
            poses: 0,
            id: crate::deform::fresh_object_id(),
        })
    }

    fn create_slot(&self, bins: usize) -> WarpSlot {
        let device = &self.device;
        let uniforms = render::uniform_buffer(
            device,
            "npr-warp object uniforms",
            std::mem::size_of::<WarpObjectUniforms>(),
        );
        let weights = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("npr-warp bin weights"),
            contents: bytemuck::cast_slice(&vec![[1.0f32, 0.0, 0.0, 0.0]; bins.max(1)]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("npr-warp object"),
            layout: &self.object_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: weights.as_entire_binding(),
                },
            ],
        });
        WarpSlot {
            uniforms,
            weights,
            bind_group,
            pair_group: None,
            proxy_poses: [None, None],
            poses: 0,
            plan: BinPlan::default(),
            mode: WarpMode::DepthTested,
        }
    }

    /// Decides the frame for `object` (§3.3.2–§3.3.3) and writes its uniforms and bin
    /// weights into a fresh slot: the object drawn at `input.now` (its own camera and
    /// pose) with the reference pair's images, `input.s ∈ [0, 1]` the frame's position
    /// between the two references. The plan is [`WarpObject::plan`].
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    ///
    /// # Errors
    /// [`WarpError::Pass`] for an object of another pass or too many prepares in one
    /// frame.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut WarpObject,
        input: &WarpInput<'_>,
    ) -> Result<Prepared, WarpError> {
        let WarpInput {
            pair,
            now,
            s,
            settings,
            ..
        } = *input;
        let plan = crate::bins::plan(
            &object.bins,
            now.eye_object(),
            [pair.poses[0].eye_object(), pair.poses[1].eye_object()],
            s,
            &settings.plan,
        );
        let u = warp_uniforms(pair, now, settings);
        let bins = object.bins.len();
        let (prepared, slot) = object
            .slots
            .next(self.id, input.frame, || self.create_slot(bins))?;
        queue.write_buffer(&slot.uniforms, 0, bytemuck::bytes_of(&u));
        queue.write_buffer(&slot.weights, 0, bytemuck::cast_slice(&plan.weights));
        slot.plan = plan;
        slot.mode = input.mode;
        slot.pair_group = Some(pair.bind_group.clone());
        slot.proxy_poses = pair.proxy_poses.clone();
        slot.poses = object.poses;
        Ok(prepared)
    }

    /// Records the draws of the plan `prepared` decided for `object` into the caller's
    /// pass (targets of the formats given to [`WarpPass::new`]).
    ///
    /// Example: `examples/embed.rs` (the README's embedding example) uses it in a caller's
    /// own renderer.
    ///
    /// # Errors
    /// [`WarpError::Pass`] for a `prepared` of another object, pass or frame.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        object: &WarpObject,
        prepared: &Prepared,
    ) -> Result<(), WarpError> {
        let slot = object.slots.get(self.id, prepared)?;
        crate::deform::check_pose(object, slot.poses)?;
        let Some(pair_group) = &slot.pair_group else {
            return Ok(());
        };
        let (plan, mode) = (&slot.plan, slot.mode);
        pass.set_bind_group(0, pair_group, &[]);
        pass.set_bind_group(1, &slot.bind_group, &[]);
        crate::deform::bind_vertices(pass, object, &slot.proxy_poses);
        pass.set_index_buffer(
            object.mesh.index_buffer.slice(..),
            wgpu::IndexFormat::Uint32,
        );
        // Group draws by pipeline so each pipeline is set once.
        for kind in [DrawKind::Single0, DrawKind::Single1, DrawKind::Blend] {
            let mut set = false;
            for d in plan.draws.iter().filter(|d| d.kind == kind) {
                if !set {
                    pass.set_pipeline(self.pipeline(mode, kind));
                    set = true;
                }
                pass.draw_indexed(d.indices.clone(), 0, d.instance..d.instance + 1);
            }
        }
        Ok(())
    }

    fn pipeline(&self, mode: WarpMode, kind: DrawKind) -> &wgpu::RenderPipeline {
        match (mode, kind) {
            (WarpMode::Fill, _) => &self.fill,
            (WarpMode::DepthTested, DrawKind::Single0) => &self.single[0],
            (WarpMode::DepthTested, DrawKind::Single1) => &self.single[1],
            (WarpMode::DepthTested, DrawKind::Blend) => &self.blend,
            (WarpMode::Paper, DrawKind::Single0) => &self.single_paper[0],
            (WarpMode::Paper, DrawKind::Single1) => &self.single_paper[1],
            (WarpMode::Paper, DrawKind::Blend) => &self.blend_paper,
            (WarpMode::PaperCoverage, DrawKind::Single0) => &self.single_coverage[0],
            (WarpMode::PaperCoverage, DrawKind::Single1) => &self.single_coverage[1],
            (WarpMode::PaperCoverage, DrawKind::Blend) => &self.blend_coverage,
        }
    }

    /// Records the proxy's wireframe (line list, [`WarpSettings::fill_color`]) at the pose
    /// `prepared` wrote; nothing when the object has no wireframe.
    ///
    /// # Errors
    /// [`WarpError::Pass`] for a `prepared` of another object, pass or frame.
    pub fn draw_wireframe(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        object: &WarpObject,
        prepared: &Prepared,
    ) -> Result<(), WarpError> {
        let slot = object.slots.get(self.id, prepared)?;
        crate::deform::check_pose(object, slot.poses)?;
        let (Some((edges, count)), Some(pair_group)) = (&object.edges, &slot.pair_group) else {
            return Ok(());
        };
        pass.set_pipeline(&self.wire);
        pass.set_bind_group(0, pair_group, &[]);
        pass.set_bind_group(1, &slot.bind_group, &[]);
        crate::deform::bind_vertices(pass, object, &slot.proxy_poses);
        pass.set_index_buffer(edges.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..*count, 0, 0..1);
        Ok(())
    }
}

npr_gpu::impl_pass!(WarpPass, WarpObject, WarpInput, WarpError);

/// The `WarpObject` uniforms of `now` warped from `pair`.
fn warp_uniforms(
    pair: &ReferencePair,
    now: &ObjectView,
    settings: &WarpSettings,
) -> WarpObjectUniforms {
    let tex = |i: usize| {
        (projective::tex_from_world(pair.clip_from_world[i]) * pair.poses[i].world_from_object)
            .to_cols_array_2d()
    };
    let cam = |i: usize| &pair.poses[i].camera;
    WarpObjectUniforms {
        clip_from_object: (now.camera.clip_from_world() * now.world_from_object).to_cols_array_2d(),
        tex_from_object0: tex(0),
        tex_from_object1: tex(1),
        ref_near_far: [cam(0).near, cam(0).far, cam(1).near, cam(1).far],
        params: [
            settings.depth_tolerance_world,
            pair.size[0] as f32,
            pair.size[1] as f32,
            settings.surface_slack_world,
        ],
        eye0_object: pair.poses[0]
            .eye_object()
            .extend(texel_angle(cam(0), pair.size[1]))
            .to_array(),
        eye1_object: pair.poses[1]
            .eye_object()
            .extend(texel_angle(cam(1), pair.size[1]))
            .to_array(),
        fill_color: Vec4::from_array(settings.fill_color).to_array(),
    }
}

/// The angle one texel of a `height`-texel image subtends under `camera`:
/// `2 tan(fov_y / 2) / height` (times a view distance, a texel's size there).
pub fn texel_angle(camera: &npr_gpu::Camera, height: u32) -> f32 {
    2.0 * (camera.fov_y_rad * 0.5).tan() / height.max(1) as f32
}

/// Each undirected edge of a triangle list once, as a line list.
pub fn edge_lines(indices: &[u32]) -> Vec<u32> {
    let mut edges: Vec<(u32, u32)> = indices
        .chunks_exact(3)
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges.into_iter().flat_map(|(a, b)| [a, b]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_block_matches_wgsl_layout() {
        npr_gpu::assert_wgsl_layout!(
            crate::shaders::ALL,
            WarpObjectUniforms,
            "WarpObject",
            [
                clip_from_object,
                tex_from_object0,
                tex_from_object1,
                ref_near_far,
                params,
                eye0_object,
                eye1_object,
                fill_color
            ]
        );
    }

    #[test]
    fn reference_sees_like_a_shadow_map() {
        let uv = glam::Vec2::splat(0.5);
        let (near, far) = (1.0, 10.0);
        // Stored depth of a surface at distance 4.
        let d = far * (4.0 - near) / ((far - near) * 4.0);
        assert!((distance_of_depth(d, near, far) - 4.0).abs() < 1e-5);
        assert!(reference_sees(3.96, uv, d, near, far, 0.05));
        assert!(reference_sees(4.04, uv, d, near, far, 0.05));
        assert!(!reference_sees(4.2, uv, d, near, far, 0.05), "hidden");
        assert!(
            !reference_sees(3.0, uv, d, near, far, 0.05),
            "in front: empty space"
        );
        assert!(reference_empty(3.0, uv, d, near, far, 0.05));
        assert!(!reference_empty(4.2, uv, d, near, far, 0.05));
        assert!(!reference_sees(3.0, uv, 1.0, near, far, 0.05), "background");
        assert!(reference_empty(3.0, uv, 1.0, near, far, 0.05));
        assert!(!reference_sees(
            3.0,
            glam::Vec2::new(1.2, 0.5),
            d,
            near,
            far,
            0.05
        ));
    }

    #[test]
    fn edges_are_unique() {
        let lines = edge_lines(&[0, 1, 2, 2, 1, 3]);
        assert_eq!(lines.len(), 10);
    }
}
