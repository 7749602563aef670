//! The tables of `cargo xtask bench warp` (see [`super::warp`]), with their columns.

use super::table::Table;

/// The benchmark's tables, filled as the meshes run.
pub(super) struct Tables {
    /// Tables 1–2: full render vs warped, per mesh, ratio, k, mode and antialiasing.
    pub(super) t1: Table,
    /// Each departure alone, added to the paper's path and removed from ours.
    pub(super) ablation: Table,
    /// The effect of the bin count N.
    pub(super) bins: Table,
    /// Table 3: objects sharing one reference pair.
    pub(super) t3: Table,
    /// Spreading the next reference over the frames between.
    pub(super) spread: Table,
    /// The proxy builds.
    pub(super) proxy: Table,
}

impl Tables {
    /// The empty tables, with their titles and columns.
    pub(super) fn new() -> Self {
        Self {
            t1: Table::new(
                "Tables 1-2: full render vs warped (reference cost amortized), per mesh, ratio, k and mode (paper's path, ours)",
                &[
                    "mesh",
                    "triangles",
                    "ratio_pct",
                    "proxy_triangles",
                    "proxy_error_rel",
                    "k",
                    "mode",
                    "antialiasing",
                    "full_ms",
                    "ref_ms",
                    "warp_ms",
                    "amortized_ms",
                    "speedup_x",
                    "fill_ms",
                    "ceiling_x",
                    "speedup_of_ceiling",
                    "psnr_mean_db",
                    "psnr_worst_db",
                    "ssim_mean",
                    "flip_mean",
                    "flip_worst",
                    "adapter",
                ],
            ),
            ablation: Table::new(
                "Departures from the paper one at a time: added to the paper's path, removed from ours (k = 20, middle ratio)",
                &[
                    "mesh",
                    "variant",
                    "departure",
                    "warp_ms",
                    "psnr_mean_db",
                    "psnr_worst_db",
                    "ssim_mean",
                    "delta_db",
                    "adapter",
                ],
            ),
            bins: Table::new(
                "Effect of the bin count N (§3.3.2), ours, k = 10, middle ratio",
                &[
                    "mesh",
                    "bins_per_axis",
                    "warp_ms",
                    "triangles_drawn",
                    "blended_bins",
                    "psnr_mean_db",
                    "adapter",
                ],
            ),
            t3: Table::new(
                "Table 3: objects sharing one reference pair, ours, k = 10, middle ratio",
                &[
                    "mesh",
                    "objects",
                    "full_ms",
                    "full_ms_per_object",
                    "warp_ms",
                    "amortized_ms",
                    "amortized_ms_per_object",
                    "speedup_x",
                    "psnr_mean_db",
                    "adapter",
                ],
            ),
            spread: Table::new(
                "Spreading the next reference over the k frames (§3.4), ours, k = 10, middle ratio",
                &[
                    "mesh",
                    "spread",
                    "frames",
                    "frame_ms_mean",
                    "frame_ms_worst",
                    "adapter",
                ],
            ),
            proxy: Table::new(
                "Proxy build (meshopt, once per mesh)",
                &[
                    "mesh",
                    "ratio_pct",
                    "proxy_triangles",
                    "error_rel",
                    "error_object",
                    "simplify_ms",
                ],
            ),
        }
    }
}
