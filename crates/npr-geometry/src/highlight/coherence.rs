//! Frame coherence of the search (beyond the paper): a key frame keeps a motion budget
//! and a watch list of the vertices that can pass their test meanwhile, so that later
//! frames within the budget test only those and find the same centres.

use glam::{Mat4, Vec3};

use super::search::{FrameKind, FrameSetup, SIMILARITY_COND, VertexScratch, turn_bound};
use super::{HighlightCentre, HighlightSearch, LightEye, NormalInterpolation};
impl HighlightSearch {
    /// Which of `vertices` still pass their per-vertex test after the light and eye move
    /// by up to `budget` (object space; similarity transforms or directions only): the
    /// watch list of a [`SearchCoherence`] key frame. With `angle(N, H) ≤ acos(C_v)` the
    /// test, the motion turns `H` by at most `φ_v = asin(τ/|S|)` (`τ` the turns of `L̂`
    /// and `V̂`) and can raise the allowance to `C_v'` computed from the distances less the
    /// budgets and `|S| − τ`; a vertex is watched when `angle(N, H) ≤ acos(C_v') + φ_v`.
    pub(super) fn watch_list(
        &self,
        frame: &FrameSetup,
        vertices: &[u32],
        budget: Budget,
    ) -> Vec<u32> {
        let half_pi = std::f32::consts::FRAC_PI_2;
        let watched = |v: usize| -> bool {
            let n = self.normals[v];
            // angle(N, H) ≤ acos(c) + φ (+ margin), without trigonometry: with
            // cos φ and sin φ, compare cosines while the sum stays below π.
            let within = |h: Vec3, c: f32, sin_phi: f32| {
                let c = c.clamp(-1.0, 1.0);
                let (cos_m, sin_m) = (WATCH_MARGIN.cos(), WATCH_MARGIN.sin());
                let sin_phi = sin_phi.clamp(0.0, 1.0);
                let cos_phi = (1.0 - sin_phi * sin_phi).sqrt();
                // cos and sin of acos(c) + φ, then + margin.
                let s_c = (1.0 - c * c).max(0.0).sqrt();
                let (c1, s1) = (c * cos_phi - s_c * sin_phi, s_c * cos_phi + c * sin_phi);
                let (c2, s2) = (c1 * cos_m - s1 * sin_m, s1 * cos_m + c1 * sin_m);
                // The sum (at most 3π/2) passed π when its sine is negative.
                let past_pi = s1 < 0.0 || s2 < 0.0;
                past_pi || n.dot(h) >= c2
            };
            match frame.kind {
                FrameKind::Direction(h) => {
                    budget.angle >= half_pi
                        || within(
                            h,
                            self.cos_spread[v] - self.margin(frame, v),
                            budget.angle.sin(),
                        )
                }
                FrameKind::Positions { light_o, eye_o, .. } => {
                    let p = self.positions[v];
                    let (l, e) = (light_o - p, eye_o - p);
                    let (ll, le) = (l.length(), e.length());
                    let s = l / ll + e / le;
                    let sl = s.length();
                    let Some(tau) = budget.direction_turn(ll, le) else {
                        return true;
                    };
                    if !(sl > tau + 1e-6) || !s.is_finite() {
                        return true;
                    }
                    let r = self.reach[v];
                    let turn = |d: f32| turn_bound(r, d);
                    let t = turn(ll - budget.light) + turn(le - budget.eye);
                    let b = (t / (sl - tau - t).max(1e-3) * SIMILARITY_COND).min(4.0);
                    within(
                        s / sl,
                        self.cos_spread[v] - b - self.margin(frame, v),
                        tau / sl,
                    )
                }
            }
        };
        vertices
            .iter()
            .copied()
            .filter(|&v| watched(v as usize))
            .collect()
    }

    /// [`HighlightSearch::find`] with frame coherence: the same centres, at
    /// the same positions, as `find` for every input, found cheaper when the light, eye
    /// and object move a little from frame to frame. See [`SearchCoherence`].
    pub fn find_coherent(
        &self,
        state: &mut SearchCoherence,
        light_eye: LightEye,
        world_from_object: Mat4,
    ) -> Vec<HighlightCentre> {
        let input = (light_eye, world_from_object, self.interpolation);
        if state.last_input == Some(input) && state.mesh == self.id {
            state.stats = CoherenceStats {
                reused: true,
                ..CoherenceStats::default()
            };
            return state.last_centres.clone();
        }
        let Some(frame) = self.setup(light_eye, world_from_object) else {
            state.forget();
            state.stats = CoherenceStats::default();
            return Vec::new();
        };
        let pose = Viewpoint::of(&frame);
        let (previous, kept) = (state.pose.take(), state.key.take());
        let mut full = false;
        let key = match kept {
            Some(k) if state.mesh == self.id && k.covers(&pose, self.interpolation) => k,
            _ => {
                full = true;
                let budget = pose.budget(previous.as_ref(), state.frames_ahead, self.extent());
                let watch = match budget {
                    Some(b) if frame.clusters_apply() => {
                        let active = self.active_vertices(&frame, b);
                        self.watch_list(&frame, &active, b)
                    }
                    _ => (0..self.positions.len() as u32).collect(),
                };
                KeyFrame {
                    pose,
                    budget: budget.unwrap_or(Budget::NONE),
                    interpolation: self.interpolation,
                    watch,
                    valid: budget.is_some() && frame.clusters_apply(),
                }
            }
        };
        state.mesh = self.id;
        let centres = self.search_vertices(&frame, &key.watch, true, &mut state.scratch);
        state.stats = CoherenceStats {
            full,
            reused: false,
            tested: key.watch.len(),
        };
        state.key = Some(key);
        state.pose = Some(pose);
        state.last_input = Some(input);
        state.last_centres.clone_from(&centres);
        centres
    }
}

/// Float slack of the watch-list tests (radians).
const WATCH_MARGIN: f32 = 1e-3;

/// How far the light and eye may move (object space) while a watch list stays valid:
/// `angle` for the half vector of directions, `light` and `eye` distances for positions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Budget {
    pub(super) angle: f32,
    pub(super) light: f32,
    pub(super) eye: f32,
}

impl Budget {
    pub(super) const NONE: Self = Self {
        angle: 0.0,
        light: 0.0,
        eye: 0.0,
    };

    /// Bound on the turn of `L̂` plus that of `V̂` at points at least `dl` from the light
    /// and `de` from the eye when they move by the budget (`asin(a/d) ≤ a/(d − a)`);
    /// `None` when either could pass that close.
    pub(super) fn direction_turn(&self, dl: f32, de: f32) -> Option<f32> {
        let one = |budget: f32, d: f32| {
            if budget <= 0.0 {
                Some(0.0)
            } else if d > 2.0 * budget {
                Some(budget / (d - budget))
            } else {
                None
            }
        };
        Some(one(self.light, dl)? + one(self.eye, de)?)
    }
}

/// Light and eye of one frame as the search sees them (object space).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Viewpoint {
    Direction(Vec3),
    Positions {
        light: Vec3,
        eye: Vec3,
    },
    /// Positions under a non-similar map: no coherence.
    Other,
}

impl Viewpoint {
    fn of(frame: &FrameSetup) -> Self {
        match frame.kind {
            FrameKind::Direction(h) => Viewpoint::Direction(h),
            FrameKind::Positions { light_o, eye_o, .. } if frame.similarity => {
                Viewpoint::Positions {
                    light: light_o,
                    eye: eye_o,
                }
            }
            FrameKind::Positions { .. } => Viewpoint::Other,
        }
    }

    /// The budget of a new key frame: `frames_ahead` times the step from the previous
    /// pose (at least a small floor, so that a still scene keeps its key), `None` where
    /// no watch list can be kept.
    fn budget(
        &self,
        previous: Option<&Viewpoint>,
        frames_ahead: f32,
        extent: f32,
    ) -> Option<Budget> {
        let k = if frames_ahead.is_finite() {
            frames_ahead.max(0.0)
        } else {
            0.0
        };
        match (self, previous) {
            (Viewpoint::Other, _) => None,
            (Viewpoint::Direction(h), previous) => {
                let step = match previous {
                    Some(Viewpoint::Direction(p)) => angle(*h, *p),
                    _ => 0.0,
                };
                let angle = (k * step).max(1e-4);
                angle.is_finite().then_some(Budget {
                    angle,
                    ..Budget::NONE
                })
            }
            (Viewpoint::Positions { light, eye }, previous) => {
                let (sl, se) = match previous {
                    Some(Viewpoint::Positions { light: pl, eye: pe }) => {
                        (light.distance(*pl), eye.distance(*pe))
                    }
                    _ => (0.0, 0.0),
                };
                let floor = 1e-4 * extent.max(f32::MIN_POSITIVE);
                let b = Budget {
                    angle: 0.0,
                    light: (k * sl).max(floor),
                    eye: (k * se).max(floor),
                };
                (b.light.is_finite() && b.eye.is_finite()).then_some(b)
            }
        }
    }
}

/// A key frame of [`SearchCoherence`]: where the light and eye were, how far they may
/// move, and the vertices that can pass their test meanwhile.
#[derive(Clone, Debug)]
struct KeyFrame {
    pose: Viewpoint,
    budget: Budget,
    interpolation: NormalInterpolation,
    watch: Vec<u32>,
    valid: bool,
}

impl KeyFrame {
    /// Whether the watch list still holds every vertex that can pass at `pose`.
    fn covers(&self, pose: &Viewpoint, interpolation: NormalInterpolation) -> bool {
        if !self.valid || interpolation != self.interpolation {
            return false;
        }
        match (self.pose, pose) {
            (Viewpoint::Direction(k), Viewpoint::Direction(h)) => angle(*h, k) <= self.budget.angle,
            (Viewpoint::Positions { light: kl, eye: ke }, Viewpoint::Positions { light, eye }) => {
                light.distance(kl) <= self.budget.light && eye.distance(ke) <= self.budget.eye
            }
            _ => false,
        }
    }
}

/// What the last [`HighlightSearch::find_coherent`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CoherenceStats {
    /// It built a new key frame (a full search: the cluster rejection over the mesh).
    pub full: bool,
    /// The input was the last call's: its centres were returned as they were.
    pub reused: bool,
    /// Vertices tested one by one.
    pub tested: usize,
}

/// Frame-to-frame state of [`HighlightSearch::find_coherent`] (beyond the paper; issue
/// 13). A key frame runs the cluster rejection with a motion budget (how far the light
/// and eye may move in object space: [`SearchCoherence::frames_ahead`] times the last
/// step) and keeps a watch list: every vertex that can pass its per-vertex test while the
/// light and eye stay within that budget (the bounds are in the private `watch_list`
/// and `active_vertices`). Later frames within the budget test only the watch list, and
/// since every other vertex provably fails its test, they solve exactly the faces the
/// full search solves: the same centres at the same positions. Beyond the budget, a
/// change of normal field or a non-similar map with point light and eye, the search
/// is full again. An unchanged input returns the last centres.
#[derive(Clone, Debug)]
pub struct SearchCoherence {
    /// How many frames of the last step's motion a key frame's budget covers (default
    /// 3): larger budgets rebuild less often but watch more vertices.
    pub frames_ahead: f32,
    key: Option<KeyFrame>,
    pose: Option<Viewpoint>,
    /// [`HighlightSearch`]'s id the state belongs to (0: none).
    mesh: u64,
    last_input: Option<(LightEye, Mat4, NormalInterpolation)>,
    last_centres: Vec<HighlightCentre>,
    scratch: VertexScratch,
    stats: CoherenceStats,
}

impl Default for SearchCoherence {
    fn default() -> Self {
        Self {
            frames_ahead: 3.0,
            key: None,
            pose: None,
            mesh: 0,
            last_input: None,
            last_centres: Vec::new(),
            scratch: VertexScratch::default(),
            stats: CoherenceStats::default(),
        }
    }
}

impl SearchCoherence {
    /// What the last search did.
    pub fn stats(&self) -> CoherenceStats {
        self.stats
    }

    /// Forgets the key frame and the last input (the next search is full).
    pub fn forget(&mut self) {
        self.key = None;
        self.pose = None;
        self.last_input = None;
        self.last_centres.clear();
    }
}

/// The angle between two vectors, accurate near zero (`atan2(|a×b|, a·b)`; an `acos` of
/// an f32 dot is off by up to ~3e-4 rad there, which the watch budgets would have to
/// absorb).
fn angle(a: Vec3, b: Vec3) -> f32 {
    a.cross(b).length().atan2(a.dot(b))
}
