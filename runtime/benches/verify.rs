//! `cargo bench -p lightbench --bench verify`: what `lightbench verify` costs per
//! configuration (render 3 frames + read back and scan every part of every resource), and
//! the overhead of the pass-by-pass re-run that names the first offending pass (one
//! submission and a read-back of its outputs after every pass), each against a plain render
//! of the same frames (waited for) in interleaved rounds: the median and quartiles of the
//! per-round ratio. Cornell box, deferred pipeline, 64×64. Needs a GPU adapter (lavapipe is
//! enough); `cargo test` runs it at its smallest.

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use lightbench::scene::builtin;
use lightbench::verify;
use std::path::Path;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{interleaved, ms, Size};

const FRAMES: u32 = 3;

fn main() {
    let rounds = Size::from_args().pick(8, 1);
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let mut scene = builtin::cornell();
    scene.size = (64, 64);
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
    let (exe, _) = compile(&gpu, &pipeline, None, &scene, &[]).expect("compile");
    let plain = || {
        ms(|| {
            let mut ex = Executor::new(&gpu, &exe, &scene).expect("executor");
            ex.set_reuse(false);
            for f in 0..FRAMES {
                ex.render_frame(&gpu, &ex.inputs(f as f32 / 60.0)).expect("frame");
            }
            ex.wait_idle(&gpu).expect("idle");
        })
    };
    let scanned = || {
        ms(|| {
            let found = verify::configuration(&gpu, &exe, &scene, (FRAMES, &mut Default::default()), &[]).expect("verify");
            assert!(found.is_none(), "the Cornell box is finite");
        })
    };
    let bisect = || {
        ms(|| {
            let first = verify::bisect::first_offender(&gpu, &exe, &scene, FRAMES, &[]).expect("bisect");
            assert!(first.is_none());
        })
    };
    plain(); // warm the driver and the pipeline cache
    println!("Cornell box, deferred, 64×64, {FRAMES} frames, ms:");
    println!(
        "{}",
        interleaved(rounds, plain, scanned).report(("plain render", "verify (render + scan)"), "ms")
    );
    println!(
        "{}",
        interleaved(rounds, plain, bisect).report(("plain render", "pass-by-pass re-run"), "ms")
    );
}
