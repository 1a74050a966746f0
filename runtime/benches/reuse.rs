//! `cargo bench -p lightbench --bench reuse`: frame time of a 4-frame render of the Cornell
//! box (static point light, static camera) with reuse of unchanged work against the same
//! render with every pass run every frame (`--no-reuse`), in the same run, as a ratio.
//! Frame time is wall-clock per `render_frame` (encode, submit and wait). Needs a GPU
//! adapter (lavapipe is enough). Not a test.

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use lightbench::scene::builtin;
use std::path::Path;
use std::time::Instant;

const FRAMES: u32 = 4;
const RUNS: u32 = 8;

/// Mean milliseconds per frame over `RUNS` renders of `FRAMES` frames, and the first
/// frame's share (it always runs everything).
fn measure(gpu: &Gpu, reuse: bool) -> (f64, f64) {
    let scene = builtin::cornell();
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
    let (exe, _) = compile(gpu, &pipeline, None, &scene, &[]).expect("compile");
    let (mut total, mut first) = (0.0, 0.0);
    for _ in 0..RUNS {
        let mut ex = Executor::new(gpu, &exe, &scene).expect("executor");
        ex.set_reuse(reuse);
        for f in 0..FRAMES {
            let inputs = ex.inputs(f as f32 / 60.0);
            let t = Instant::now();
            ex.render_frame(gpu, &inputs).expect("frame");
            let ms = t.elapsed().as_secs_f64() * 1e3;
            total += ms;
            if f == 0 {
                first += ms;
            }
        }
    }
    (total / (RUNS * FRAMES) as f64, first / RUNS as f64)
}

fn main() {
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    measure(&gpu, true); // warm the pipeline cache and the driver
    let (off, off_first) = measure(&gpu, false);
    let (on, on_first) = measure(&gpu, true);
    println!("Cornell box, {FRAMES} frames × {RUNS} runs, static light and camera");
    println!("  no reuse : {off:8.3} ms/frame (first frame {off_first:.3} ms)");
    println!("  reuse    : {on:8.3} ms/frame (first frame {on_first:.3} ms)");
    println!("  ratio reuse / no reuse: {:.3}", on / off);
}
