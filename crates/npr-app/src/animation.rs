//! Playing a model's glTF clips: which clip `--animation` names, the moment each frame
//! shows, the model posed at that moment (on the CPU: morphs, then linear blend skinning,
//! `npr_geometry::animation`), and `npr pose`, which writes a posed mesh for other tools.
//!
//! Every effect then runs on the posed mesh as on any model: curvature, highlights,
//! stroke directions and outlines are computed on the posed surface.

use crate::AppError;
use crate::model::Model;
use crate::view::Framing;
use npr_geometry::animation::{Clip, Rig};
#[cfg(not(target_arch = "wasm32"))]
use std::path::PathBuf;

/// Poses sampled for the framing of a clip (its bounds over the whole clip).
const FRAMING_SAMPLES: usize = 32;

/// What `--animation` asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ClipChoice {
    /// The default: the model's first clip, or its bind pose when it has none.
    First,
    /// `none`: the bind pose.
    None,
    /// A clip by its index in the file.
    Index(usize),
    /// A clip by its name.
    Name(String),
}

impl ClipChoice {
    /// `--animation`'s value: absent (or empty, as a preset's `clip = ""`), `none`, an
    /// index or a name.
    pub fn parse(value: Option<&str>) -> Self {
        match value {
            None | Some("") => Self::First,
            Some("none") => Self::None,
            Some(v) => v
                .parse::<usize>()
                .map_or_else(|_| Self::Name(v.to_string()), Self::Index),
        }
    }
}

/// The moments of a clip the frames show: `--time`, `--fps` and `--no-loop`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Playback {
    /// The moment of the first frame, seconds.
    pub time: f32,
    /// Frames per second.
    pub fps: f32,
    /// Clip seconds per second of frames.
    pub speed: f32,
    /// Whether the clip wraps past its end (else it holds its last pose).
    pub looped: bool,
}

impl Default for Playback {
    fn default() -> Self {
        Self {
            time: 0.0,
            fps: 30.0,
            speed: 1.0,
            looped: true,
        }
    }
}

impl Playback {
    /// Checks the values.
    ///
    /// # Errors
    /// [`AppError::Usage`] for a time that is not finite or a rate not above 0.
    pub fn validate(&self) -> Result<(), AppError> {
        if !self.time.is_finite() {
            return Err(AppError::Usage(format!(
                "--time {}: a time in seconds",
                self.time
            )));
        }
        if !self.speed.is_finite() {
            return Err(AppError::Usage(format!(
                "animation speed {}: a finite number",
                self.speed
            )));
        }
        if !(self.fps.is_finite() && self.fps > 0.0) {
            return Err(AppError::Usage(format!(
                "--fps {}: a rate above 0",
                self.fps
            )));
        }
        Ok(())
    }

    /// The clip time of frame `i`: `time + speed · i / fps`, wrapped into the clip (a glTF clip
    /// runs from 0 to its last key, [`Clip::duration`]) or held at its ends.
    pub fn at(&self, clip: &Clip, i: usize) -> f32 {
        let t = self.time + self.speed * i as f32 / self.fps;
        let duration = clip.duration();
        if duration.is_nan() || duration <= 0.0 {
            return 0.0;
        }
        if self.looped {
            t.rem_euclid(duration)
        } else {
            t.clamp(0.0, duration)
        }
    }
}

/// The clip `choice` names in `model`: `None` for the bind pose (or a model without
/// clips and no choice).
///
/// # Errors
/// [`AppError::Usage`] with one line naming the model's clips when it has no such clip.
pub fn resolve_clip(model: &Model, choice: &ClipChoice) -> Result<Option<usize>, AppError> {
    let clips: &[Clip] = model.rig.as_ref().map_or(&[], Rig::clips);
    let names = || {
        if clips.is_empty() {
            "it has no clips".to_string()
        } else {
            let list: Vec<String> = clips
                .iter()
                .enumerate()
                .map(|(i, c)| c.name().map_or_else(|| i.to_string(), str::to_string))
                .collect();
            format!("its clips: {}", list.join(", "))
        }
    };
    match choice {
        ClipChoice::First => Ok((!clips.is_empty()).then_some(0)),
        ClipChoice::None => Ok(None),
        ClipChoice::Index(i) if *i < clips.len() => Ok(Some(*i)),
        ClipChoice::Index(i) => Err(AppError::Usage(format!(
            "{} has no clip {i}; {}",
            model.name,
            names()
        ))),
        ClipChoice::Name(n) => clips
            .iter()
            .position(|c| c.name() == Some(n.as_str()))
            .map(Some)
            .ok_or_else(|| {
                AppError::Usage(format!("{} has no clip \"{n}\"; {}", model.name, names()))
            }),
    }
}

/// One pose of a rigged model as the GPU poses it ([`Animated::gpu_pose_at`]).
#[derive(Clone, Debug)]
pub struct GpuPose<'a> {
    /// The rig.
    pub rig: &'a npr_geometry::animation::Rig,
    /// Its pose at the frame's time.
    pub pose: npr_geometry::animation::Pose,
    /// Where rig vertex `v` sits in the model's (and the uploaded mesh's) vertex order.
    pub order: &'a [u32],
}

/// A model with its clip chosen: poses it frame by frame, framed over the whole clip so
/// that the camera holds still while it plays.
#[derive(Clone, Debug)]
pub struct Animated {
    model: Model,
    clip: Option<usize>,
    playback: Playback,
    framing: Framing,
    /// For a rigged model: where each of the rig's vertices goes in the model's vertex
    /// order, and the model's triangles ([`Model::from_mesh`]'s reordering, which depends
    /// on the triangles alone, so it is computed once for every pose); and each vertex's
    /// bind-pose matrix, inverted, for [`Animated::carried_directions`].
    layout: Option<Layout>,
}

#[derive(Clone, Debug)]
struct Layout {
    vertex_to_output: Vec<u32>,
    vertices: usize,
    indices: Vec<u32>,
    bind_inverse: Vec<glam::Mat4>,
}

impl Animated {
    /// `model` playing `clip` ([`resolve_clip`]) as `playback` says.
    ///
    /// # Errors
    /// As [`Playback::validate`].
    pub fn new(model: Model, clip: Option<usize>, playback: Playback) -> Result<Self, AppError> {
        playback.validate()?;
        let framing = match (model.rig.as_ref(), clip) {
            (Some(rig), Some(c)) => {
                let (lo, hi) = rig.clip_bounds(&rig.clips()[c], FRAMING_SAMPLES);
                Framing::of_bounds(lo, hi)
            }
            (Some(rig), None) => Framing::of(&rig.pose_mesh(&rig.bind_pose())),
            _ => model.framing,
        };
        let layout = model.rig.as_ref().map(|rig| {
            let bind = rig.bind_pose();
            let reordered = npr_geometry::locality::reorder_for_locality(&rig.pose_mesh(&bind));
            Layout {
                vertex_to_output: reordered.vertex_to_output,
                vertices: reordered.mesh.positions.len(),
                indices: reordered.mesh.indices,
                bind_inverse: rig
                    .vertex_transforms(&bind)
                    .iter()
                    .map(glam::Mat4::inverse)
                    .collect(),
            }
        });
        Ok(Self {
            model,
            clip,
            playback,
            framing,
            layout,
        })
    }

    /// Whether a clip plays (frames differ).
    pub fn plays(&self) -> bool {
        self.clip.is_some()
    }

    /// The framing over the whole clip.
    pub fn framing(&self) -> Framing {
        self.framing
    }

    /// The clip time of frame `i` (0 without a clip).
    pub fn time_of(&self, i: usize) -> f32 {
        match (self.model.rig.as_ref(), self.clip) {
            (Some(rig), Some(c)) => self.playback.at(&rig.clips()[c], i),
            _ => 0.0,
        }
    }

    /// The mesh of frame `i` as the file places it (no recentring): the clip's pose at
    /// [`Animated::time_of`], the bind pose without a clip, the loaded mesh for a model
    /// without a rig.
    pub fn posed_mesh(&self, i: usize) -> npr_geometry::Mesh {
        self.mesh_at(self.time_of(i))
    }

    /// The mesh at clip time `t` (wrapped or held as the playback says; see
    /// [`Animated::posed_mesh`]).
    pub fn mesh_at(&self, t: f32) -> npr_geometry::Mesh {
        match (self.model.rig.as_ref(), self.pose_at(t)) {
            (Some(rig), Some(pose)) => rig.pose_mesh(&pose),
            _ => self.model.mesh.clone(),
        }
    }

    /// The rig's pose at clip time `t` (wrapped or held as the playback says), the bind
    /// pose without a clip; `None` for a model without a rig.
    pub fn pose_at(&self, t: f32) -> Option<npr_geometry::animation::Pose> {
        let rig = self.model.rig.as_ref()?;
        Some(match self.clip {
            Some(c) => {
                let clip = &rig.clips()[c];
                let t = Playback {
                    time: t,
                    ..self.playback
                }
                .at(clip, 0);
                rig.sample(clip, t)
            }
            None => rig.bind_pose(),
        })
    }

    /// What [`crate::engine::Renderer::set_pose_on_gpu`] needs to pose frame time `t` on
    /// the GPU: the rig, its pose at `t` and where each rig vertex sits in the model's
    /// vertex order. `None` for a model without a rig.
    pub fn gpu_pose_at(&self, t: f32) -> Option<GpuPose<'_>> {
        let (rig, layout) = (self.model.rig.as_ref()?, self.layout.as_ref()?);
        let pose = self.pose_at(t)?;
        Some(GpuPose {
            rig,
            pose,
            order: &layout.vertex_to_output,
        })
    }

    /// The names of the model's clips (an index where a clip has none).
    pub fn clip_names(&self) -> Vec<String> {
        self.model.rig.as_ref().map_or_else(Vec::new, |r| {
            r.clips()
                .iter()
                .enumerate()
                .map(|(i, c)| c.name().map_or_else(|| i.to_string(), str::to_string))
                .collect()
        })
    }

    /// The clip playing (its index), if any.
    pub fn clip(&self) -> Option<usize> {
        self.clip
    }

    /// The length of the clip playing, seconds (0 without one).
    pub fn duration(&self) -> f32 {
        match (self.model.rig.as_ref(), self.clip) {
            (Some(rig), Some(c)) => rig.clips()[c].duration(),
            _ => 0.0,
        }
    }

    /// The stroke directions of `which` on the bind pose, per vertex of the rig's mesh
    /// (computed once; see [`Animated::carried_directions`]).
    pub fn rest_directions(&self, which: crate::preset::DirectionPreset) -> Vec<glam::Vec3> {
        match self.model.rig.as_ref() {
            Some(rig) => crate::engine::stroke_directions(&rig.pose_mesh(&rig.bind_pose()), which),
            None => crate::engine::stroke_directions(&self.model.mesh, which),
        }
    }

    /// `rest` ([`Animated::rest_directions`]) carried to clip time `t`, per vertex of
    /// `posed` (that is [`Animated::model_at`]`(t)`, whose normals it uses): each vertex's
    /// direction turned by its skinning matrix at `t` over its matrix at the bind pose,
    /// then laid into the posed tangent plane. Exact where a part moves rigidly; near a
    /// joint the blend of two matrices is an approximation of the posed surface's own
    /// field.
    pub fn carried_directions(
        &self,
        rest: &[glam::Vec3],
        t: f32,
        posed: &Model,
    ) -> Vec<glam::Vec3> {
        let (Some(rig), Some(layout), Some(pose)) = (
            self.model.rig.as_ref(),
            self.layout.as_ref(),
            self.pose_at(t),
        ) else {
            return rest.to_vec();
        };
        let mut out = vec![glam::Vec3::ZERO; posed.mesh.positions.len()];
        for (v, ((&d, b), m)) in rest
            .iter()
            .zip(&layout.bind_inverse)
            .zip(rig.vertex_transforms(&pose))
            .enumerate()
        {
            let Some(o) = layout.vertex_to_output.get(v).map(|&o| o as usize) else {
                continue;
            };
            if let (Some(slot), Some(&n)) = (out.get_mut(o), posed.mesh.normals.get(o)) {
                let d = m.transform_vector3(b.transform_vector3(d));
                *slot = (d - n * n.dot(d)).normalize_or_zero();
            }
        }
        out
    }

    /// Frame `i`'s model: the posed mesh, with the clip's framing.
    pub fn frame(&self, i: usize) -> Model {
        self.model_at(self.time_of(i))
    }

    /// The model at clip time `t`: the posed mesh, with the clip's framing.
    pub fn model_at(&self, t: f32) -> Model {
        let Some(layout) = &self.layout else {
            return self.model.clone();
        };
        // The pose in the model's vertex order (as Model::from_mesh would reorder it).
        let posed = self.mesh_at(t);
        let mut mesh = npr_geometry::Mesh {
            positions: vec![glam::Vec3::ZERO; layout.vertices],
            normals: vec![glam::Vec3::ZERO; layout.vertices],
            uvs: if posed.uvs.is_empty() {
                Vec::new()
            } else {
                vec![glam::Vec2::ZERO; layout.vertices]
            },
            indices: layout.indices.clone(),
        };
        for (v, &o) in layout.vertex_to_output.iter().enumerate() {
            let o = o as usize;
            if o < layout.vertices {
                mesh.positions[o] = posed.positions[v];
                mesh.normals[o] = posed.normals[v];
                if let (Some(dst), Some(&uv)) = (mesh.uvs.get_mut(o), posed.uvs.get(v)) {
                    *dst = uv;
                }
            }
        }
        let mut m = Model::in_order(&self.model.name, mesh);
        m.path.clone_from(&self.model.path);
        m.notes.clone_from(&self.model.notes);
        m.framing = self.framing;
        m
    }
}

/// Sets clip time `t`'s pose of `animated` into `renderer` as `preset.animation` says:
/// the vertices posed on the CPU and uploaded, or posed on the GPU
/// ([`crate::preset::Posing`]); the stroke directions carried from `rest` (the rest
/// pose's field of the preset's direction, [`Animated::rest_directions`]) when given,
/// else taken again on the pose.
///
/// # Errors
/// As [`crate::engine::Renderer::set_pose`] and
/// [`crate::engine::Renderer::set_pose_on_gpu`].
pub fn set_pose_at(
    renderer: &mut crate::engine::Renderer,
    (device, queue): (&wgpu::Device, &wgpu::Queue),
    animated: &Animated,
    t: f32,
    preset: &crate::preset::Preset,
    rest: Option<&[glam::Vec3]>,
) -> Result<(), AppError> {
    let model = animated.model_at(t);
    let which = preset.hatching.direction;
    let directions = rest.map(|r| (which, animated.carried_directions(r, t, &model)));
    let gpu = match preset.animation.posing {
        crate::preset::Posing::Gpu => animated.gpu_pose_at(t),
        crate::preset::Posing::Cpu => None,
    };
    match (gpu, directions) {
        (Some(g), directions) => renderer.set_pose_on_gpu(device, queue, model, &g, directions),
        (None, Some(d)) => renderer.set_pose_with_directions(queue, model, d),
        (None, None) => renderer.set_pose(queue, model),
    }
}

/// Arguments of `npr pose`.
#[cfg(not(target_arch = "wasm32"))]
#[derive(clap::Args, Debug, Clone)]
pub struct PoseArgs {
    /// The model: a glTF (.gltf/.glb) with skins, morph targets or animations (any
    /// model without is written as loaded).
    pub model: PathBuf,
    /// The clip: its name, its index, or `none` for the bind pose. Default: the first.
    #[arg(long, value_name = "NAME|INDEX|none")]
    pub animation: Option<String>,
    /// The moment, seconds into the clip (held at its ends).
    #[arg(long, default_value_t = 0.0)]
    pub time: f32,
    /// The posed mesh: OBJ or PLY (binary), in the file's units and scene space.
    #[arg(long)]
    pub out: PathBuf,
}

/// Runs `npr pose`: writes the model posed at one moment (native only: a command).
///
/// # Errors
/// A model that cannot be loaded, a clip it lacks, an output that is not `.obj` or
/// `.ply`, or the write failing (nothing is written then).
#[cfg(not(target_arch = "wasm32"))]
pub fn pose(args: &PoseArgs) -> Result<PathBuf, AppError> {
    let ext = args
        .out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let encode: fn(&npr_geometry::Mesh) -> Vec<u8> = match ext.as_deref() {
        Some("obj") => |m| npr_geometry::io::write::obj(m).into_bytes(),
        Some("ply") => |m| {
            npr_geometry::io::write::ply(
                m,
                npr_geometry::io::write::PlyEncoding::BinaryLittleEndian,
            )
        },
        _ => {
            return Err(AppError::Usage(format!(
                "--out {}: the posed mesh is written as .obj or .ply",
                args.out.display()
            )));
        }
    };
    let model = Model::load(&args.model)?;
    let clip = resolve_clip(&model, &ClipChoice::parse(args.animation.as_deref()))?;
    let playback = Playback {
        time: args.time,
        looped: false,
        ..Playback::default()
    };
    let animated = Animated::new(model, clip, playback)?;
    crate::output::write_atomic(&args.out, &encode(&animated.posed_mesh(0)))?;
    Ok(args.out.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn choices_parse() {
        assert_eq!(ClipChoice::parse(None), ClipChoice::First);
        assert_eq!(ClipChoice::parse(Some("none")), ClipChoice::None);
        assert_eq!(ClipChoice::parse(Some("2")), ClipChoice::Index(2));
        assert_eq!(
            ClipChoice::parse(Some("Walk")),
            ClipChoice::Name("Walk".into())
        );
    }

    #[test]
    fn playback_wraps_or_holds() {
        let sampler = npr_geometry::animation::Sampler::new(
            npr_geometry::animation::Interpolation::Linear,
            vec![1.0, 3.0],
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            3,
        )
        .unwrap();
        let clip = Clip::new(
            Some("c".into()),
            vec![npr_geometry::animation::Channel {
                node: 0,
                property: npr_geometry::animation::Property::Translation,
                sampler,
            }],
        );
        let p = Playback {
            time: 1.5,
            fps: 4.0,
            speed: 2.0,
            looped: true,
        };
        // The clip runs from 0 to its last key, 3 s: frames at 1.5, 2.0, 2.5, then 3.0 and
        // 3.5 wrap to 0.0 and 0.5.
        let times: Vec<f32> = (0..5).map(|i| p.at(&clip, i)).collect();
        assert_eq!(times, vec![1.5, 2.0, 2.5, 0.0, 0.5]);
        let held = Playback { looped: false, ..p };
        assert_eq!(held.at(&clip, 4), 3.0);
        assert_eq!(Playback { time: -1.0, ..held }.at(&clip, 0), 0.0);
        assert!(
            Playback {
                fps: 0.0,
                ..Playback::default()
            }
            .validate()
            .is_err()
        );
        assert!(
            Playback {
                time: f32::NAN,
                ..Playback::default()
            }
            .validate()
            .is_err()
        );
    }
}
