//! A process-wide GPU context for tests, and the rule for what a test does without one.
//!
//! Under `cargo xtask test` (which sets `NPR_REQUIRE_GPU=1` after making sure a driver is
//! installed) a GPU test that finds no adapter FAILS. Elsewhere (plain `cargo test`) it
//! prints why and returns early (a skip).

use crate::GpuContext;
use std::sync::OnceLock;

/// Environment variable that makes a missing adapter a test failure.
pub const REQUIRE_GPU_ENV: &str = "NPR_REQUIRE_GPU";

static CONTEXT: OnceLock<Result<GpuContext, String>> = OnceLock::new();

/// The shared context, created on first use (one device per test process).
///
/// # Errors
/// The message of the [`crate::GpuError`] that creating it returned.
pub fn shared_context() -> Result<&'static GpuContext, &'static str> {
    CONTEXT
        .get_or_init(|| {
            let ctx = GpuContext::new().map_err(|e| e.to_string())?;
            eprintln!("npr-gpu tests: adapter {}", ctx.adapter_summary());
            Ok(ctx)
        })
        .as_ref()
        .map_err(String::as_str)
}

/// The shared context for a GPU test, or `None` after printing why the test is skipped.
///
/// # Panics
/// When no adapter exists and [`REQUIRE_GPU_ENV`] is set to `1` (as `cargo xtask test`
/// does): there a missing GPU is a failure, not a skip.
pub fn context_or_skip(test: &str) -> Option<&'static GpuContext> {
    match shared_context() {
        Ok(ctx) => Some(ctx),
        Err(e) => {
            if std::env::var(REQUIRE_GPU_ENV).is_ok_and(|v| v == "1") {
                panic!("{test}: {REQUIRE_GPU_ENV}=1 but no GPU adapter: {e}");
            }
            eprintln!(
                "SKIPPED {test}: no GPU adapter ({e}); run `cargo xtask test` to install one"
            );
            None
        }
    }
}
