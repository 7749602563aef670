//! The browser check's compute step: the curvature, `N = H`, region and §4.2 receiver
//! compute passes run on the page's own WebGPU device and compared with the CPU in the page.

use super::Driver;
use anyhow::{Context as _, bail};

/// The compute passes on the page's own device (`ComputeCheck::start` of the check's
/// build, `crates/npr-web/check`): the
/// curvature tensor and the `N = H` search on a torus, read back over the next animation
/// frames and compared with the CPU in the page. The search must give the CPU's centres
/// within 1e-4 of the bounding radius, merged on the GPU into the very entries the CPU's
/// merge of its faces keeps, the curvature the CPU's within the native bounds
/// (1e-3 of the robust largest |κ|, 0.5° for directions and normals, the same validity),
/// the receivers the CPU's on at least 99.5 % of the faces either received, and the
/// regions of the CPU's centres the CPU's outcomes, faces and moment ellipses (centres
/// within 1e-3 of the radius, areas within 0.5 %). On a knot, four frames of the knot swaying made wholly on the GPU, each pose included
/// (`FrameOnGpu` with `pose_on_gpu`: curvature and tables from the posed vertex buffer,
/// nothing read back between) must be the CPU's reposes and updates (ids, found, peaks, opacities; centres within 1e-4 of the radius,
/// the wholes' records within 2e-3: `tests/gpu_projectors.rs`).
pub(super) fn check(driver: &Driver, session: &str) -> anyhow::Result<()> {
    let result = driver.script_async(
        session,
        "const done = arguments[arguments.length - 1];
         try {
           const check = window.nprModule.ComputeCheck.start(window.nprViewer);
           const poll = () => {
             try {
               const r = check.result(window.nprViewer);
               if (r) { done(JSON.parse(r)); } else { requestAnimationFrame(poll); }
             } catch (e) { done({ error: String(e) }); }
           };
           requestAnimationFrame(poll);
         } catch (e) { done({ error: String(e) }); }",
    )?;
    if let Some(e) = result.get("error") {
        bail!("the compute check in the page: {e}");
    }
    let num = |key: &str| {
        result[key]
            .as_f64()
            .with_context(|| format!("the compute check has no {key}: {result}"))
    };
    let (kappa, direction) = (
        num("curvature_kappa_error")?,
        num("curvature_direction_error_deg")?,
    );
    let (validity, vertices) = (
        num("curvature_validity_differences")?,
        num("curvature_vertices")?,
    );
    let normal = num("curvature_normal_error_deg")?;
    let (cpu, gpu, centre) = (
        num("centres_cpu")?,
        num("centres_gpu")?,
        num("centre_error_of_radius")?,
    );
    let (merge_differs, accepted) = (
        num("centres_merge_differs")?,
        num("centres_accepted_faces")?,
    );
    let (walked, agreement, overflowed) = (
        num("receivers_cpu_faces")?,
        num("receivers_agreement")?,
        num("receivers_overflowed")?,
    );
    let (fitted, differ) = (num("regions_cpu_fitted")?, num("regions_outcomes_differ")?);
    let (region_centre, region_area) = (
        num("regions_centre_error_of_radius")?,
        num("regions_area_error")?,
    );
    let region_overflow = num("regions_overflowed")?;
    let flag = |key: &str| {
        result[key]
            .as_bool()
            .with_context(|| format!("the compute check has no {key}: {result}"))
    };
    let frames_same = flag("frame_highlights_same")?;
    let (frames, frame_highlights, frame_peaks) = (
        num("frame_frames")?,
        num("frame_highlights")?,
        num("frame_peaks")?,
    );
    let (frame_centre, frame_gap) = (
        num("frame_centre_error_of_radius")?,
        num("frame_record_gap")?,
    );
    println!(
        "xtask: compute passes in Chromium: curvature within {kappa:.2e} of the largest |κ| and \
         {direction:.3}° (normals {normal:.3}°) over {vertices} vertices; {gpu} GPU centres against {cpu} CPU \
         (merged on the GPU from {accepted} faces), within {centre:.2e} of the radius; receivers agree on {:.2} % of {walked} faces; \
         {fitted} regions fitted as the CPU's, {differ} apart, ellipse centres within \
         {region_centre:.2e} of the radius, areas within {:.3} %; {frames} frames of a knot swaying made \
         wholly on the GPU, poses included: {frame_highlights} highlights ({frame_peaks} peaks), the CPU's: \
         {frames_same}, centres within {frame_centre:.2e} of the radius, records within \
         {frame_gap:.2e}",
        100.0 * agreement,
        100.0 * region_area
    );
    if vertices < 1.0 {
        bail!("the page measured no curvature: {result}");
    }
    // The native bounds of the curvature test (`npr-gpu/tests/curvature.rs`).
    if validity > 0.0 || kappa > 1e-3 || direction > 0.5 || normal > 0.5 {
        bail!(
            "the page's GPU curvature differs from the CPU's beyond the native bounds \
             (1e-3 of the largest |κ|, 0.5°): {result}"
        );
    }
    if cpu < 1.0 || gpu != cpu || centre > 1e-4 || merge_differs > 0.0 {
        bail!("the page's GPU N = H search differs from the CPU's: {result}");
    }
    // The native bound of `npr-specular/tests/gpu_receivers.rs`.
    if walked < 1.0 || agreement < 0.995 || overflowed > 0.0 {
        bail!("the page's GPU receivers differ from the CPU's: {result}");
    }
    // The native bounds of `npr-specular/tests/gpu_regions.rs`.
    if fitted < 1.0
        || differ > 0.0
        || region_overflow > 0.0
        || region_centre > 1e-3
        || region_area > 5e-3
    {
        bail!("the page's GPU regions differ from the CPU's: {result}");
    }
    // The native bounds of `npr-specular/tests/gpu_projectors.rs`.
    if !frames_same
        || frames < 4.0
        || frame_highlights < 1.0
        || frame_peaks < 1.0
        || frame_centre > 1e-4
        || frame_gap > 2e-3
    {
        bail!("the page's frames made on the GPU differ from the CPU's updates: {result}");
    }
    Ok(())
}
