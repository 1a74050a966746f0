//! `cargo bench -p lightbench --bench inflight`: wall time of 200 frames of `deferred.lbp`
//! on `many_lights` (100 point lights, every pass every frame, no timestamps) with two frames
//! in flight (the default: the CPU encodes a frame while the GPU runs the one before) against
//! waiting for each frame as it is submitted (0 in flight: serial), interleaved in one run, as
//! a ratio. Needs an adapter (lavapipe is
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
use common::Size;

impl Size {
    fn frames(self) -> u32 {
        self.pick(200, 2)
    }
    fn rounds(self) -> u32 {
        self.pick(2, 1)
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
    let (mut waiting, mut overlapped) = (0.0, 0.0);
    for _ in 0..rounds {
        waiting += frames(&gpu, &mut ex, (0, count));
        overlapped += frames(&gpu, &mut ex, (2, count));
    }
    println!("deferred.lbp, many_lights at 256×192, {count} frames ({rounds} rounds, interleaved)");
    println!("  waiting for each frame (0 in flight): {:9.1} ms", waiting / rounds as f64);
    println!("  2 frames in flight     : {:9.1} ms", overlapped / rounds as f64);
    println!("  ratio in flight / waiting: {:.3}", overlapped / waiting);
    if !gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
        println!("no timestamp queries on this adapter: timed frames not compared");
        return;
    }
    ex.set_timing(true);
    let (mut waited, mut late) = (0.0, 0.0);
    for _ in 0..rounds {
        ex.set_late_timestamps(false);
        waited += frames(&gpu, &mut ex, (2, count));
        ex.set_late_timestamps(true);
        late += frames(&gpu, &mut ex, (2, count));
    }
    println!("timed frames (timestamps on), 2 frames in flight:");
    println!("  each timed frame waited: {:9.1} ms", waited / rounds as f64);
    println!("  timestamps read late   : {:9.1} ms", late / rounds as f64);
    println!("  ratio late / waited: {:.3}", late / waited);
}
