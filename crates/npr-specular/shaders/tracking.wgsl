// Frame coherence on the GPU (beyond Lee & Choi): this frame's centres, as the search
// computed them (`cs_centres` of `centre_search.wgsl`), matched with the last update's
// highlights as the CPU matches them (`HighlightSet::match_centres`: closest pairs
// first, each highlight within its reach), then written as the region growth's seeds in
// the order the CPU grows them (the matched centres in their highlights' id order, then
// the new ones in the search's order, which is the order of the ids they are given), so
// that a frame's regions are grown in the search's submission, with no readback between
// (`regions.wgsl`, dispatched indirectly over the seeds written here). The centres are
// the merged ones, then the peaks (bright regions without an `N = H` point) where the
// search found them (`cs_peaks`); each highlight is matched first with a centre of its
// own kind, as the CPU's sort puts those pairs first. Where the search found no peaks the update finds its own, and
// the caller compares the seeds with its own and grows a frame that differs again.

@group(0) @binding(0) var<storage, read_write> frame: RegionFrameData;
@group(0) @binding(1) var<storage, read> centres: array<CentreRecord>;
// The search's `Counter`: (faces accepted, centres merged or `NO_MERGE`, peaks after them
// or `NO_MERGE`).
@group(0) @binding(2) var<storage, read> search_counts: array<u32>;
@group(0) @binding(3) var<storage, read> track: TrackData;
// The growth's indirect dispatch (x, y, z), then the status: 0 seeded, 1 more seeds than
// the room, 2 no merged list; then the highlights and centres matched, the merged
// centres among them and the peaks after them (`NONE`: not found), and from `MATCH_AT`
// per highlight the centre it took.
@group(0) @binding(4) var<storage, read_write> dispatch: array<u32>;
const MATCH_AT: u32 = 8u;
// The highlights whose σ the user set (`HighlightControls::sigma`): their count (x of
// the first entry), then (id, σ bits) sorted by id. Any other highlight takes the global
// σ (`RegionParams::track_sigma`, this frame's): a table the GPU wrote a frame ago holds
// the σ of that frame.
@group(0) @binding(5) var<storage, read> own_sigma: array<vec2<u32>>;

// Highlight `id`'s σ this frame.
fn sigma_of(id: u32) -> f32 {
    var lo = 1u;
    var hi = own_sigma[0].x + 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if own_sigma[mid].x < id {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    if lo < own_sigma[0].x + 1u && own_sigma[lo].x == id {
        return bitcast<f32>(own_sigma[lo].y);
    }
    return frame.params.track_sigma;
}

const TRACK_WORKGROUP: u32 = 256u;
// `MAX_MERGED` of the search: its centres.
const MAX_CENTRES: u32 = 256u;
// Highlights of the last update matched at most (`MAX_TRACKED` of `tracking.rs`).
const MAX_TRACKED: u32 = 256u;
const NONE: u32 = 0xffffffffu;

// Per highlight of the last update, the centre it took (or `NONE`); per centre, 1 once
// taken; this round's least distance (bits) and least pair; the seeds' centres and σ.
var<workgroup> centre_of: array<u32, MAX_TRACKED>;
var<workgroup> taken: array<u32, MAX_CENTRES>;
var<workgroup> round_distance: atomic<u32>;
var<workgroup> round_pair: atomic<u32>;
var<workgroup> round_best: u32;
var<workgroup> centre_count: u32;
var<workgroup> merged_count: u32;
var<workgroup> seed_centre: array<u32, MAX_CENTRES>;
var<workgroup> seed_sigma: array<f32, MAX_CENTRES>;

fn centre_valid(j: u32) -> bool {
    return centres[j].position_object.w == 1.0;
}

// Highlight `i`'s distance to centre `j` (object space), or −1 where the pair is not
// free, out of reach, or of the other phase (`across`: 0 a highlight and a centre of one
// kind, both of an `N = H` point or both peaks; 1 of different kinds).
fn free_pair(i: u32, j: u32, across: u32) -> f32 {
    if centre_of[i] != NONE || taken[j] != 0u || !centre_valid(j) {
        return -1.0;
    }
    let was_peak = track.previous[i].state.z != 0u;
    if ((j >= merged_count) != was_peak) != (across == 1u) {
        return -1.0;
    }
    let h = track.previous[i].position_reach;
    let d = length(h.xyz - centres[j].position_object.xyz);
    if d <= h.w {
        return d;
    }
    return -1.0;
}

// The seed of centre `j` at σ (`seed_records` of `region_pass.rs`): its frame from the
// world normal and the direction of κmax, covered when an earlier seed with a frame
// starts on its face. `k` is its place among the seeds.
fn write_seed(k: u32, j: u32, sigma: f32) {
    let c = centres[j];
    let face = c.solution.x;
    var s: Seed;
    // A seed without a frame grows nothing; its centre and σ still say which it is.
    s.origin = vec4<f32>(c.position_world.xyz, sigma);
    s.start = vec4<u32>(NONE, 0u, j, face);
    let n = try_normalize(c.normal_world.xyz);
    let d = c.dir_kappa_max.xyz;
    let e_u = try_normalize(d - n.xyz * dot(n.xyz, d));
    if n.w == 1.0 && e_u.w == 1.0 {
        var covered = 0u;
        if face < frame.params.face_count {
            for (var m = 0u; m < k; m += 1u) {
                let o = frame.seeds[m].start;
                if o.x == face && frame.seeds[m].n.w == 1.0 {
                    covered = 1u;
                }
            }
        }
        s.n = vec4<f32>(n.xyz, 1.0);
        s.e_u = vec4<f32>(e_u.xyz, 0.0);
        s.e_v = vec4<f32>(cross(n.xyz, e_u.xyz), 0.0);
        s.start = vec4<u32>(face, covered, j, face);
    }
    frame.seeds[k] = s;
}

fn finish(count: u32, status: u32) {
    frame.params.seed_count = count;
    dispatch[0] = count;
    dispatch[1] = 1u;
    dispatch[2] = 1u;
    dispatch[3] = status;
}

// One workgroup: the greedy matching (each round, the closest free pair within its
// highlight's reach, ties to the lower highlight then the lower centre, as the CPU's
// stable sort of the pairs; the pairs of one kind first, then those across kinds), then the
// seeds.
@compute @workgroup_size(256)
fn cs_track(@builtin(local_invocation_index) lid: u32) {
    if lid == 0u {
        let merged = search_counts[1];
        let peaks = select(search_counts[2], 0u, search_counts[2] == NONE);
        centre_count = select(min(merged + peaks, MAX_CENTRES), NONE, merged == NONE);
        merged_count = merged;
    }
    let c = workgroupUniformLoad(&centre_count);
    if c == NONE {
        if lid == 0u {
            finish(0u, 2u);
        }
        return;
    }
    let p = min(track.params.count, MAX_TRACKED);
    // Every valid centre is a seed, matched or new: too many for the room, and the frame
    // is refused before any matching.
    if lid == 0u {
        var valid = 0u;
        for (var j = 0u; j < c; j += 1u) {
            valid += select(0u, 1u, centre_valid(j));
        }
        round_best = select(0u, NONE, valid > frame.params.track_room);
    }
    if workgroupUniformLoad(&round_best) == NONE {
        if lid == 0u {
            finish(0u, 1u);
        }
        return;
    }
    centre_of[lid] = NONE;
    taken[lid] = 0u;
    workgroupBarrier();
    for (var phase = 0u; phase < 2u; phase += 1u) {
        loop {
            if lid == 0u {
                atomicStore(&round_distance, NONE);
                atomicStore(&round_pair, NONE);
            }
            workgroupBarrier();
            for (var k = lid; k < p * c; k += TRACK_WORKGROUP) {
                let d = free_pair(k / c, k % c, phase);
                if d >= 0.0 {
                    atomicMin(&round_distance, bitcast<u32>(d));
                }
            }
            workgroupBarrier();
            let best = atomicLoad(&round_distance);
            for (var k = lid; k < p * c; k += TRACK_WORKGROUP) {
                let d = free_pair(k / c, k % c, phase);
                if d >= 0.0 && bitcast<u32>(d) == best {
                    atomicMin(&round_pair, k);
                }
            }
            workgroupBarrier();
            if lid == 0u {
                round_best = atomicLoad(&round_pair);
                if round_best != NONE {
                    centre_of[round_best / c] = round_best % c;
                    taken[round_best % c] = 1u;
                }
            }
            if workgroupUniformLoad(&round_best) == NONE {
                break;
            }
        }
    }
    // The matching, for `projectors.wgsl`: per highlight of the last update the centre
    // it took (or `NONE`).
    dispatch[MATCH_AT + lid] = centre_of[lid];
    if lid != 0u {
        return;
    }
    dispatch[4] = p;
    dispatch[5] = c;
    dispatch[6] = merged_count;
    // The search's peaks (or `NONE`: it could not find them), for `projectors.wgsl`.
    dispatch[7] = search_counts[2];
    var n = 0u;
    for (var i = 0u; i < p; i += 1u) {
        if centre_of[i] != NONE {
            seed_centre[n] = centre_of[i];
            seed_sigma[n] = sigma_of(track.previous[i].state.x);
            n += 1u;
        }
    }
    for (var j = 0u; j < c; j += 1u) {
        if taken[j] == 0u && centre_valid(j) {
            seed_centre[n] = j;
            seed_sigma[n] = frame.params.track_sigma;
            n += 1u;
        }
    }
    if n > frame.params.track_room {
        finish(0u, 1u);
        return;
    }
    for (var k = 0u; k < n; k += 1u) {
        write_seed(k, seed_centre[k], seed_sigma[k]);
    }
    finish(n, 0u);
}
