//! What the specular paper's figure examples share: the subjects, the tile renderer
//! (restricted to the §4.2 receivers, or not, for Fig. 5(a)) and the projector styles.
// Each example uses part of this module.
#![allow(dead_code)]

use glam::{Mat4, Vec3};
use npr_geometry::{CurvatureOptions, CurvatureRadius, LightEye, Mesh, generate};
use npr_gpu::figures::{fixture_mesh, framing_camera};
use npr_gpu::{
    BaseShading, FrameUniforms, GpuContext, GpuMesh, Light, ObjectUniforms, OffscreenTarget,
    ShadingModel, TargetFormats, readback_rgba,
};
use npr_specular::snapshot::{HighlightScene, Renderer};
use npr_specular::{
    HighlightFrame, HighlightInput, HighlightPass, HighlightSet, HighlightShape, ProjectorControls,
};

/// An example's error.
pub type Error = Box<dyn std::error::Error>;

/// Side of a figure tile in pixels.
pub const TILE: u32 = 360;

/// A mesh with its highlights, framed.
pub struct Subject {
    pub name: String,
    pub mesh: Mesh,
    pub gpu: GpuMesh,
    pub set: HighlightSet,
    pub world_from_normalized: Mat4,
}

/// `smoothing`: curvature ball radius in mean edge lengths (scanned meshes carry bumps
/// that a larger ball smooths into fewer, calmer highlights).
pub fn subject(ctx: &GpuContext, name: &str, mesh: Mesh, smoothing: f32) -> Result<Subject, Error> {
    let gpu = GpuMesh::upload(&ctx.device, &mesh)?;
    let options = CurvatureOptions {
        radius: CurvatureRadius::EdgeLengths(smoothing),
        ..CurvatureOptions::default()
    };
    let set = HighlightSet::new(&mesh, &options)?;
    let (_, world_from_normalized) = framing_camera(&mesh, 1.0);
    Ok(Subject {
        name: name.to_string(),
        mesh,
        gpu,
        set,
        world_from_normalized,
    })
}

/// The subjects named `names` of the figures: the knot and the ellipsoid (procedural),
/// spot and the Stanford bunny (`fixtures/meshes/`).
pub fn subjects(ctx: &GpuContext, names: &[&str]) -> Result<Vec<Subject>, Error> {
    let mut out = Vec::new();
    for &name in names {
        let mesh = match name {
            "knot" => generate::paper_knot(),
            "ellipsoid" => generate::ellipsoid(1.2, 0.8, 0.6, 24),
            _ => {
                let file = fixture_mesh(&format!("{name}.obj"));
                npr_geometry::load_obj(&file)
                    .map_err(|e| format!("loading {}: {e}", file.display()))?
            }
        };
        out.push(subject(ctx, name, mesh, 3.0)?);
    }
    Ok(out)
}

/// Every subject of the figures, in the gallery's order.
pub const ALL_SUBJECTS: [&str; 4] = ["knot", "ellipsoid", "spot", "stanford-bunny"];

/// The star texture, narrowed (σ = 0.92).
pub fn star() -> ProjectorControls {
    ProjectorControls {
        texture_layer: HighlightShape::Star.layer(),
        sigma: 0.92,
        ..Default::default()
    }
}

/// The disc texture.
pub fn disc() -> ProjectorControls {
    ProjectorControls {
        texture_layer: HighlightShape::Disc.layer(),
        ..Default::default()
    }
}

/// The normal-map texture, shininess 8.
pub fn normal_map() -> ProjectorControls {
    ProjectorControls {
        texture_layer: HighlightShape::NormalMap.layer(),
        shininess: 8.0,
        ..Default::default()
    }
}

/// The turn of the subjects in Fig. 2, 4, 5, 6, 7.
pub fn spin() -> Mat4 {
    Mat4::from_rotation_y(0.4)
}

/// Draws highlights on every face (no §4.2 restriction): the wrong projection of the
/// paper's Fig. 5(a), through [`HighlightPass::draw_list_unrestricted`].
pub struct Unrestricted {
    base: BaseShading,
    pass: HighlightPass,
    target: OffscreenTarget,
}

impl Unrestricted {
    pub fn new(ctx: &GpuContext) -> Result<Self, Error> {
        let (d, q) = (&ctx.device, &ctx.queue);
        Ok(Self {
            base: BaseShading::new(d, q, TargetFormats::default(), &Default::default()),
            pass: HighlightPass::new(d, q, TargetFormats::default(), &Default::default())?,
            target: OffscreenTarget::new(d, TILE, TILE)?,
        })
    }

    fn render(
        &self,
        ctx: &GpuContext,
        scene: &HighlightScene<'_>,
    ) -> Result<image::RgbaImage, Error> {
        let (d, q) = (&ctx.device, &ctx.queue);
        let view = FrameUniforms::new(&scene.camera, &scene.light);
        let frame = npr_gpu::FrameId::default();
        let mut object = self.base.create_object(d, scene.mesh);
        let base_input = npr_gpu::BaseInput {
            frame,
            view: &view,
            object: &scene.object,
            model: scene.base,
        };
        let base = self.base.prepare(q, &mut object, &base_input)?;
        let mut draw = self.pass.create_object(d, scene.mesh);
        let list = HighlightPass::draw_list_unrestricted(scene.set, scene.indices);
        let highlights = HighlightFrame::with_list(frame, scene.set, &list);
        let input = HighlightInput {
            frame,
            highlights: &highlights,
            view: &view,
            object: &scene.object,
        };
        let highlights = self.pass.prepare(q, &mut draw, &input)?;
        let mut enc = d.create_command_encoder(&Default::default());
        {
            let mut rpass = self.target.begin_clear_pass(&mut enc, scene.clear);
            self.base.draw(&mut rpass, &object, &base)?;
            self.pass.draw(&mut rpass, &draw, &highlights)?;
        }
        q.submit(Some(enc.finish()));
        Ok(readback_rgba(d, q, &self.target.color)?)
    }
}

/// How a tile's highlights are drawn.
#[derive(Clone, Copy)]
pub enum Draw<'a> {
    /// The set's §4.2 receivers, through the snapshot renderer.
    Restricted(&'a Renderer),
    /// Every face a receiver (Fig. 5(a)).
    Unrestricted(&'a Unrestricted),
}

/// One tile: base `model` of `s` turned by `spin` (+ highlights with `controls` when
/// given; + Phong's own highlight with `phong_specular`).
pub fn tile(
    ctx: &GpuContext,
    draw: Draw<'_>,
    s: &mut Subject,
    (spin, model): (Mat4, ShadingModel),
    controls: Option<ProjectorControls>,
    phong_specular: bool,
) -> Result<image::RgbaImage, Error> {
    let (camera, _) = framing_camera(&s.mesh, 1.0);
    let to_light = Vec3::new(0.4, 0.7, 1.0).normalize();
    let light = Light::directional(to_light);
    let world_from_object = spin * s.world_from_normalized;
    if let Some(c) = controls {
        s.set.tuning.controls = c;
    }
    let le = LightEye::Positions {
        light: to_light * 50.0,
        eye: camera.eye,
    };
    s.set.update(le, world_from_object);
    let k_s = if phong_specular { 0.8 } else { 0.0 };
    let object = ObjectUniforms::new(
        world_from_object,
        Vec3::new(0.8, 0.35, 0.25),
        k_s,
        Vec3::ONE,
        60.0,
    );
    let scene = HighlightScene {
        mesh: &s.gpu,
        indices: &s.mesh.indices,
        set: &s.set,
        object,
        camera,
        light,
        base: model,
        highlights: controls.is_some(),
        clear: [1.0, 1.0, 1.0, 1.0],
    };
    match draw {
        Draw::Restricted(renderer) => Ok(renderer.render(&ctx.device, &ctx.queue, &scene)?),
        Draw::Unrestricted(u) => u.render(ctx, &scene),
    }
}

/// A Phong tile of `s` (turned by [`spin`]) with stylized highlights `c` only (no Phong
/// highlight of its own).
pub fn phong(
    ctx: &GpuContext,
    renderer: &Renderer,
    s: &mut Subject,
    c: ProjectorControls,
) -> Result<image::RgbaImage, Error> {
    let how = (spin(), ShadingModel::Phong);
    tile(ctx, Draw::Restricted(renderer), s, how, Some(c), false)
}

/// The GPU and the tile renderer every figure uses.
pub fn setup() -> Result<(GpuContext, Renderer), Error> {
    let ctx = GpuContext::new()?;
    let renderer = Renderer::new(&ctx.device, &ctx.queue, TILE, TILE)?;
    Ok((ctx, renderer))
}
