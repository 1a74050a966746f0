//! `cargo bench -p lightbench --bench reuse`: frame time of a 4-frame render of the Cornell
//! box (static point light, static camera) with reuse of unchanged work against the same
//! render with every pass run every frame (`--no-reuse`), in interleaved rounds, as the
//! median and quartiles of the per-round ratio. Frame time is wall-clock per `render_frame`
//! with each frame waited for (encode, submit and wait: 0 frames in flight). Needs a GPU
//! adapter (lavapipe is enough); `cargo test` runs it at its smallest.

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use lightbench::scene::builtin;
use std::path::Path;
use std::time::Instant;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{interleaved, quartiles, Size};

const FRAMES: u32 = 4;

/// One render of `FRAMES` frames by a new executor: mean ms per frame, and the first frame's
/// (it always runs everything).
fn render(gpu: &Gpu, exe: &lightbench_compiler::Executable, reuse: bool) -> (f64, f64) {
    let scene = builtin::cornell();
    let mut ex = Executor::new(gpu, exe, &scene).expect("executor");
    ex.set_reuse(reuse);
    ex.set_frames_in_flight(0);
    let (mut total, mut first) = (0.0, 0.0);
    for f in 0..FRAMES {
        let inputs = ex.inputs(f as f32 / 60.0);
        let t = Instant::now();
        ex.render_frame(gpu, &inputs).expect("frame");
        let ms = t.elapsed().as_secs_f64() * 1e3;
        total += ms;
        if f == 0 {
            first = ms;
        }
    }
    (total / FRAMES as f64, first)
}

fn main() {
    let rounds = Size::from_args().pick(16, 2);
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
    let (exe, _) = compile(&gpu, &pipeline, None, &builtin::cornell(), &[]).expect("compile");
    render(&gpu, &exe, true); // warm the pipeline cache and the driver
    let (mut first_off, mut first_on) = (vec![], vec![]);
    let p = interleaved(
        rounds,
        || {
            let (mean, first) = render(&gpu, &exe, false);
            first_off.push(first);
            mean
        },
        || {
            let (mean, first) = render(&gpu, &exe, true);
            first_on.push(first);
            mean
        },
    );
    println!("Cornell box, {FRAMES} frames a render, static light and camera, ms per frame:");
    println!("{}", p.report(("no reuse", "reuse"), "ms"));
    println!(
        "  first frame (runs everything): no reuse {:.3} ms, reuse {:.3} ms (medians)",
        quartiles(first_off).1,
        quartiles(first_on).1
    );
}
