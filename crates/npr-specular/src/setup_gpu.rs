//! The highlight setup of a frame on the GPU, in one submission: the `N = H` search
//! ([`CentreSearchPass`], its centres merged and computed there) and the regions
//! ([`RegionPass`]) seeded from those centres on the GPU
//! ([`RegionPass::prepare_tracked`]), so that the frame waits once; then the update
//! ([`HighlightSet::update_from_search`]) on the centres and regions read back. The
//! search also finds the peaks (bright regions without an `N = H` point,
//! [`crate::SearchSolutions::peaks`]), which are seeded with the centres; a frame whose
//! peaks it could not find (too many bright parts or centres) has the update find
//! its own and its regions grown in a second submission ([`RegionPass::grower`]).
//!
//! ```ignore
//! let mut setup = SetupOnGpu::new(device, &set)?;
//! // per frame
//! match setup.update((device, queue), &mut set, (light_eye, world_from_object))? {
//!     Some(waits) => {} // the set is updated; `waits` submissions were waited on
//!     None => { set.update(light_eye, world_from_object); } // the CPU's turn
//! }
//! ```

use crate::{
    CentreSearchPass, HighlightSet, RegionObject, RegionPass, SearchObject, SpecularError,
    TrackedInput,
};
use glam::Mat4;
use npr_geometry::{HighlightCentre, LightEye};
use npr_gpu::FrameId;

/// One set's setup on the GPU: the passes and the set's tables. `None` in `search` or
/// `regions` where the device's limits are too small for the mesh.
#[derive(Debug)]
pub struct SetupOnGpu {
    search_pass: CentreSearchPass,
    search: Option<SearchObject>,
    region_pass: RegionPass,
    regions: Option<RegionObject>,
    frame: FrameId,
}

/// `Ok(None)` for a table too large for the device's bindings (that step stays on the
/// CPU), else the object or the error.
fn fits<T>(made: Result<T, SpecularError>) -> Result<Option<T>, SpecularError> {
    match made {
        Ok(o) => Ok(Some(o)),
        Err(SpecularError::Gpu(npr_gpu::GpuError::MeshTooLarge { .. })) => Ok(None),
        Err(e) => Err(e),
    }
}

impl SetupOnGpu {
    /// The passes, and `set`'s search and region tables uploaded (each left to the CPU
    /// where it exceeds the device's storage bindings).
    ///
    /// # Errors
    /// A GPU failure other than a mesh too large for the device's limits.
    pub fn new(device: &wgpu::Device, set: &HighlightSet) -> Result<Self, SpecularError> {
        let search_pass = CentreSearchPass::new(device);
        let region_pass = RegionPass::new(device);
        Ok(Self {
            // The peaks' tables where they fit too, else the search alone.
            search: match fits(search_pass.create_object_with_peaks(device, set))? {
                Some(s) => Some(s),
                None => fits(search_pass.create_object(device, set.search()))?,
            },
            regions: fits(region_pass.create_object(device, set))?,
            search_pass,
            region_pass,
            frame: FrameId::default(),
        })
    }

    /// Whether the search runs on the GPU for this set (its tables fit the device).
    pub fn searches(&self) -> bool {
        self.search.is_some()
    }

    /// Updates `set` for this light, eye and transform on the GPU: the search and its
    /// regions seeded from its centres on the GPU in one submission, then the update on
    /// what comes back, a frame whose seeds are not the GPU's (the search could not give
    /// its peaks) grown again in a second submission (on the CPU where the mesh does not fit the region
    /// pass). Returns the submissions waited on; `None` where the CPU must run the
    /// search (the mesh does not fit the device's limits, or the list overflowed), and
    /// then `set` is unchanged.
    ///
    /// # Errors
    /// A pass's or readback's failure.
    pub fn update(
        &mut self,
        (device, queue): (&wgpu::Device, &wgpu::Queue),
        set: &mut HighlightSet,
        (light_eye, world_from_object): (LightEye, Mat4),
    ) -> Result<Option<usize>, SpecularError> {
        let Some(search) = self.search.as_mut() else {
            return Ok(None);
        };
        self.frame = self.frame.next();
        let frame = self.frame;
        // The peaks too, where the update sizes highlights by their regions.
        let searched = self.search_pass.prepare_for_set(
            queue,
            search,
            (set, frame),
            (light_eye, world_from_object),
        )?;
        // The regions seeded on the GPU, where the update sizes highlights by their
        // regions, the mesh fits and the last update's highlights are few enough to match
        // there.
        let regions = self
            .regions
            .as_mut()
            .filter(|_| set.sizing == crate::HighlightSizing::Region);
        let grown = match regions {
            Some(regions) => {
                let tracked = TrackedInput {
                    frame,
                    set,
                    light_eye,
                    world_from_object,
                    search: (search, &searched),
                };
                match self.region_pass.prepare_tracked(queue, regions, &tracked) {
                    Ok(p) => Some(p),
                    Err(SpecularError::Mismatch(_)) => None,
                    Err(e) => return Err(e),
                }
            }
            None => None,
        };
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr highlight setup"),
        });
        self.search_pass.record(&mut encoder, search, &searched)?;
        if let (Some(regions), Some(grown)) = (self.regions.as_ref(), grown.as_ref()) {
            self.region_pass.record(&mut encoder, regions, grown)?;
        }
        queue.submit([encoder.finish()]);
        let pending = match (self.regions.as_ref(), grown.as_ref()) {
            (Some(regions), Some(grown)) => Some(regions.map_tracked(device, queue, grown)?),
            _ => None,
        };
        let solved = search.read(device, &searched)?;
        let tracked = pending.map(|p| p.wait(device)).transpose()?;
        if !solved.complete() {
            return Ok(None);
        }
        let Some(regions) = self.regions.as_mut() else {
            set.update_from_search(light_eye, world_from_object, &solved, None);
            return Ok(Some(1));
        };
        let mut waits = 1;
        let mut again = self.region_pass.grower(
            (device, queue),
            regions,
            frame,
            (light_eye, world_from_object),
        );
        let mut grow = |set: &HighlightSet, seeds: &[(HighlightCentre, f32)]| {
            tracked
                .as_ref()
                .and_then(|t| t.for_seeds(seeds))
                .or_else(|| {
                    waits = 2;
                    again(set, seeds)
                })
        };
        set.update_from_search(light_eye, world_from_object, &solved, Some(&mut grow));
        Ok(Some(waits))
    }
}
