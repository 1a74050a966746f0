//! `cargo bench -p lightbench --bench watch`: hot-reload latency as a user feels it — from
//! writing a shader file to the first completed frame with the new Plan — over 60 edits of
//! the tone-map shader of `pipelines/deferred.ron` on the Cornell box (128×128), p50 and p95,
//! beside the frame time; and the share of it spent compiling. Goal: p95 ≤ 50 ms beyond one
//! frame. The debouncer's quiet time (`reload::DEBOUNCE`, 30 ms) is part of the latency.
//! Needs a GPU adapter (lavapipe is enough); `cargo test` runs it at its smallest (2 edits).

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::reload::{Outcome, Reloader, DEBOUNCE};
use lightbench::scene::builtin;
use std::time::{Duration, Instant};

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{load_line, Size};

fn percentile(v: &mut [f64], p: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p).round() as usize]
}

fn main() {
    let edits = Size::from_args().pick(60, 2);
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let dir = std::env::temp_dir().join(format!("lightbench-bench-watch-{}", std::process::id()));
    lightbench::bundled::init(&dir).expect("init");
    let scene = builtin::cornell();
    let (mut reloader, exe) = Reloader::new(&gpu, (&dir.join("pipelines/deferred.ron"), None), (&scene, None), &[]).expect("compile");
    let mut ex = Executor::new(&gpu, &exe, &scene).expect("executor");
    // Each frame waited for: the frame time is a frame's, and "the first completed frame" is.
    ex.set_frames_in_flight(0);
    let frame = |ex: &mut Executor| {
        let inputs = ex.inputs(0.0);
        ex.render_frame(&gpu, &inputs).expect("frame");
    };
    let start = Instant::now();
    for _ in 0..20 {
        frame(&mut ex);
    }
    let frame_ms = start.elapsed().as_secs_f64() * 1e3 / 20.0;
    let tonemap = dir.join("shaders/tonemap.wgsl");
    let text = std::fs::read_to_string(&tonemap).expect("tonemap");
    let (mut latency, mut compile, mut swap) = (vec![], vec![], vec![]);
    for i in 0..edits {
        let edited = text.replace(
            "vec3<f32>(1.0)), 1.0);",
            &format!("vec3<f32>(1.0)) * {:.3}, 1.0);", 0.5 + i as f32 * 0.005),
        );
        let written = Instant::now();
        std::fs::write(&tonemap, edited).expect("write");
        loop {
            match reloader.poll(&gpu, &mut ex, Duration::from_millis(5)) {
                Some(Outcome::Reloaded {
                    compile: c,
                    latency: l,
                    report,
                    ..
                }) => {
                    swap.push((l.as_secs_f64() * 1e3, report.pipelines_built.len()));
                    frame(&mut ex);
                    latency.push(written.elapsed().as_secs_f64() * 1e3);
                    compile.push(c.as_secs_f64() * 1e3);
                    break;
                }
                Some(Outcome::Failed { message, .. }) => panic!("{message}"),
                Some(Outcome::Rewatched { folders }) => panic!("no folder is replaced here: {folders:?}"),
                None => frame(&mut ex),
            }
        }
    }
    let mean_compile = compile.iter().sum::<f64>() / compile.len() as f64;
    let (p50, p95) = (percentile(&mut latency.clone(), 0.5), percentile(&mut latency, 0.95));
    println!(
        "hot reload, {edits} edits of shaders/tonemap.wgsl, Cornell box 128×128 ({}):",
        load_line()
    );
    println!("  frame time            {frame_ms:>7.1} ms");
    println!(
        "  write → new frame     p50 {p50:>6.1} ms   p95 {p95:>6.1} ms   (debounce {} ms included)",
        DEBOUNCE.as_millis()
    );
    println!("  p95 beyond one frame  {:>7.1} ms   (goal ≤ 50 ms)", p95 - frame_ms);
    println!(
        "  compiling             {mean_compile:>7.1} ms on average = {:.0}% of the p50",
        100.0 * mean_compile / p50
    );
    let to_swap = swap.iter().map(|s| s.0).sum::<f64>() / swap.len() as f64;
    println!(
        "  first event → swap    {to_swap:>7.1} ms on average (compile, then building {} changed pipeline(s): on lavapipe LLVM compiles each)",
        swap[0].1
    );
    // What dominates a reload as felt (medians): from the file event the watcher waits out
    // the debounce, compiles, builds the changed pipelines and swaps; before the event, the
    // file system's notice; after the swap, the frame.
    let median = |v: &mut Vec<f64>| percentile(v, 0.5);
    let (event_to_swap, compiling) = (median(&mut swap.iter().map(|s| s.0).collect()), median(&mut compile.clone()));
    let debounce = DEBOUNCE.as_secs_f64() * 1e3;
    println!(
        "  of the p50: debounce {debounce:.0} ms, compile {compiling:.1} ms, pipeline build and swap {:.1} ms, before the event and the frame after {:.1} ms",
        event_to_swap - debounce - compiling,
        p50 - event_to_swap
    );
    let _ = std::fs::remove_dir_all(&dir);
}
