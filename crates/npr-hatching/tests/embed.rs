//! The README's embedding example (`examples/embed.rs`, included here as a module) gives
//! the CPU reference's image: `CpuHatcher` on the same inputs and parameters, within the
//! bound of `gpu_hatching_equals_cpu_reference` (mean |difference| ≤ 0.25 code values, at
//! most 0.5 % of pixels off by more than 2).
#![allow(clippy::unwrap_used, clippy::expect_used)]

#[allow(dead_code)]
#[path = "../examples/embed.rs"]
mod embed;

use npr_hatching::{CpuHatcher, HatchParams, TamParams, TonalArtMap};

#[test]
fn embed_example_matches_the_cpu_reference() {
    let Some(ctx) = npr_gpu::testing::context_or_skip("embed_example_matches_the_cpu_reference")
    else {
        return;
    };
    let (w, h) = (320, 240);
    let gpu = embed::render(&ctx.device, &ctx.queue, w, h).unwrap();
    let tam = TonalArtMap::generate(&TamParams::pen()).unwrap();
    let cpu = CpuHatcher::new(&tam, &HatchParams::default())
        .unwrap()
        .hatch_rgba8(&embed::inputs(w, h).unwrap())
        .unwrap();
    assert_eq!(gpu.dimensions(), cpu.dimensions());
    let (mut sum, mut bad) = (0u64, 0usize);
    for (p, q) in gpu.pixels().zip(cpu.pixels()) {
        let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0);
        sum += u64::from(d);
        bad += usize::from(d > 2);
    }
    let n = f64::from(w * h);
    let (mean, frac) = (sum as f64 / n, bad as f64 / n);
    assert!(
        mean <= 0.25 && frac <= 0.005,
        "mean {mean}, fraction {frac}"
    );
    // And it is hatching: dark on the left, paper on the right.
    let dark = |x0: u32| {
        (0..h)
            .map(|y| u32::from(gpu.get_pixel(x0, y)[0]))
            .sum::<u32>()
            / h
    };
    assert!(
        dark(5) < 100 && dark(w - 5) > 200,
        "{} {}",
        dark(5),
        dark(w - 5)
    );
}
