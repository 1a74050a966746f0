//! `cargo bench -p lightbench --bench verify`: what `lightbench verify` costs per
//! configuration (render 3 frames + read back and scan every part of every resource), and
//! the overhead of the pass-by-pass re-run that names the first offending pass (one
//! submission and a read-back of its outputs after every pass), each against a plain render
//! of the same frames in the same run. Cornell box, deferred pipeline, 64×64. Needs a GPU
//! adapter (lavapipe is enough). Not a test.

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use lightbench::scene::builtin;
use lightbench::verify;
use std::path::Path;
use std::time::Instant;

const FRAMES: u32 = 3;
const RUNS: u32 = 5;

fn ms(f: &mut dyn FnMut()) -> f64 {
    f(); // warm
    let t = Instant::now();
    for _ in 0..RUNS {
        f();
    }
    t.elapsed().as_secs_f64() * 1e3 / RUNS as f64
}

fn main() {
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let mut scene = builtin::cornell();
    scene.size = (64, 64);
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
    let (exe, _) = compile(&gpu, &pipeline, None, &scene, &[]).expect("compile");
    let plain = ms(&mut || {
        let mut ex = Executor::new(&gpu, &exe, &scene).expect("executor");
        ex.set_reuse(false);
        for f in 0..FRAMES {
            ex.render_frame(&gpu, &ex.inputs(f as f32 / 60.0)).expect("frame");
        }
    });
    let scanned = ms(&mut || {
        let found = verify::configuration(&gpu, &exe, &scene, (FRAMES, &mut Default::default()), &[]).expect("verify");
        assert!(found.is_none(), "the Cornell box is finite");
    });
    let bisect = ms(&mut || {
        let first = verify::bisect::first_offender(&gpu, &exe, &scene, FRAMES, &[]).expect("bisect");
        assert!(first.is_none());
    });
    println!("Cornell box, deferred, 64×64, {FRAMES} frames, mean of {RUNS} runs");
    println!("  plain render          : {plain:8.1} ms");
    println!(
        "  verify (render + scan): {scanned:8.1} ms per configuration, {:.2}× plain",
        scanned / plain
    );
    println!("  pass-by-pass re-run   : {bisect:8.1} ms, {:.2}× plain", bisect / plain);
}
