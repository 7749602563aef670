//! The `N = H` search (§3.1, Eq. (3)–(6)) as a compute pass (`shaders/centre_search.wgsl`):
//! `cs_clusters` lists the clusters of 64 faces whose normal cone can hold `N = H` (the
//! others are skipped whole, as the CPU search skips vertex clusters), `cs_search` solves
//! the faces of the listed clusters, one workgroup each, dispatched indirectly; the
//! accepted faces
//! appended to a compact list by an integer atomic counter (WebGPU has no float
//! atomics), and `cs_merge` merges the list into one entry per centre as the CPU search
//! does ([`HighlightSearch::centres_from_solutions`]: the faces in the CPU's visiting
//! order, [`HighlightSearch::visit_ranks`], the deeper of two solutions within
//! [`HighlightSearch::merge_distance`] kept), and `cs_centres` computes each kept centre
//! as [`HighlightSearch::centre_at`] does. Only the lists are read back: at most
//! [`SearchObject::capacity`] accepted faces of 16 bytes and [`MAX_MERGED`] centres of
//! 112, never a mesh-sized buffer (a test's or a panel's readback: the GPU backend's
//! frames, [`crate::HighlightSetup`], read nothing back and go on to the regions on the
//! GPU).
//!
//! It speaks the pass contract ([`npr_gpu::pass`]) with `record` in place of `draw`:
//!
//! ```ignore
//! let pass = CentreSearchPass::new(device);
//! let mut object = pass.create_object(device, set.search())?;
//! // per frame
//! let input = SearchInput { frame, search: set.search(), light_eye, world_from_object };
//! let prepared = pass.prepare(queue, &mut object, &input)?;
//! pass.record(&mut encoder, &object, &prepared)?;
//! queue.submit([encoder.finish()]);
//! let solutions = object.read(device, &prepared)?; // the centres, for a comparison
//! ```
//!
//! The CPU search ([`HighlightSearch::find`]) is the reference: `tests/gpu_search.rs`
//! compares the two on the same frame. WGSL has no `f64`, so the solve runs in `f32`
//! where the CPU's runs in `f64`; the shader's header says which tolerances change.

use glam::Mat4;
use npr_geometry::{FaceSolution, HighlightSearch, LightEye};
use npr_gpu::compute::{
    buffer_init, check_bindings, dispatch_size, pipeline, pipeline_over, storage_layout_entry,
};
use npr_gpu::pass::{FrameId, PassId, Prepared, Slots};

use crate::SpecularError;
use crate::cpu::clusters::{self, CLUSTER_FACES, ClusterRecord};

mod peaks;
mod readback;
mod replace;
mod slot;
pub(crate) use readback::CentreRecord;
pub(crate) use replace::{Replace, ReplaceWork};
use slot::make_slot;
pub(crate) mod tables;
pub use readback::PendingSolutions;
use readback::{slot_records, solution_entries};
use tables::{Params, field_records, ordered_triangles, params_of, vertex_records};

/// Accepted faces one frame keeps by default: far more than a frame has highlights
/// (each centre is found by one to six faces), at 16 bytes each.
pub const DEFAULT_CAPACITY: usize = 4096;

/// Centres the GPU's merge keeps at most (`MAX_MERGED` of `centre_search.wgsl`): past it
/// [`SearchSolutions::centres`] is `None` and the CPU merges the accepted faces.
pub const MAX_MERGED: usize = 256;

/// Bytes of `Counter` at the head of `SearchFrame` (`centre_search.wgsl`): the params
/// follow it.
const COUNTER_BYTES: u64 = 16;

/// `NO_MERGE` of `centre_search.wgsl`.
const NO_MERGE: u32 = u32::MAX;

/// The search's compute pipeline: one per device, shared by every object.
#[derive(Debug)]
pub struct CentreSearchPass {
    id: PassId,
    device: wgpu::Device,
    /// `cs_clusters`: group 0 and the dispatch group.
    clusters_pipeline: wgpu::ComputePipeline,
    /// `cs_search`: group 0 only, dispatched indirectly.
    pipeline: wgpu::ComputePipeline,
    /// `cs_merge`: group 0 only, one workgroup.
    merge_pipeline: wgpu::ComputePipeline,
    /// `cs_centres`: group 0's tables, list and params ([`centres_layouts`]'s first),
    /// and group 1's field, records and the peaks' tables (its second); the peaks'
    /// passes over the same groups: `cs_bright`, `cs_join_bright`, `cs_part_best` and
    /// `cs_part_brightest` over the vertices, then `cs_peaks`.
    centres_pipeline: wgpu::ComputePipeline,
    vertex_pipelines: [wgpu::ComputePipeline; 4],
    peaks_pipeline: wgpu::ComputePipeline,
    centres_layouts: [wgpu::BindGroupLayout; 2],
    /// `cs_replace` and its second group's layout (shared with each object).
    replace: Replace,
    layout: wgpu::BindGroupLayout,
    dispatch_layout: wgpu::BindGroupLayout,
    /// Workgroups a row of `cs_search`'s indirect dispatch holds: the device's
    /// `max_compute_workgroups_per_dimension`.
    row: u32,
}

/// What one search needs: the frame, the search whose tables the object holds, and the
/// light, eye and transform of [`HighlightSearch::find`].
#[derive(Clone, Copy, Debug)]
pub struct SearchInput<'a> {
    /// The caller's submission.
    pub frame: FrameId,
    /// The search of the mesh (its tables are uploaded again when its id changes).
    pub search: &'a HighlightSearch,
    /// Light and eye, world space.
    pub light_eye: LightEye,
    /// The object's transform.
    pub world_from_object: Mat4,
}

/// One mesh's search tables on the GPU and the per-frame lists.
#[derive(Debug)]
pub struct SearchObject {
    search_id: u64,
    vertex_count: usize,
    faces: usize,
    capacity: usize,
    vertices: wgpu::Buffer,
    /// The triangles in [`clusters::face_order`] (the order `cs_search` visits).
    triangles: wgpu::Buffer,
    /// That order: visiting slot → face.
    face_order: Vec<u32>,
    order: wgpu::Buffer,
    /// One [`clusters::ClusterRecord`] per workgroup of faces, for the pose of
    /// `search_id`.
    clusters: wgpu::Buffer,
    /// The curvature field the centres interpolate ([`HighlightSearch::field_floats`]),
    /// for the pose of `search_id`.
    field: wgpu::Buffer,
    /// The peaks' tables ([`CentreSearchPass::create_object_with_peaks`]); `None`: no
    /// peaks looked for, and `empty` bound in their place (two: one is bound writable).
    peaks: Option<peaks::PeakTables>,
    empty: [wgpu::Buffer; 2],
    /// `cs_replace`, for the projectors that read its output ([`crate::gpu::ProjectorPass`]).
    replace: Replace,
    slots: Slots<Slot>,
}

/// One prepare's counts and params (`SearchFrame`), list and readback copy.
#[derive(Debug)]
struct Slot {
    /// `SearchFrame` of the shader: the counter (16 bytes), then the params.
    frame: wgpu::Buffer,
    solutions: wgpu::Buffer,
    /// `cs_search`'s indirect dispatch (`Dispatch` of the shader), written by
    /// `cs_clusters`.
    dispatch: wgpu::Buffer,
    /// The clusters `cs_clusters` listed (index + 1; 0 past them).
    listed: wgpu::Buffer,
    readback: wgpu::Buffer,
    group: wgpu::BindGroup,
    dispatch_group: wgpu::BindGroup,
    /// `cs_centres`'s output, [`MAX_MERGED`] records (and as many for `cs_replace`), and
    /// its two groups.
    records: wgpu::Buffer,
    centres_groups: [wgpu::BindGroup; 2],
    /// Whether this frame has a half vector (no dispatch otherwise: nothing is found).
    active: bool,
    /// The σ this frame looks for peaks at ([`CentreSearchPass::prepare_with_peaks`]).
    peaks: Option<f32>,
}

/// The faces one frame's search accepted.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SearchSolutions {
    /// The accepted faces (at most the object's capacity), in no particular order.
    pub faces: Vec<FaceSolution>,
    /// How many faces were accepted: more than `faces.len()` when the list overflowed
    /// (then use the CPU search for that frame, or a larger capacity).
    pub accepted: usize,
    /// How many clusters of faces (workgroups of [`SearchObject::cluster_faces`]) the
    /// search solved; the others' normal cones could not hold `N = H` and were skipped
    /// whole ([`SearchObject::cluster_count`] in all).
    pub clusters_solved: usize,
    /// The centres, merged and computed on the GPU (`cs_merge`, `cs_centres`): those
    /// [`HighlightSearch::centres_from_solutions`] gives for `faces`, in its order (an
    /// accepted face whose centre has no normal, which the CPU leaves out before merging,
    /// takes part in the GPU's merge; the tests never met one); `None` when the list
    /// overflowed or held more than [`MAX_MERGED`] centres.
    pub centres: Option<Vec<npr_geometry::HighlightCentre>>,
    /// The peaks, found on the GPU where asked for
    /// ([`CentreSearchPass::prepare_with_peaks`]): the bright regions `N·H ≥ σ` that hold
    /// no `N = H` centre, each with a centre at its maximum of `N̂·Ĥ`, in the order
    /// [`crate::HighlightSet`]'s update finds them; `None` where not asked for or not
    /// found (no merged centres, more than [`MAX_MERGED`] in all, or more parts of bright
    /// vertices than the scratch lists), and then the update finds its own.
    pub peaks: Option<Vec<npr_geometry::HighlightCentre>>,
    /// The σ the peaks were looked for at (an update takes them only at its own σ).
    pub peak_sigma: Option<f32>,
}

impl SearchSolutions {
    /// Whether every accepted face is in [`SearchSolutions::faces`].
    pub fn complete(&self) -> bool {
        self.accepted == self.faces.len()
    }
}

impl CentreSearchPass {
    /// The compute pipeline. A compute pass draws into no target, so it takes no
    /// [`npr_gpu::TargetFormats`].
    pub fn new(device: &wgpu::Device) -> Self {
        let module = crate::shaders::CENTRE_SEARCH.module(device);
        let mut entries: Vec<_> = (0..4).map(|b| storage_layout_entry(b, b < 2)).collect();
        entries.extend((5..8).map(|b| storage_layout_entry(b, b < 7)));
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr centre search"),
            entries: &entries,
        });
        let dispatch_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("npr centre search dispatch"),
            entries: &[storage_layout_entry(0, false)],
        });
        // `cs_centres`, `cs_bright` and `cs_peaks` read group 0's vertices and triangles
        // and its frame (counts and params: `cs_peaks` writes the peaks' count) and list,
        // and group 1's field and the peaks' adjacency; they write group 1's records and
        // the peaks' scratch.
        let tables: Vec<_> = (0..4).map(|b| storage_layout_entry(b, b < 2)).collect();
        let centres_layouts = [
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("npr centre search centres tables"),
                entries: &tables,
            }),
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("npr centre search centres"),
                entries: &[
                    storage_layout_entry(1, true),
                    storage_layout_entry(2, false),
                    storage_layout_entry(3, true),
                    storage_layout_entry(4, false),
                ],
            }),
        ];
        Self {
            id: PassId::fresh(),
            device: device.clone(),
            clusters_pipeline: pipeline_over(
                device,
                &module,
                &[&layout, &dispatch_layout],
                "cs_clusters",
            ),
            pipeline: pipeline(device, &module, &layout, "cs_search"),
            merge_pipeline: pipeline(device, &module, &layout, "cs_merge"),
            centres_pipeline: pipeline_over(
                device,
                &module,
                &[&centres_layouts[0], &centres_layouts[1]],
                "cs_centres",
            ),
            vertex_pipelines: [
                "cs_bright",
                "cs_join_bright",
                "cs_part_best",
                "cs_part_brightest",
            ]
            .map(|entry| {
                pipeline_over(
                    device,
                    &module,
                    &[&centres_layouts[0], &centres_layouts[1]],
                    entry,
                )
            }),
            peaks_pipeline: pipeline_over(
                device,
                &module,
                &[&centres_layouts[0], &centres_layouts[1]],
                "cs_peaks",
            ),
            replace: Replace::new(device, &module, &centres_layouts[0]),
            centres_layouts,
            layout,
            dispatch_layout,
            row: device.limits().max_compute_workgroups_per_dimension,
        }
    }

    /// Uploads `search`'s tables ([`HighlightSearch::solve_vertices`], 80 bytes a welded
    /// vertex, and its triangles with their cone-test slack, 16 bytes a face), keeping [`DEFAULT_CAPACITY`] accepted
    /// faces a frame.
    ///
    /// # Errors
    /// [`npr_gpu::GpuError::MeshTooLarge`] when a table exceeds the device's storage
    /// binding limit.
    pub fn create_object(
        &self,
        device: &wgpu::Device,
        search: &HighlightSearch,
    ) -> Result<SearchObject, SpecularError> {
        self.create_object_with_capacity(device, search, DEFAULT_CAPACITY)
    }

    /// [`CentreSearchPass::create_object`] keeping `capacity` accepted faces a frame (at
    /// least 1).
    ///
    /// # Errors
    /// As [`CentreSearchPass::create_object`].
    pub fn create_object_with_capacity(
        &self,
        device: &wgpu::Device,
        search: &HighlightSearch,
        capacity: usize,
    ) -> Result<SearchObject, SpecularError> {
        let solve_vertices = search.solve_vertices();
        let records = vertex_records(&solve_vertices);
        let face_order = clusters::face_order(&solve_vertices, search.triangles());
        let margins = search.face_margins();
        let triangles = ordered_triangles(search, &margins, &face_order);
        let ranks = search.visit_ranks();
        let order = slot_records(&face_order, &ranks);
        let clusters =
            clusters::cluster_records(search.triangles(), &margins, &solve_vertices, &face_order);
        let capacity = capacity.max(1);
        check_bindings(
            &[
                ("search vertices", (records.len() * 80) as u64),
                ("search triangles", (triangles.len() * 16) as u64),
                ("search solutions", (solution_entries(capacity) * 16) as u64),
                ("search order", (face_order.len() * 8) as u64),
                (
                    "search clusters",
                    (clusters.len() * std::mem::size_of::<ClusterRecord>()) as u64,
                ),
                ("search field", (records.len() * 48) as u64),
            ],
            device.limits().max_storage_buffer_binding_size,
        )?;
        // Copied out only by the tests that compare a pose made on the GPU.
        let usage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC;
        Ok(SearchObject {
            search_id: search.id(),
            vertex_count: records.len(),
            faces: triangles.len(),
            capacity,
            vertices: buffer_init(device, "npr search vertices", &records, usage),
            triangles: buffer_init(device, "npr search triangles", &triangles, usage),
            order: buffer_init(device, "npr search order", &order, usage),
            clusters: buffer_init(device, "npr search clusters", &clusters, usage),
            field: buffer_init(device, "npr search field", &field_records(search), usage),
            peaks: None,
            empty: [0, 1].map(|_| buffer_init(device, "npr search no peaks", &[0u32; 4], usage)),
            replace: self.replace.clone(),
            face_order,
            slots: Slots::new(self.id),
        })
    }

    /// [`CentreSearchPass::create_object`] for `set`'s search, with the tables its
    /// peaks need (the vertices' neighbours and faces, about 16 bytes a corner, and a
    /// scratch of 16 bytes a vertex and 32 KiB), for
    /// [`CentreSearchPass::prepare_with_peaks`].
    ///
    /// # Errors
    /// As [`CentreSearchPass::create_object`].
    pub fn create_object_with_peaks(
        &self,
        device: &wgpu::Device,
        set: &crate::HighlightSet,
    ) -> Result<SearchObject, SpecularError> {
        let mut object = self.create_object(device, set.search())?;
        let mut slot_of = vec![0u32; object.face_order.len()];
        for (slot, &f) in object.face_order.iter().enumerate() {
            if let Some(s) = slot_of.get_mut(f as usize) {
                *s = slot as u32;
            }
        }
        let adjacency = peaks::adjacency_words(set, &slot_of);
        let nv = set.topology().vertex_count();
        check_bindings(
            &[
                ("search peak adjacency", (adjacency.len() * 4) as u64),
                ("search peak scratch", (peaks::scratch_words(nv) * 4) as u64),
            ],
            device.limits().max_storage_buffer_binding_size,
        )?;
        object.peaks = Some(peaks::PeakTables::new(device, &adjacency, nv));
        Ok(object)
    }

    /// Takes a slot for `input.frame` and writes its params. When `input.search` is not
    /// the search the object was built or last prepared with (a new pose: same mesh, new
    /// normals and curvature), its vertex tables, the faces' slack and the clusters' cones
    /// are written again.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a foreign object or too many prepares in one frame;
    /// [`SpecularError::Mismatch`] for a search of another mesh (other vertex or face
    /// counts).
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        object: &mut SearchObject,
        input: &SearchInput<'_>,
    ) -> Result<Prepared, SpecularError> {
        self.prepare_with_peaks(queue, object, input, None)
    }

    /// [`CentreSearchPass::prepare_with_peaks`] for `set`'s search in `frame`, looking for
    /// the peaks at the set's σ where its highlights are sized by their regions (the
    /// peaks its update would find).
    ///
    /// # Errors
    /// As [`CentreSearchPass::prepare`].
    pub fn prepare_for_set(
        &self,
        queue: &wgpu::Queue,
        object: &mut SearchObject,
        (set, frame): (&crate::HighlightSet, FrameId),
        (light_eye, world_from_object): (LightEye, Mat4),
    ) -> Result<Prepared, SpecularError> {
        let input = SearchInput {
            frame,
            search: set.search(),
            light_eye,
            world_from_object,
        };
        let sigma = (set.tuning.sizing == crate::HighlightSizing::Region)
            .then_some(set.tuning.controls.sigma);
        self.prepare_with_peaks(queue, object, &input, sigma)
    }

    /// [`CentreSearchPass::prepare`] that also looks for the peaks at `peak_sigma` (an
    /// object of [`CentreSearchPass::create_object_with_peaks`]; `None`, or an object
    /// without the peaks' tables, looks for none): [`SearchSolutions::peaks`].
    ///
    /// # Errors
    /// As [`CentreSearchPass::prepare`].
    pub fn prepare_with_peaks(
        &self,
        queue: &wgpu::Queue,
        object: &mut SearchObject,
        input: &SearchInput<'_>,
        peak_sigma: Option<f32>,
    ) -> Result<Prepared, SpecularError> {
        object.slots.check_pass(self.id)?;
        let search = input.search;
        if search.id() != object.search_id {
            let solve_vertices = search.solve_vertices();
            let records = vertex_records(&solve_vertices);
            if records.len() != object.vertex_count || search.triangles().len() != object.faces {
                return Err(SpecularError::Mismatch(format!(
                    "a search object of {} vertices and {} faces prepared with a search of {} and {}",
                    object.vertex_count,
                    object.faces,
                    records.len(),
                    search.triangles().len()
                )));
            }
            if !records.is_empty() {
                queue.write_buffer(&object.vertices, 0, bytemuck::cast_slice(&records));
                // The new pose's per-face slack, which the per-face test reads, and its
                // cones and spheres, over the mesh's fixed face order.
                let (order, margins) = (&object.face_order, search.face_margins());
                let triangles = ordered_triangles(search, &margins, order);
                queue.write_buffer(&object.triangles, 0, bytemuck::cast_slice(&triangles));
                let clusters =
                    clusters::cluster_records(search.triangles(), &margins, &solve_vertices, order);
                if !clusters.is_empty() {
                    queue.write_buffer(&object.clusters, 0, bytemuck::cast_slice(&clusters));
                }
                let field = field_records(search);
                if field.len() == object.vertex_count {
                    queue.write_buffer(&object.field, 0, bytemuck::cast_slice(&field));
                }
            }
            object.search_id = search.id();
        }
        let frame = search.solve_frame(input.light_eye, input.world_from_object);
        let peaks = peak_sigma
            .filter(|s| *s > 0.0 && object.peaks.is_some())
            .map(|s| peaks::peak_params(s, input.light_eye, input.world_from_object));
        let looks = peaks.as_ref().map(|q| q.sigma);
        let params = params_of(
            frame,
            (object.faces, object.capacity),
            self.row,
            (search, input.world_from_object),
            peaks,
        );
        let (device, layout) = (&self.device, &self.layout);
        let (adjacency, scratch) = match &object.peaks {
            Some(t) => (&t.adjacency, &t.scratch),
            None => (&object.empty[0], &object.empty[1]),
        };
        let tables = [
            &object.vertices,
            &object.triangles,
            &object.order,
            &object.clusters,
            &object.field,
            adjacency,
            scratch,
        ];
        let sizes = (object.capacity, object.faces.div_ceil(CLUSTER_FACES));
        let dispatch_layout = &self.dispatch_layout;
        let centres_layouts = [&self.centres_layouts[0], &self.centres_layouts[1]];
        let (prepared, slot) = object.slots.next(self.id, input.frame, || {
            make_slot(
                device,
                [layout, dispatch_layout],
                centres_layouts,
                tables,
                sizes,
            )
        })?;
        queue.write_buffer(&slot.frame, COUNTER_BYTES, bytemuck::bytes_of(&params));
        slot.active = frame.is_some();
        slot.peaks = looks;
        Ok(prepared)
    }

    /// One frame's search at once (native; the browser maps and polls instead): prepare,
    /// record in an encoder of its own, submit, and read the accepted faces back, waiting
    /// for the GPU. For callers whose frame waits on the list anyway (the app's GPU
    /// search, benches, measures).
    ///
    /// # Errors
    /// As [`CentreSearchPass::prepare`] and [`SearchObject::read`].
    pub fn search_now(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        object: &mut SearchObject,
        input: &SearchInput<'_>,
    ) -> Result<SearchSolutions, SpecularError> {
        let prepared = self.prepare(queue, object, input)?;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("npr centre search"),
        });
        self.record(&mut encoder, object, &prepared)?;
        queue.submit([encoder.finish()]);
        object.read(device, &prepared)
    }

    /// Records the search: the counter cleared, the clusters listed, one invocation per
    /// face of theirs, the merge, the centres and (where prepared for them) the peaks,
    /// and the counts, list and centres copied for [`SearchObject::read`].
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a `prepared` of another pass, object or frame; nothing
    /// is recorded then.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: &SearchObject,
        prepared: &Prepared,
    ) -> Result<(), SpecularError> {
        self.record_with(encoder, object, prepared, true)
    }

    /// [`CentreSearchPass::record`] without the copies for [`SearchObject::read`]: for a
    /// frame whose centres are read on the GPU alone ([`crate::gpu::FrameOnGpu`]).
    ///
    /// # Errors
    /// As [`CentreSearchPass::record`].
    pub fn record_on_gpu(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: &SearchObject,
        prepared: &Prepared,
    ) -> Result<(), SpecularError> {
        self.record_with(encoder, object, prepared, false)
    }

    fn record_with(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        object: &SearchObject,
        prepared: &Prepared,
        readback: bool,
    ) -> Result<(), SpecularError> {
        let slot = object.slots.get(self.id, prepared)?;
        encoder.clear_buffer(&slot.frame, 0, Some(COUNTER_BYTES));
        encoder.clear_buffer(&slot.dispatch, 0, None);
        encoder.clear_buffer(&slot.listed, 0, None);
        if slot.active {
            let max = self.device.limits().max_compute_workgroups_per_dimension;
            let (x, y) = dispatch_size(object.cluster_count(), max);
            // Two passes: the dispatch buffer is written as storage by the first and read
            // as the second's indirect arguments.
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("npr centre search clusters"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&self.clusters_pipeline);
                pass.set_bind_group(0, &slot.group, &[]);
                pass.set_bind_group(1, &slot.dispatch_group, &[]);
                pass.dispatch_workgroups(x, y, 1);
            }
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("npr centre search"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &slot.group, &[]);
            pass.dispatch_workgroups_indirect(&slot.dispatch, 0);
            pass.set_pipeline(&self.merge_pipeline);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(&self.centres_pipeline);
            pass.set_bind_group(0, &slot.centres_groups[0], &[]);
            pass.set_bind_group(1, &slot.centres_groups[1], &[]);
            pass.dispatch_workgroups(MAX_MERGED.div_ceil(64) as u32, 1, 1);
            drop(pass);
            if let Some(tables) = object.peaks.as_ref().filter(|_| slot.peaks.is_some()) {
                tables.clear(encoder);
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("npr centre search peaks"),
                    timestamp_writes: None,
                });
                pass.set_bind_group(0, &slot.centres_groups[0], &[]);
                pass.set_bind_group(1, &slot.centres_groups[1], &[]);
                let (x, y) = dispatch_size(tables.vertices, max);
                for p in &self.vertex_pipelines {
                    pass.set_pipeline(p);
                    pass.dispatch_workgroups(x, y, 1);
                }
                pass.set_pipeline(&self.peaks_pipeline);
                pass.dispatch_workgroups(1, 1, 1);
            }
        }
        if !readback {
            return Ok(());
        }
        // The header: faces accepted, clusters listed (`Dispatch::count`), centres
        // merged; then the accepted faces and the centres' records.
        let entries = object.capacity as u64 * 16;
        encoder.copy_buffer_to_buffer(&slot.frame, 0, &slot.readback, 0, 4);
        encoder.copy_buffer_to_buffer(&slot.dispatch, 12, &slot.readback, 4, 4);
        encoder.copy_buffer_to_buffer(&slot.frame, 4, &slot.readback, 8, 8);
        encoder.copy_buffer_to_buffer(&slot.solutions, 0, &slot.readback, 16, entries);
        encoder.copy_buffer_to_buffer(
            &slot.records,
            0,
            &slot.readback,
            16 + entries,
            (readback::CENTRE_RECORD_BYTES * MAX_MERGED) as u64,
        );
        Ok(())
    }
}

impl SearchObject {
    /// The buffers a pose's tables go to ([`crate::gpu::ReposePass`]): the vertices, the
    /// faces in the search's order, the clusters and the field.
    pub(crate) fn pose_tables(&self) -> [&wgpu::Buffer; 4] {
        [&self.vertices, &self.triangles, &self.clusters, &self.field]
    }

    /// The order the search visits the faces in (fixed per mesh).
    pub(crate) fn face_order(&self) -> &[u32] {
        &self.face_order
    }

    /// The counter and centre records of `prepared`'s slot, for the tracking that reads
    /// them in the same submission (`tracking.wgsl`).
    pub(crate) fn centre_buffers(
        &self,
        prepared: &Prepared,
    ) -> Result<(&wgpu::Buffer, &wgpu::Buffer), SpecularError> {
        let slot = self.slots.get(self.slots.pass(), prepared)?;
        Ok((&slot.frame, &slot.records))
    }

    /// Accepted faces a frame keeps.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Faces solved per search.
    pub fn face_count(&self) -> usize {
        self.faces
    }

    /// Clusters of faces the search tests as a whole, one workgroup each.
    pub fn cluster_count(&self) -> usize {
        self.faces.div_ceil(CLUSTER_FACES)
    }

    /// Faces a cluster holds (consecutive in the Morton order of their centroids).
    pub const fn cluster_faces() -> usize {
        CLUSTER_FACES
    }

    /// Reads back the faces the search of `prepared` accepted, after the submission that
    /// holds its [`CentreSearchPass::record`]: waits for the GPU, maps the compact list
    /// (16 bytes an entry plus the counter), and decodes it. Native only: in the browser
    /// use [`SearchObject::map`] and poll.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a stale or foreign `prepared`; [`SpecularError::Gpu`]
    /// when the map fails or the device is lost.
    pub fn read(
        &self,
        device: &wgpu::Device,
        prepared: &Prepared,
    ) -> Result<SearchSolutions, SpecularError> {
        Ok(self.map(prepared)?.wait(device)?)
    }

    /// Asks for the map of `prepared`'s list, after the submission that holds its
    /// [`CentreSearchPass::record`], without waiting: [`PendingSolutions::try_take`]
    /// gives it once the map has completed (the browser's way, and a renderer's that reads
    /// results a frame late). Take it before the slot is recorded again.
    ///
    /// # Errors
    /// [`SpecularError::Pass`] for a stale or foreign `prepared`.
    pub fn map(&self, prepared: &Prepared) -> Result<PendingSolutions, SpecularError> {
        let slot = self.slots.get(self.slots.pass(), prepared)?;
        Ok(PendingSolutions {
            map: npr_gpu::BufferReadback::map(slot.readback.clone()),
            capacity: self.capacity,
            peaks: slot.peaks,
        })
    }
}

#[cfg(test)]
mod tests;
