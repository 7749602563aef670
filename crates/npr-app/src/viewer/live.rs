//! Live warping (Park & Ihm) for the window and the browser page alike: reference frames
//! every k frames at the current pose and at the pose the camera is predicted to reach k
//! frames ahead, warped frames between them.

use super::state::{CameraPredictor, OrbitView, ViewerState};
use crate::AppError;
use crate::engine::{FrameStats, Renderer};
use crate::view::View;
// std's `Instant::now()` panics in the browser (wasm32-unknown-unknown has no clock).
#[cfg(not(target_arch = "wasm32"))]
use std::time::Instant;
#[cfg(target_arch = "wasm32")]
use web_time::Instant;

/// Live warping's state: references every k frames at the current pose and at the pose
/// predicted k frames ahead, warped frames between, and (native only) now and then a full
/// render to measure the last warped frame. Full frames (shown, and measured against) use
/// the warp's antialiasing, as references and warped frames do.
#[derive(Clone, Debug, Default)]
pub struct WarpLive {
    /// The camera's recent poses, for the reference k frames ahead.
    pub predictor: CameraPredictor,
    /// Frame of the last pair of references.
    pub last_reference: Option<u64>,
    /// Smoothed time of a full frame (references), ms (GPU waited for where the platform
    /// can wait: not in the browser, where it is the CPU's share).
    pub full_ms: f64,
    /// Smoothed time of a warped frame, ms (as [`WarpLive::full_ms`]).
    pub warped_ms: f64,
    /// PSNR of the last measured warped frame against a full render, dB (native only:
    /// the browser cannot read a frame back within the frame).
    pub psnr_db: Option<f64>,
}

/// An exponential moving average (the first sample starts it).
fn smooth(avg: f64, x: f64) -> f64 {
    if avg == 0.0 { x } else { 0.8 * avg + 0.2 * x }
}

impl WarpLive {
    /// One frame of the viewer into `renderer`'s target, as the window and the page draw
    /// it: the camera's pose is recorded for prediction, then the warp effect warps live
    /// (a pair of references every `k` frames, warped frames between) and every other effect
    /// renders.
    ///
    /// # Errors
    /// GPU or technique errors from the renderer.
    pub fn draw(
        &mut self,
        renderer: &mut Renderer,
        ctx: &npr_gpu::GpuContext,
        state: &ViewerState,
        view: &View,
        frame: u64,
    ) -> Result<FrameStats, AppError> {
        self.predictor
            .push(frame, OrbitView::of(&state.preset, state.turntable_deg));
        if state.preset.effect == crate::preset::Effect::Warp {
            self.frame(renderer, ctx, state, view, frame)
        } else {
            self.last_reference = None;
            renderer.render(&ctx.device, &ctx.queue, &state.preset, view)
        }
    }

    /// One frame of live warping into `renderer`'s target: at `frame` a pair of references
    /// is due every `preset.warp.k` frames (that frame is the full render), else the frame
    /// is warped from the two references around it.
    ///
    /// # Errors
    /// GPU or technique errors from the renderer.
    fn frame(
        &mut self,
        renderer: &mut Renderer,
        ctx: &npr_gpu::GpuContext,
        state: &ViewerState,
        view: &View,
        frame: u64,
    ) -> Result<FrameStats, AppError> {
        let (device, queue) = (&ctx.device, &ctx.queue);
        let preset = &state.preset;
        let k = u64::from(preset.warp.k.max(1));
        let wait = || {
            let _ = device.poll(wgpu::PollType::wait_indefinitely());
        };
        let due =
            self.last_reference.is_none_or(|f| frame >= f + k) || renderer.warp_references() == 0;
        if due {
            // The references: now, and where the camera will be in k frames.
            let started = Instant::now();
            renderer.warp_reference(device, queue, preset, view)?;
            let ahead = self
                .predictor
                .predict(k as f32)
                .unwrap_or(OrbitView::of(preset, state.turntable_deg));
            let mut future = preset.clone();
            future.camera.yaw_deg = ahead.yaw_deg;
            future.camera.pitch_deg = ahead.pitch_deg;
            future.camera.distance = ahead.distance;
            future.turn_deg = ahead.turn_deg;
            let future_view = View::new(&future, &renderer.model().framing, renderer.size(), 0.0);
            renderer.warp_reference(device, queue, preset, &future_view)?;
            // This frame is the full render.
            let stats = renderer.render(device, queue, preset, view)?;
            wait();
            self.full_ms = smooth(self.full_ms, started.elapsed().as_secs_f64() * 1e3);
            self.last_reference = Some(frame);
            return Ok(FrameStats {
                psnr_db: self.psnr_db,
                ..stats
            });
        }
        let started = Instant::now();
        let mut stats = renderer.warp_frame(device, queue, preset, view, None)?;
        wait();
        self.warped_ms = smooth(self.warped_ms, started.elapsed().as_secs_f64() * 1e3);
        // Half-way between references, measure this warped frame against a full render
        // (which is then shown instead, so the measurement costs no stale frame).
        #[cfg(not(target_arch = "wasm32"))]
        if self.last_reference.is_some_and(|f| frame == f + k / 2) {
            let warped = renderer.read(device, queue)?;
            renderer.render(device, queue, preset, view)?;
            let full = renderer.read(device, queue)?;
            self.psnr_db = Some(npr_warp::metrics::compare(&full, &warped).psnr_db);
        }
        stats.psnr_db = self.psnr_db;
        Ok(stats)
    }
}
