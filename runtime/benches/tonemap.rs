//! `cargo bench -p lightbench --bench tonemap`: seed 003 Table 6.2 style — what tone mapping
//! costs and how much of it the log-average luminance takes, with the one-workgroup reduction
//! (`luminance = single`) against the parallel one (`parallel`: tiles, then the tiles), on the
//! Cornell box at three resolutions. Needs a GPU adapter (lavapipe is enough); `cargo test`
//! runs it at its smallest (64², one round).
//! Every pass runs every frame, GPU ms from timestamps; the two options run in interleaved
//! rounds of a frame each, and the ratio is the median [quartiles] of the per-round single /
//! parallel of the reduction's cost. Then what FXAA (`aa = fxaa`, seed 003 §3.3) and TAA
//! (`aa = taa`) cost per frame at the same resolutions, beside the tone mapping they follow
//! (the per-frame ratio's median [quartiles]).

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::scene::builtin;
use std::path::Path;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{interleaved, load_line, quartiles, Paired, Size};

/// An executor of `deferred.ron` with these variants at this size, every pass every frame,
/// warmed by a frame.
fn executor(gpu: &Gpu, size: (u32, u32), variants: &[(&str, &str)]) -> Executor {
    let mut scene = builtin::cornell();
    scene.size = size;
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
    let variants: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let (exe, _) = lightbench::render::compile(gpu, &pipeline, None, &scene, &variants).unwrap_or_else(|e| panic!("{e}"));
    let mut ex = Executor::new(gpu, &exe, &scene).expect("executor");
    ex.set_reuse(false);
    ex.render_frame(gpu, &ex.inputs(0.0)).expect("warm-up frame");
    ex
}

/// One frame: (reduction GPU ms, tone-mapping pass GPU ms, anti-aliasing pass GPU ms).
fn frame(gpu: &Gpu, ex: &mut Executor, f: u32) -> (f64, f64, f64) {
    ex.render_frame(gpu, &ex.inputs(f as f32 / 60.0)).expect("frame");
    let (mut reduce, mut tonemap, mut aa) = (0.0, 0.0, 0.0);
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
    (reduce, tonemap, aa)
}

fn median(v: &[f64]) -> f64 {
    quartiles(v.to_vec()).1
}

fn main() {
    let run = Size::from_args();
    let (sizes, rounds) = (
        run.pick(vec![(256, 256), (1024, 1024), (2048, 2048)], vec![(64, 64)]),
        run.pick(8, 1),
    );
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter");
    println!("{}\n{}", gpu.describe(), load_line());
    println!("log-average luminance + tone mapping, Cornell box, GPU ms per frame (medians of {rounds} interleaved rounds)");
    println!(
        "{:>11} {:>12} {:>12} {:>12} {:>28}",
        "size", "single ms", "parallel ms", "tonemap ms", "single/parallel [quartiles]"
    );
    for &size in &sizes {
        let (mut single, mut parallel) = (
            executor(&gpu, size, &[("luminance", "single")]),
            executor(&gpu, size, &[("luminance", "parallel")]),
        );
        let mut tone = vec![];
        let (mut fs, mut fp) = (0, 0);
        let p = interleaved(
            rounds,
            || {
                fp += 1;
                frame(&gpu, &mut parallel, fp).0
            },
            || {
                fs += 1;
                let (reduce, t, _) = frame(&gpu, &mut single, fs);
                tone.push(t);
                reduce
            },
        );
        let (q1, r, q3) = p.ratio();
        println!(
            "{:>11} {:>12.3} {:>12.3} {:>12.3} {:>28}",
            format!("{}x{}", size.0, size.1),
            median(&p.b),
            median(&p.a),
            median(&tone),
            format!("{r:.2}× [{q1:.2}–{q3:.2}]")
        );
    }
    for aa in ["fxaa", "taa"] {
        println!("{} (aa = {aa}), GPU ms per frame (medians of {rounds} frames)", aa.to_uppercase());
        println!(
            "{:>11} {:>12} {:>10} {:>24}",
            "size", "tonemap ms", "aa ms", "aa/tonemap [quartiles]"
        );
        for &size in &sizes {
            let mut ex = executor(&gpu, size, &[("aa", aa)]);
            let (tone, ms): (Vec<f64>, Vec<f64>) = (1..=rounds as u32).map(|f| frame(&gpu, &mut ex, f)).map(|(_, t, a)| (t, a)).unzip();
            let (q1, r, q3) = Paired {
                a: tone.clone(),
                b: ms.clone(),
            }
            .ratio();
            println!(
                "{:>11} {:>12.3} {:>10.3} {:>24}",
                format!("{}x{}", size.0, size.1),
                median(&tone),
                median(&ms),
                format!("{r:.2}× [{q1:.2}–{q3:.2}]")
            );
        }
    }
}
