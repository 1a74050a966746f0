//! `cargo bench -p lightbench --bench inflight`: wall time of 20 frames of `deferred.lbp`
//! on `many_lights` (100 point lights, every pass every frame, no timestamps) with two frames
//! in flight (the default: the CPU encodes a frame while the GPU runs the one before) against
//! waiting for each frame as it is submitted (0 in flight: serial), in 10 interleaved rounds:
//! the per-round ratio's median and quartiles. Needs an adapter (lavapipe is
//! enough; there "the GPU" is the same CPU cores, so overlap gains little, where a real GPU
//! would hide the encoding). Then the same with GPU timestamps on: each timed frame waited
//! for (what measurements do) against timestamps read late (what the viewer does);
//! `cargo test` runs it at its smallest (`Size::Smoke`: 2 frames, one round).

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use lightbench::scene::Scene;
use std::path::Path;
use std::time::Instant;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{interleaved, Size};

impl Size {
    fn frames(self) -> u32 {
        self.pick(20, 2)
    }
    fn rounds(self) -> usize {
        self.pick(10, 1)
    }
}

fn frames(gpu: &Gpu, ex: &mut Executor, (in_flight, count): (u32, u32)) -> f64 {
    ex.set_frames_in_flight(in_flight);
    let t = Instant::now();
    for f in 0..count {
        let inputs = ex.inputs(f as f32 / 60.0);
        ex.render_frame(gpu, &inputs).expect("frame");
    }
    ex.wait_idle(gpu).expect("idle");
    t.elapsed().as_secs_f64() * 1e3
}

fn main() {
    run(Size::from_args());
}

fn run(size: Size) {
    let (count, rounds) = (size.frames(), size.rounds());
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let mut scene: Scene = lightbench::scene::load("many_lights").expect("scene");
    scene.size = (256, 192);
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.lbp");
    let (exe, _) = compile(&gpu, &pipeline, None, &scene, &[]).expect("compile");
    let mut ex = Executor::new(&gpu, &exe, &scene).expect("executor");
    ex.set_reuse(false);
    ex.set_timing(false);
    frames(&gpu, &mut ex, (2, count)); // warm up
                                       // Both sides use the one executor in turn.
    let ex = std::cell::RefCell::new(ex);
    let run = |in_flight: u32| frames(&gpu, &mut ex.borrow_mut(), (in_flight, count));
    println!("deferred.lbp, many_lights at 256×192, {count} frames a round, ms:");
    let p = interleaved(rounds, || run(0), || run(2));
    println!("{}", p.report(("waiting for each frame (0 in flight)", "2 frames in flight"), "ms"));
    if !gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
        println!("no timestamp queries on this adapter: timed frames not compared");
        return;
    }
    println!("timed frames (timestamps on), 2 frames in flight:");
    let timed = |late: bool| {
        let mut ex = ex.borrow_mut();
        ex.set_timing(true);
        ex.set_late_timestamps(late);
        frames(&gpu, &mut ex, (2, count))
    };
    let p = interleaved(rounds, || timed(false), || timed(true));
    println!("{}", p.report(("each timed frame waited", "timestamps read late"), "ms"));
}
