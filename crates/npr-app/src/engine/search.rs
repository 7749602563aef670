//! Where the engine's per-frame `N = H` search runs (`[specular] search`): on the CPU
//! (`HighlightSet::update`), or as a compute pass (`npr_specular::CentreSearchPass`,
//! its accepted faces merged into centres there and the compact list read back, then
//! `HighlightSet::update_from_search` with the regions grown by
//! `npr_specular::RegionPass`), or the faster of the two for
//! the model, timed on its first frame (`auto`, the default). The GPU path falls back to
//! the CPU's where the device's limits are too small for the mesh or a frame's list or a
//! region overflows. `auto` times the whole update both ways (search, matching, regions,
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
    gpu: Option<native::GpuSearch>,
    /// `Some(true)` for the GPU: what `auto` measured for the current set.
    #[cfg(not(target_arch = "wasm32"))]
    chosen: Option<bool>,
}

impl SearchSetup {
    /// Forgets the GPU object and `auto`'s choice (a new set or model).
    pub(crate) fn forget(&mut self) {
        *self = Self::default();
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
                SearchPreset::Gpu => true,
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
                && let Some(solved) = self.gpu_faces(gpu, set, (light_eye, world_from_object))?
            {
                self.update_on_gpu(gpu, set, (light_eye, world_from_object), &solved)?;
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
    use npr_gpu::FrameId;
    use npr_specular::{
        CentreSearchPass, HighlightSet, RegionObject, RegionPass, SearchInput, SearchObject,
        SearchSolutions, SpecularError,
    };
    use std::time::Instant;

    /// The compute passes and the set's tables on the GPU; `None` in `object` or
    /// `regions` where the device's limits are too small for the mesh.
    pub(super) struct GpuSearch {
        pass: CentreSearchPass,
        object: Option<SearchObject>,
        region_pass: RegionPass,
        regions: Option<RegionObject>,
        frame: FrameId,
    }

    /// `RegionPass::create_object`, `None` where the mesh is too large for the device.
    fn region_object(
        device: &wgpu::Device,
        pass: &RegionPass,
        set: &HighlightSet,
    ) -> Result<Option<RegionObject>, AppError> {
        match pass.create_object(device, set) {
            Ok(o) => Ok(Some(o)),
            Err(SpecularError::Gpu(npr_gpu::GpuError::MeshTooLarge { .. })) => Ok(None),
            Err(e) => Err(e.into()),
        }
    }

    impl SearchSetup {
        /// Updates `set` from the GPU search's list (`solved`, complete), its regions grown
        /// on the GPU too (on the CPU where the mesh does not fit the device's limits).
        pub(super) fn update_on_gpu(
            &mut self,
            (device, queue): (&wgpu::Device, &wgpu::Queue),
            set: &mut HighlightSet,
            (light_eye, world_from_object): (LightEye, Mat4),
            solved: &SearchSolutions,
        ) -> Result<(), AppError> {
            let Some(gpu) = self.gpu.as_mut() else {
                set.update_from_search(light_eye, world_from_object, solved, None);
                return Ok(());
            };
            let Some(object) = gpu.regions.as_mut() else {
                set.update_from_search(light_eye, world_from_object, solved, None);
                return Ok(());
            };
            let mut grow = gpu.region_pass.grower(
                (device, queue),
                object,
                gpu.frame,
                (light_eye, world_from_object),
            );
            set.update_from_search(light_eye, world_from_object, solved, Some(&mut grow));
            Ok(())
        }

        /// The GPU search's list for this frame (merged into centres on the GPU where they
        /// fit its merge); `None` where the CPU must run it (the mesh does not fit the
        /// device's limits, or the list overflowed).
        pub(super) fn gpu_faces(
            &mut self,
            (device, queue): (&wgpu::Device, &wgpu::Queue),
            set: &HighlightSet,
            (light_eye, world_from_object): (LightEye, Mat4),
        ) -> Result<Option<SearchSolutions>, AppError> {
            if self.gpu.is_none() {
                let pass = CentreSearchPass::new(device);
                let object = match pass.create_object(device, set.search()) {
                    Ok(o) => Some(o),
                    Err(SpecularError::Gpu(npr_gpu::GpuError::MeshTooLarge { .. })) => None,
                    Err(e) => return Err(e.into()),
                };
                let region_pass = RegionPass::new(device);
                let regions = region_object(device, &region_pass, set)?;
                self.gpu = Some(GpuSearch {
                    pass,
                    object,
                    region_pass,
                    regions,
                    frame: FrameId::default(),
                });
            }
            let Some(gpu) = self.gpu.as_mut() else {
                return Ok(None);
            };
            let Some(object) = gpu.object.as_mut() else {
                return Ok(None);
            };
            gpu.frame = gpu.frame.next();
            let input = SearchInput {
                frame: gpu.frame,
                search: set.search(),
                light_eye,
                world_from_object,
            };
            let solved = gpu.pass.search_now(device, queue, object, &input)?;
            Ok(solved.complete().then_some(solved))
        }

        /// `auto`: times the whole highlight update of this frame on the CPU
        /// (`HighlightSet::update`) and on the GPU (the search with its submit and
        /// readback, then the update on its list with the regions grown on the GPU),
        /// twice each, and keeps the second timings; whether the GPU's was faster. Both
        /// update the same frame, so `set` holds a valid update after either.
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
                gpu_s = match self.gpu_faces(gpu, set, frame)? {
                    Some(solved) => {
                        self.update_on_gpu(gpu, set, frame, &solved)?;
                        t.elapsed().as_secs_f64()
                    }
                    None => f64::INFINITY,
                };
            }
            Ok(gpu_s < cpu_s)
        }
    }
}
