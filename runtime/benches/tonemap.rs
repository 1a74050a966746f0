//! `cargo bench -p lightbench --bench tonemap`: seed 003 Table 6.2 style — what tone mapping
//! costs and how much of it the log-average luminance takes, with the one-workgroup reduction
//! (`luminance = single`) against the parallel one (`parallel`: tiles, then the tiles), on the
//! Cornell box at three resolutions. Needs a GPU adapter (lavapipe is enough); `cargo test`
//! runs it at its smallest (64², a frame each).
//! Every pass runs every frame; figures are GPU-ms means over the frames after a warm-up, and
//! the ratio is single / parallel of the reduction's cost. Then what FXAA (`aa = fxaa`, seed
//! 003 §3.3) and TAA (`aa = taa`) cost per frame at the same resolutions, beside the tone
//! mapping they follow.

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::scene::builtin;
use std::path::Path;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::Size;

/// (reduction GPU ms, tone-mapping pass GPU ms, anti-aliasing pass GPU ms) per frame.
fn measure(gpu: &Gpu, size: (u32, u32), variants: &[(&str, &str)], frames: u32) -> (f64, f64, f64) {
    let mut scene = builtin::cornell();
    scene.size = size;
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
    let variants: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let (exe, _) = lightbench::render::compile(gpu, &pipeline, None, &scene, &variants).unwrap_or_else(|e| panic!("{e}"));
    let mut ex = Executor::new(gpu, &exe, &scene).expect("executor");
    ex.set_reuse(false);
    ex.render_frame(gpu, &ex.inputs(0.0)).expect("warm-up frame");
    let (mut reduce, mut tonemap, mut aa) = (0.0, 0.0, 0.0);
    for f in 1..=frames {
        ex.render_frame(gpu, &ex.inputs(f as f32 / 60.0)).expect("frame");
        for t in &ex.last_timings {
            let ms = t.gpu_ms.unwrap_or(f64::NAN);
            if t.pass.starts_with("luminance") {
                reduce += ms;
            } else if t.pass.starts_with("tonemap") {
                tonemap += ms;
            } else if t.pass == "fxaa" || t.pass == "taa" {
                aa += ms;
            }
        }
    }
    let f = frames as f64;
    (reduce / f, tonemap / f, aa / f)
}

fn main() {
    let run = Size::from_args();
    let (sizes, frames) = (
        run.pick(vec![(256, 256), (1024, 1024), (2048, 2048)], vec![(64, 64)]),
        run.pick(5, 1),
    );
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter");
    println!("{}", gpu.describe());
    println!("log-average luminance + tone mapping, Cornell box, GPU ms per frame (mean of {frames} after a warm-up)");
    println!(
        "{:>11} {:>14} {:>14} {:>12} {:>16}",
        "size", "single ms", "parallel ms", "tonemap ms", "single/parallel"
    );
    for &size in &sizes {
        let (single, tone, _) = measure(&gpu, size, &[("luminance", "single")], frames);
        let (parallel, _, _) = measure(&gpu, size, &[("luminance", "parallel")], frames);
        println!(
            "{:>11} {single:>14.3} {parallel:>14.3} {tone:>12.3} {:>15.2}×",
            format!("{}x{}", size.0, size.1),
            single / parallel
        );
    }
    for aa in ["fxaa", "taa"] {
        println!("{} (aa = {aa}), GPU ms per frame", aa.to_uppercase());
        println!("{:>11} {:>12} {:>10} {:>16}", "size", "tonemap ms", "aa ms", "aa/tonemap");
        for &size in &sizes {
            let (_, tone, ms) = measure(&gpu, size, &[("aa", aa)], frames);
            println!(
                "{:>11} {tone:>12.3} {ms:>10.3} {:>15.2}×",
                format!("{}x{}", size.0, size.1),
                ms / tone
            );
        }
    }
}
