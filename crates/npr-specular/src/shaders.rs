//! The WGSL of this crate, embedded at compile time from its own `shaders/` directory and
//! composed with the shared snippets of [`npr_gpu::shaders`]. The passes compile
//! [`ShaderFile::full_source`]; the naga validation and uniform-layout tests read the same
//! text.

use npr_gpu::shaders::{COMMON, NUMERIC, ShaderFile};

/// `CentreRecord`, one centre as the GPU search computes it: composed before the search
/// and the tracking.
const CENTRE_RECORD_WGSL: &str = include_str!("../shaders/centre_record.wgsl");
/// `RegionFrameData`, the region growth's values and seeds: composed before the growth
/// and the tracking.
const REGION_FRAME_WGSL: &str = include_str!("../shaders/region_frame.wgsl");

/// `TrackData`, the table of highlights the GPU keeps from frame to frame: composed
/// after `centre_record.wgsl` before the tracking and the projectors.
const HIGHLIGHT_TABLE_WGSL: &str = include_str!("../shaders/highlight_table.wgsl");

/// `ReceiverFrame`, the §4.2 walk's values and queries: composed before the walk and the
/// projectors.
const RECEIVER_FRAME_WGSL: &str = include_str!("../shaders/receiver_frame.wgsl");

/// `receiver_frame.wgsl` itself (structs only, validated alone).
pub const RECEIVER_FRAME: ShaderFile = ShaderFile {
    name: "receiver_frame.wgsl",
    source: RECEIVER_FRAME_WGSL,
    prelude: &[],
};

/// `centre_record.wgsl` itself (structs only, validated alone).
pub const CENTRE_RECORD: ShaderFile = ShaderFile {
    name: "centre_record.wgsl",
    source: CENTRE_RECORD_WGSL,
    prelude: &[],
};

/// `region_frame.wgsl` itself (structs only, validated alone).
pub const REGION_FRAME: ShaderFile = ShaderFile {
    name: "region_frame.wgsl",
    source: REGION_FRAME_WGSL,
    prelude: &[],
};

/// The highlight pass (Eq. (9), §5), after `common.wgsl`.
pub const SPECULAR_HIGHLIGHT: ShaderFile = ShaderFile {
    name: "specular_highlight.wgsl",
    source: include_str!("../shaders/specular_highlight.wgsl"),
    prelude: &[COMMON],
};

/// The `N = H` search (§3.1, Eq. (3)–(6)) as a compute pass, one face per invocation,
/// its merge and its centres, after `numeric.wgsl`, `centre_record.wgsl` and
/// `highlight_table.wgsl`.
pub const CENTRE_SEARCH: ShaderFile = ShaderFile {
    name: "centre_search.wgsl",
    source: include_str!("../shaders/centre_search.wgsl"),
    prelude: &[NUMERIC, CENTRE_RECORD_WGSL, HIGHLIGHT_TABLE_WGSL],
};

/// The §4.2 receivers as a compute pass, one workgroup per highlight's walk, after
/// `receiver_frame.wgsl`.
pub const RECEIVERS: ShaderFile = ShaderFile {
    name: "receivers.wgsl",
    source: include_str!("../shaders/receivers.wgsl"),
    prelude: &[RECEIVER_FRAME_WGSL],
};

/// The regions `N·H ≥ σ` grown and fitted with their moment ellipses as a compute pass,
/// one workgroup per seed, after `numeric.wgsl` and `region_frame.wgsl`.
pub const REGIONS: ShaderFile = ShaderFile {
    name: "regions.wgsl",
    source: include_str!("../shaders/regions.wgsl"),
    prelude: &[NUMERIC, REGION_FRAME_WGSL],
};

/// The search's centres matched with the last update's highlights and written as the
/// region growth's seeds on the GPU, after `numeric.wgsl`, `centre_record.wgsl` and
/// `region_frame.wgsl`.
pub const TRACKING: ShaderFile = ShaderFile {
    name: "tracking.wgsl",
    source: include_str!("../shaders/tracking.wgsl"),
    prelude: &[
        NUMERIC,
        CENTRE_RECORD_WGSL,
        REGION_FRAME_WGSL,
        HIGHLIGHT_TABLE_WGSL,
    ],
};

/// `highlight_table.wgsl` itself, after `centre_record.wgsl` (structs only).
pub const HIGHLIGHT_TABLE: ShaderFile = ShaderFile {
    name: "highlight_table.wgsl",
    source: HIGHLIGHT_TABLE_WGSL,
    prelude: &[NUMERIC, CENTRE_RECORD_WGSL],
};

/// The frame's highlights made into projectors on the GPU (§3.2–§3.4 frame after
/// frame), after `numeric.wgsl`, `centre_record.wgsl`, `region_frame.wgsl`,
/// `highlight_table.wgsl` and `receiver_frame.wgsl`.
pub const PROJECTORS: ShaderFile = ShaderFile {
    name: "projectors.wgsl",
    source: include_str!("../shaders/projectors.wgsl"),
    prelude: &[
        NUMERIC,
        CENTRE_RECORD_WGSL,
        REGION_FRAME_WGSL,
        HIGHLIGHT_TABLE_WGSL,
        RECEIVER_FRAME_WGSL,
    ],
};

/// A pose's tables made on the GPU from the posed vertices and their curvature, after
/// `numeric.wgsl`.
pub const REPOSE: ShaderFile = ShaderFile {
    name: "repose.wgsl",
    source: include_str!("../shaders/repose.wgsl"),
    prelude: &[NUMERIC],
};

/// Every shader file of this crate.
pub const ALL: &[ShaderFile] = &[
    SPECULAR_HIGHLIGHT,
    CENTRE_SEARCH,
    RECEIVERS,
    REGIONS,
    TRACKING,
    PROJECTORS,
    REPOSE,
    CENTRE_RECORD,
    REGION_FRAME,
    HIGHLIGHT_TABLE,
    RECEIVER_FRAME,
];
