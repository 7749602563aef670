//! `cs_replace` of `centre_search.wgsl`: the last frame's highlights (a table the GPU
//! or the CPU wrote) placed again on this frame's pose and transform at their faces and
//! barycentrics, as `HighlightSet`'s matching places a highlight it lost
//! (`HighlightSearch::centre_at`), after the search's centres. The projectors
//! ([`crate::gpu::ProjectorPass`]) record it before `cs_project`, which fades the lost ones out
//! where it put them.

use super::{SearchObject, Slot};
use crate::SpecularError;
use npr_gpu::compute::{group_entry, pipeline_over, storage_layout_entry};
use npr_gpu::pass::Prepared;

/// `cs_replace`'s pipeline and its second group's layout (the field, the centres and the
/// table); its first group is the centres' tables group of the search's slot.
#[derive(Clone, Debug)]
pub(crate) struct Replace {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

/// What records `cs_replace` for one frame: its pipeline and two groups.
#[derive(Debug)]
pub(crate) struct ReplaceWork {
    pipeline: wgpu::ComputePipeline,
    groups: [wgpu::BindGroup; 2],
}

impl Replace {
    pub(super) fn new(
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        tables: &wgpu::BindGroupLayout,
    ) -> Self {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr centre search replace"),
            entries: &[
                storage_layout_entry(1, true),
                storage_layout_entry(2, false),
                storage_layout_entry(5, true),
            ],
        });
        Self {
            pipeline: pipeline_over(device, module, &[tables, &layout], "cs_replace"),
            layout,
        }
    }
}

impl SearchObject {
    /// Per face its visiting slot (`cs_replace` reads a centre's face through it).
    pub(crate) fn slots_of_faces(&self) -> Vec<u32> {
        let mut slots = vec![u32::MAX; self.faces];
        for (slot, &face) in self.face_order.iter().enumerate() {
            if let Some(s) = slots.get_mut(face as usize) {
                *s = slot as u32;
            }
        }
        slots
    }

    /// `cs_replace` for `prepared`'s frame over `table` (`TrackData`).
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a stale or foreign `prepared`.
    pub(crate) fn replace_work(
        &self,
        device: &wgpu::Device,
        prepared: &Prepared,
        table: &wgpu::Buffer,
        groups: &mut npr_gpu::compute::GroupCache,
    ) -> Result<ReplaceWork, SpecularError> {
        let slot: &Slot = self.slots.get(self.slots.pass(), prepared)?;
        let group = groups.get_or_make(&[&self.field, &slot.records, table], || {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("npr centre search replace"),
                layout: &self.replace.layout,
                entries: &[
                    group_entry(1, &self.field),
                    group_entry(2, &slot.records),
                    group_entry(5, table),
                ],
            })
        });
        Ok(ReplaceWork {
            pipeline: self.replace.pipeline.clone(),
            groups: [slot.centres_groups[0].clone(), group],
        })
    }
}

impl ReplaceWork {
    /// Dispatches it (one invocation per highlight of the table, [`crate::gpu::MAX_MERGED`]
    /// at most) in `pass`.
    pub(crate) fn dispatch(&self, pass: &mut wgpu::ComputePass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.groups[0], &[]);
        pass.set_bind_group(1, &self.groups[1], &[]);
        pass.dispatch_workgroups(crate::gpu::MAX_MERGED.div_ceil(64) as u32, 1, 1);
    }
}
