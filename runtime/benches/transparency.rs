//! `cargo bench -p lightbench --bench transparency`: seed 003 Table 6.3 style — what
//! compositing blended surfaces costs, drawn far to near by object (`transparency = sorted`),
//! peeled in 4 and 8 layers (`depth_peeling`) and from per-pixel fragment lists
//! (`fragment_lists`: clear, append, sort and blend), on the built-in panes scene at the
//! seed's three resolutions. Needs a GPU adapter (lavapipe is enough); `cargo test` runs it at
//! its smallest (64², a round). Every pass runs every frame. The four setups run in
//! interleaved rounds, a frame each, the order rotating from round to round: figures are the
//! medians of the passes that composite blended surfaces (GPU ms), and the per-round ratios
//! (median and quartiles) of peeling 4 layers to lists and of the whole frame with lists to
//! the one with 8 peeled layers.

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::scene::builtin;
use std::path::Path;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{quartiles, Size};

const PASSES: [&str; 6] = ["transparent", "oit_clear", "oit_append", "oit_resolve", "peel", "peel_resolve"];

/// An executor for one setup, warmed up; `layers` for depth peeling.
fn setup(gpu: &Gpu, size: (u32, u32), transparency: &str, layers: u32) -> Executor {
    let mut scene = builtin::by_name("panes").expect("the panes scene");
    scene.size = size;
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
    let variants = [("transparency".to_string(), transparency.to_string())];
    let ws = lightbench_compiler::Workspace::disk();
    let (exe, _) = lightbench::render::compile_in(&ws, gpu, &pipeline, None, &scene, &variants).unwrap_or_else(|e| panic!("{e}"));
    // `peel.layers` repeats a pass: plan for it.
    let set = lightbench::render::parse_params(&exe.plan, &[("peel.layers".into(), layers.to_string())]).expect("peel.layers");
    let values = lightbench::render::param_values(&exe.plan, &set).expect("values");
    let (exe, _) =
        lightbench::render::compile_with(&ws, gpu, (&pipeline, None), &scene, &variants, &values).unwrap_or_else(|e| panic!("{e}"));
    let mut ex = Executor::new(gpu, &exe, &scene).expect("executor");
    ex.set_reuse(false);
    ex.render_frame(gpu, &ex.inputs(0.0)).expect("warm-up frame");
    ex
}

/// One frame: (compositing GPU ms, frame GPU ms).
fn frame(gpu: &Gpu, ex: &mut Executor, f: u32) -> (f64, f64) {
    ex.render_frame(gpu, &ex.inputs(f as f32 / 60.0)).expect("frame");
    let (mut blend, mut frame) = (0.0, 0.0);
    for t in &ex.last_timings {
        let ms = t.gpu_ms.unwrap_or(f64::NAN);
        frame += ms;
        if PASSES.contains(&t.pass.as_str()) {
            blend += ms;
        }
    }
    (blend, frame)
}

fn main() {
    let run = Size::from_args();
    let (sizes, rounds) = (
        run.pick(vec![(800, 600), (1280, 720), (1920, 1080)], vec![(64, 64)]),
        run.pick(9, 1),
    );
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter");
    println!("{}", gpu.describe());
    println!(
        "blended surfaces on the panes scene, GPU ms: medians of {rounds} interleaved rounds of a frame per setup (after a warm-up); ratios: median [quartiles] of the per-round ratio ({})",
        common::load_line()
    );
    println!(
        "{:>11} {:>10} {:>10} {:>10} {:>10} {:>24} {:>30}",
        "size", "sorted ms", "peel 4 ms", "peel 8 ms", "lists ms", "peel 4 / lists", "frame lists / peel 8"
    );
    let setups = [("sorted", 4), ("depth_peeling", 4), ("depth_peeling", 8), ("fragment_lists", 4)];
    for &size in &sizes {
        let mut ex: Vec<Executor> = setups.iter().map(|&(t, l)| setup(&gpu, size, t, l)).collect();
        // Per setup, per round: (compositing, frame); each round's order rotated.
        let mut got: Vec<Vec<(f64, f64)>> = vec![vec![]; setups.len()];
        for r in 0..rounds {
            for k in 0..setups.len() {
                let i = (k + r) % setups.len();
                got[i].push(frame(&gpu, &mut ex[i], r as u32 + 1));
            }
        }
        let median = |i: usize| quartiles(got[i].iter().map(|g| g.0).collect()).1;
        let per_round = |f: &dyn Fn(usize) -> f64| {
            let (q1, m, q3) = quartiles((0..rounds).map(f).collect());
            format!("{m:.2}× [{q1:.2}–{q3:.2}]")
        };
        println!(
            "{:>11} {:>10.3} {:>10.3} {:>10.3} {:>10.3} {:>24} {:>30}",
            format!("{}x{}", size.0, size.1),
            median(0),
            median(1),
            median(2),
            median(3),
            per_round(&|r| got[1][r].0 / got[3][r].0),
            per_round(&|r| got[3][r].1 / got[2][r].1),
        );
    }
}
