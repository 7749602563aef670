//! Where the engine's per-frame `N = H` search runs (`[specular] search`): on the CPU
//! (`HighlightSet::update`), or as compute passes (`npr_specular::CentreSearchPass`, its
//! accepted faces merged into centres there, and `npr_specular::RegionPass`, seeded from
//! those centres on the GPU, `RegionPass::prepare_tracked`, in the same submission: the
//! frame waits once, then `HighlightSet::update_from_search` takes the centres and
//! regions read back; a frame whose update adds a peak to the seeds grows its regions in
//! a second submission), or the faster of the two for the model, timed on its first
//! frame (`auto`, the default). The GPU path falls back to the CPU's where the device's
//! limits are too small for the mesh or a frame's list or a region overflows. `auto` times the whole update both ways (search, matching, regions,
//! projectors). In the browser a readback completes only between frames, so
//! the search runs on the CPU there.

use crate::AppError;
use crate::preset::SearchPreset;
use glam::Mat4;
use npr_geometry::LightEye;
use npr_specular::HighlightSet;

/// The GPU search of the current set, and the path `auto` chose for it.
#[derive(Default)]
pub(crate) struct SearchSetup {
    #[cfg(not(target_arch = "wasm32"))]
    gpu: Option<npr_specular::SetupOnGpu>,
    /// `Some(true)` for the GPU: what `auto` measured for the current set.
    #[cfg(not(target_arch = "wasm32"))]
    chosen: Option<bool>,
    /// Submissions the last update waited on (0 on the CPU).
    waits: usize,
}

impl SearchSetup {
    /// Forgets the GPU object and `auto`'s choice (a new set or model).
    pub(crate) fn forget(&mut self) {
        *self = Self::default();
    }

    /// Submissions the last update waited on: 0 on the CPU, 1 where the regions grew in
    /// the search's submission, 2 where they were grown again in one of their own.
    pub(crate) fn waits(&self) -> usize {
        self.waits
    }

    /// Whether `auto` chose the GPU for the current set (`false` before it has timed
    /// both, and in the browser, where the search stays on the CPU).
    pub(crate) fn chose_gpu(&self) -> bool {
        #[cfg(not(target_arch = "wasm32"))]
        {
            self.chosen == Some(true)
        }
        #[cfg(target_arch = "wasm32")]
        {
            false
        }
    }

    /// Updates `set` for this light, eye and transform on the path `preset` asks for;
    /// returns whether the search ran on the GPU.
    ///
    /// # Errors
    /// A GPU failure other than a mesh too large for the device's limits.
    pub(crate) fn update(
        &mut self,
        gpu: (&wgpu::Device, &wgpu::Queue),
        set: &mut HighlightSet,
        preset: SearchPreset,
        (light_eye, world_from_object): (LightEye, Mat4),
    ) -> Result<bool, AppError> {
        self.waits = 0;
        #[cfg(target_arch = "wasm32")]
        {
            let _ = (gpu, preset);
            set.update(light_eye, world_from_object);
            Ok(false)
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            let on_gpu = match preset {
                SearchPreset::Cpu => false,
                // (`engine::specular` makes a `gpu-frame` frame itself; where it cannot,
                // the search setup's GPU path is the next best.)
                SearchPreset::Gpu | SearchPreset::GpuFrame => true,
                SearchPreset::Auto => match self.chosen {
                    Some(c) => c,
                    None => {
                        let c = self.time_both(gpu, set, (light_eye, world_from_object))?;
                        self.chosen = Some(c);
                        c
                    }
                },
            };
            if on_gpu
                && let Some(waits) = self.update_on_gpu(gpu, set, (light_eye, world_from_object))?
            {
                self.waits = waits;
                return Ok(true);
            }
            set.update(light_eye, world_from_object);
            Ok(false)
        }
    }
}

#[cfg(not(target_arch = "wasm32"))]
mod native {
    use super::SearchSetup;
    use crate::AppError;
    use glam::Mat4;
    use npr_geometry::LightEye;
    use npr_specular::{HighlightSet, SetupOnGpu};
    use std::time::Instant;

    impl SearchSetup {
        /// Updates `set` on the GPU (`SetupOnGpu::update`, its passes created on first
        /// use): the submissions waited on, or `None` where the CPU must run the search.
        pub(super) fn update_on_gpu(
            &mut self,
            (device, queue): (&wgpu::Device, &wgpu::Queue),
            set: &mut HighlightSet,
            frame: (LightEye, Mat4),
        ) -> Result<Option<usize>, AppError> {
            let setup = match &mut self.gpu {
                Some(s) => s,
                None => self.gpu.insert(SetupOnGpu::new(device, set)?),
            };
            Ok(setup.update((device, queue), set, frame)?)
        }

        /// `auto`: times the whole highlight update of this frame on the CPU
        /// (`HighlightSet::update`) and on the GPU (`update_on_gpu`: the search and its
        /// regions with their submit and readback, then the update), twice each, and
        /// keeps the second timings; whether the GPU's was faster. Both update the same
        /// frame, so `set` holds a valid update after either.
        pub(super) fn time_both(
            &mut self,
            gpu: (&wgpu::Device, &wgpu::Queue),
            set: &mut HighlightSet,
            frame: (LightEye, Mat4),
        ) -> Result<bool, AppError> {
            let mut cpu_s = f64::INFINITY;
            let mut gpu_s = f64::INFINITY;
            for _ in 0..2 {
                let t = Instant::now();
                set.update(frame.0, frame.1);
                cpu_s = t.elapsed().as_secs_f64();
                let t = Instant::now();
                gpu_s = match self.update_on_gpu(gpu, set, frame)? {
                    Some(_) => t.elapsed().as_secs_f64(),
                    None => f64::INFINITY,
                };
            }
            Ok(gpu_s < cpu_s)
        }
    }
}
