//! `cargo bench -p lightbench --bench allocations`: heap allocations per frame in the steady
//! state (a counting global allocator around `render_frame`), `deferred.lbp` on the Cornell box
//! (7 passes) and on `many_lights` (100 point lights, per-light repetitions), every pass every
//! frame and with unchanged work reused, GPU timestamps off (on, the read-back's mapping adds
//! its own). What wgpu allocates to record and submit a frame is included: the figure is the
//! whole cost a frame puts on the allocator. Needs an adapter (lavapipe is enough);
//! `cargo test` runs it at its smallest.

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::Size;

struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Steady frames counted: 50 (2 in the smoke run).
fn frames() -> u32 {
    Size::from_args().pick(50, 2)
}

/// Allocations per frame over `frames()` steady frames (after 5 to settle).
fn per_frame(gpu: &Gpu, ex: &mut Executor) -> f64 {
    let inputs = ex.inputs(0.0);
    for _ in 0..5 {
        ex.render_frame(gpu, &inputs).expect("frame");
    }
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    for _ in 0..frames() {
        ex.render_frame(gpu, &inputs).expect("frame");
    }
    (ALLOCATIONS.load(Ordering::Relaxed) - before) as f64 / frames() as f64
}

/// The floor: allocations of an empty frame's wgpu calls alone (an encoder, an error scope,
/// a submission, a poll), as `render_frame` makes them when every pass is reused.
fn empty_submission(gpu: &Gpu) -> f64 {
    let submit = || {
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let enc = gpu.device.create_command_encoder(&Default::default());
        let buffer = enc.finish();
        let _ = pollster::block_on(scope.pop());
        gpu.queue.submit([buffer]);
        let _ = gpu.device.poll(wgpu::PollType::Poll);
    };
    (0..5).for_each(|_| submit());
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    (0..frames()).for_each(|_| submit());
    (ALLOCATIONS.load(Ordering::Relaxed) - before) as f64 / frames() as f64
}

fn main() {
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.lbp");
    println!("allocations per steady frame, deferred.lbp, {} frames (timestamps off):", frames());
    println!(
        "  wgpu alone, an empty frame (encoder, error scope, submit, poll): {:.1}",
        empty_submission(&gpu)
    );
    for name in ["cornell", "many_lights"] {
        let mut scene = lightbench::scene::load(name).expect("scene");
        scene.size = (64, 64);
        let (exe, _) = compile(&gpu, &pipeline, None, &scene, &[]).expect("compile");
        let mut ex = Executor::new(&gpu, &exe, &scene).expect("executor");
        ex.set_timing(false);
        let passes = ex.plan().passes.len();
        let reps: usize = ex.plan().passes.iter().map(|p| p.reps.len()).sum();
        ex.set_reuse(false);
        let every = per_frame(&gpu, &mut ex);
        ex.set_reuse(true);
        let reused = per_frame(&gpu, &mut ex);
        println!("  {name:12} ({passes} passes, {reps} repetitions): every pass {every:7.1}, unchanged work reused {reused:7.1}");
    }
}
