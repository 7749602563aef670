// The highlights of an update as the GPU keeps them from frame to frame (its piece 0
// each, in id order), composed before the shaders that read or write the table:
// `tracking.wgsl` matches this frame's centres with them, `projectors.wgsl` builds this
// frame's projectors from them and writes the next table. The CPU writes the same table
// from its own update (`HighlightSet`'s highlights) where it keeps them.

// One highlight: its centre (object space) and its reach for the next frame's matching
// (`match_centres`'s, at least twice the mean edge); its σ (x); its centre as last
// placed (world frame of that update, or of this one where the CPU placed it again:
// slot `NONE`), footprint (half extents, offset; rotation, region area, normal cone,
// fit scale), state (id, found, peak, pieces) and opacity (x).
struct TrackedHighlight {
    position_reach: vec4<f32>,
    sigma: vec4<f32>,
    centre: CentreRecord,
    footprint: vec4<f32>,
    shape: vec4<f32>,
    state: vec4<u32>,
    fade: vec4<f32>,
}

struct TrackParams {
    // Highlights in `previous` (at most `MAX_TRACKED` are matched).
    count: u32,
    // Seeds the growth had room for, and σ of a new highlight (the global controls'), as
    // the frame that wrote the table had them; `cs_track` reads this frame's from
    // `RegionParams` (`track_room`, `track_sigma`).
    room: u32,
    sigma: f32,
    // 1 once a frame has been drawn (new highlights then fade in).
    tracking: u32,
    // The id the next new highlight takes.
    next_id: u32,
    // Projectors the frame drew (pieces included), and the centres suppressed (merged
    // away) in it.
    drawn: u32,
    merged: u32,
    // 0: built on the GPU; 1: the frame's regions could not be seeded, so its highlights
    // were held as they were; 2: more projectors than `MAX_DRAWN`; 3: a region's walk was
    // cut short at its queue's capacity (fitted from what it walked); 4: the search could
    // not find the frame's peaks (drawn without them).
    status: u32,
}

// The table and its size in one storage buffer (not a uniform one; see
// `RegionFrameData`).
struct TrackData {
    params: TrackParams,
    previous: array<TrackedHighlight>,
}
