//! Where the engine's per-frame `N = H` search runs (`[specular] search`): on the CPU
//! (`HighlightSet::update`), or as compute passes (`npr_specular::CentreSearchPass`, its
//! accepted faces merged into centres there, and `npr_specular::RegionPass`, seeded from
//! those centres on the GPU, `RegionPass::prepare_tracked`, in the same submission: the
//! frame waits once, then `HighlightSet::update_from_search` takes the centres and
//! regions read back; a frame whose update adds a peak to the seeds grows its regions in
//! a second submission), or the fastest of these and the whole frame on the GPU
//! (`gpu-frame`, drawn by `engine::specular`), timed on the model's first frame (`auto`,
//! the default). The GPU path falls back to the CPU's where the device's limits are too
//! small for the mesh or a frame's list or a region overflows. `auto` times the whole
//! update each way (search, matching, regions, projectors). In the browser a readback
//! completes only between frames, so `gpu` searches on the CPU there (`gpu-frame` reads
//! nothing back and runs there as anywhere) and `auto` keeps the CPU.

use crate::AppError;
use crate::preset::SearchPreset;
use glam::Mat4;
use npr_geometry::LightEye;
use npr_specular::HighlightSet;

/// Where `auto` found a frame's highlights fastest.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Path {
    /// `HighlightSet::update`.
    Cpu,
    /// `SetupOnGpu`: the search and regions on the GPU, read back, the update on the CPU.
    Gpu,
    /// `FrameOnGpu`: the whole frame's highlights on the GPU, nothing read back.
    Frame,
}

/// The GPU search of the current set, and the path `auto` chose for it.
#[derive(Default)]
pub(crate) struct SearchSetup {
    #[cfg(not(target_arch = "wasm32"))]
    gpu: Option<npr_specular::SetupOnGpu>,
    /// What `auto` measured fastest for the current set.
    #[cfg(not(target_arch = "wasm32"))]
    chosen: Option<Path>,
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
            self.chosen == Some(Path::Gpu)
        }
        #[cfg(target_arch = "wasm32")]
        {
            false
        }
    }

    /// Whether `auto` chose the whole frame on the GPU (`FrameOnGpu`) for the current
    /// set.
    pub(crate) fn chose_frame(&self) -> bool {
        #[cfg(not(target_arch = "wasm32"))]
        {
            self.chosen == Some(Path::Frame)
        }
        #[cfg(target_arch = "wasm32")]
        {
            false
        }
    }

    /// Whether `auto` has yet to time the paths for the current set.
    pub(crate) fn untimed(&self) -> bool {
        #[cfg(not(target_arch = "wasm32"))]
        {
            self.chosen.is_none()
        }
        #[cfg(target_arch = "wasm32")]
        {
            false
        }
    }

    /// Updates `set` for this light, eye and transform on the path `preset` asks for;
    /// returns whether the search ran on the GPU. `auto`'s first frame times the whole
    /// frame on the GPU too where `frame_gpu` is given.
    ///
    /// # Errors
    /// A GPU failure other than a mesh too large for the device's limits.
    pub(crate) fn update(
        &mut self,
        gpu: (&wgpu::Device, &wgpu::Queue),
        set: &mut HighlightSet,
        preset: SearchPreset,
        (light_eye, world_from_object): (LightEye, Mat4),
        frame_gpu: Option<&mut npr_specular::FrameOnGpu>,
    ) -> Result<bool, AppError> {
        self.waits = 0;
        #[cfg(target_arch = "wasm32")]
        {
            let _ = (gpu, preset, frame_gpu);
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
                SearchPreset::Auto => {
                    let path = match self.chosen {
                        Some(p) => p,
                        None => {
                            let frame = (light_eye, world_from_object);
                            let p = self.time_all(gpu, set, frame, frame_gpu)?;
                            self.chosen = Some(p);
                            p
                        }
                    };
                    // (A frame `auto` gives to the GPU whole is drawn by
                    // `engine::specular`; this one, its first, by the search setup.)
                    path != Path::Cpu
                }
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
    use super::Path;
    use super::SearchSetup;
    use crate::AppError;
    use glam::Mat4;
    use npr_geometry::LightEye;
    use npr_specular::{FrameOnGpu, HighlightSet, SetupOnGpu};
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
        /// (`HighlightSet::update`), on the GPU (`update_on_gpu`: the search and its
        /// regions with their submit and readback, then the update) and, where given, the
        /// whole frame's highlights on the GPU (`FrameOnGpu::record`, submitted and waited
        /// for: its GPU time is the frame's), twice each, and keeps the second timings;
        /// the fastest. `set` holds a valid update after any.
        pub(super) fn time_all(
            &mut self,
            gpu: (&wgpu::Device, &wgpu::Queue),
            set: &mut HighlightSet,
            frame: (LightEye, Mat4),
            mut frame_gpu: Option<&mut FrameOnGpu>,
        ) -> Result<Path, AppError> {
            let (device, queue) = gpu;
            let mut times = [f64::INFINITY; 3];
            for round in 0..2u64 {
                let t = Instant::now();
                set.update(frame.0, frame.1);
                times[0] = t.elapsed().as_secs_f64();
                let t = Instant::now();
                times[1] = match self.update_on_gpu(gpu, set, frame)? {
                    Some(_) => t.elapsed().as_secs_f64(),
                    None => f64::INFINITY,
                };
                if let Some(f) = frame_gpu.as_deref_mut() {
                    f.start_from(queue, set, frame.1);
                    let t = Instant::now();
                    let mut encoder = device.create_command_encoder(&Default::default());
                    // Frame ids of its own (its objects' slots count frames apart).
                    let id = npr_gpu::FrameId(u64::MAX - round);
                    f.record(queue, &mut encoder, set, frame, id)?;
                    queue.submit([encoder.finish()]);
                    device
                        .poll(wgpu::PollType::wait_indefinitely())
                        .map_err(|e| npr_gpu::GpuError::Readback(e.to_string()))?;
                    times[2] = t.elapsed().as_secs_f64();
                }
            }
            let fastest = (0..3).fold(0, |b, i| if times[i] < times[b] { i } else { b });
            Ok([Path::Cpu, Path::Gpu, Path::Frame][fastest])
        }
    }
}
