//! `cargo bench -p lightbench --bench transparency`: seed 003 Table 6.3 style — what
//! compositing blended surfaces costs, drawn far to near by object (`transparency = sorted`),
//! peeled in 4 and 8 layers (`depth_peeling`) and from per-pixel fragment lists
//! (`fragment_lists`: clear, append, sort and blend), on the built-in panes scene at the
//! seed's three resolutions. Needs a GPU adapter (lavapipe is enough); `cargo test` runs it at
//! its smallest (64², a frame). Every pass runs every frame; figures are GPU-ms means over 5 frames
//! after a warm-up, of the passes that composite blended surfaces, and of the whole frame.

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::scene::builtin;
use std::path::Path;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::Size;

const PASSES: [&str; 6] = ["transparent", "oit_clear", "oit_append", "oit_resolve", "peel", "peel_resolve"];

/// (compositing GPU ms, frame GPU ms) per frame; `layers` for depth peeling.
fn measure(gpu: &Gpu, size: (u32, u32), transparency: &str, layers: u32, frames: u32) -> (f64, f64) {
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
    let (mut blend, mut frame) = (0.0, 0.0);
    for f in 1..=frames {
        ex.render_frame(gpu, &ex.inputs(f as f32 / 60.0)).expect("frame");
        for t in &ex.last_timings {
            let ms = t.gpu_ms.unwrap_or(f64::NAN);
            frame += ms;
            if PASSES.contains(&t.pass.as_str()) {
                blend += ms;
            }
        }
    }
    (blend / frames as f64, frame / frames as f64)
}

fn main() {
    let run = Size::from_args();
    let (sizes, frames) = (
        run.pick(vec![(800, 600), (1280, 720), (1920, 1080)], vec![(64, 64)]),
        run.pick(5, 1),
    );
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter");
    println!("{}", gpu.describe());
    println!("blended surfaces on the panes scene, GPU ms per frame (mean of {frames} after a warm-up)");
    println!(
        "{:>11} {:>10} {:>10} {:>10} {:>10} {:>14} {:>15}",
        "size", "sorted ms", "peel 4 ms", "peel 8 ms", "lists ms", "peel 4 / lists", "frame ms (l/p8)"
    );
    for &size in &sizes {
        let (sorted, _) = measure(&gpu, size, "sorted", 4, frames);
        let (peel4, _) = measure(&gpu, size, "depth_peeling", 4, frames);
        let (peel8, peel8_frame) = measure(&gpu, size, "depth_peeling", 8, frames);
        let (lists, lists_frame) = measure(&gpu, size, "fragment_lists", 4, frames);
        println!(
            "{:>11} {sorted:>10.3} {peel4:>10.3} {peel8:>10.3} {lists:>10.3} {:>13.2}× {:>7.1}/{peel8_frame:.1}",
            format!("{}x{}", size.0, size.1),
            peel4 / lists,
            lists_frame
        );
    }
}
