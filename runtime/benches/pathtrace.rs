//! `cargo bench -p lightbench --bench pathtrace`: paths per second of the GPU path tracer
//! (`pipelines/pathtrace.lbp`, what `reference --device gpu` runs) against the CPU reference
//! on the same scene, size, term and sample count, on the adapter at hand: rounds interleave
//! the two (each renders to the end: the GPU side waits for its last frame), and the figure
//! is the median and quartiles of the per-round ratio of paths per second. Both sides'
//! seconds are whole renders, setup included (the CPU's BVH; the GPU's pipeline compile and
//! acceleration structure). Needs an adapter with ray queries (lavapipe is enough; there both
//! sides run on the same CPU cores). `cargo test` runs it
//! once at its smallest (`Size::Smoke`).

use lightbench::gpu::{DeviceOptions, Gpu};
use lightbench::gpu_reference::{render, Tracer};
use lightbench::reference::{self, Budget, Settings, Term};
use lightbench::scene::Scene;
use std::path::{Path, PathBuf};

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::Size;
use common::{load_line, quartiles};

impl Size {
    fn rounds(self) -> usize {
        self.pick(7, 1)
    }
    fn size(self) -> (u32, u32) {
        self.pick((128, 128), (16, 16))
    }
    fn spp(self) -> u32 {
        self.pick(64, 4)
    }
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn scene(spec: &str, size: (u32, u32)) -> Scene {
    lightbench::scene::load::load_sized(spec, Some(size), &[]).expect("scene")
}

/// One case: its paths per second on each side over the rounds, and the ratio's quartiles.
fn case(gpu: &Gpu, size: Size, (spec, term): (&str, Term)) {
    let scene = scene(spec, size.size());
    let s = Settings {
        budget: Budget::Spp(size.spp()),
        terms: vec![term],
        ..Settings::default()
    };
    let pipeline = root().join("pipelines/pathtrace.lbp");
    let ws = lightbench_compiler::Workspace::disk();
    let tracer = Tracer {
        ws: &ws,
        pipeline: &pipeline,
    };
    let paths = (scene.size.0 * scene.size.1 * size.spp()) as f64;
    let (mut cpu, mut on_gpu, mut ratio) = (vec![], vec![], vec![]);
    for _ in 0..size.rounds() {
        let c = paths / reference::render(&scene, &s, false).seconds;
        let g = paths / render(gpu, &tracer, &scene, &s, false).expect("GPU path tracer").seconds;
        cpu.push(c);
        on_gpu.push(g);
        ratio.push(g / c);
    }
    let (c, g, (q1, r, q3)) = (quartiles(cpu).1, quartiles(on_gpu).1, quartiles(ratio));
    println!(
        "  {spec} {} {}x{} {} spp: CPU {:.3} M paths/s, GPU {:.3} M paths/s, GPU/CPU {r:.2}x (quartiles {q1:.2}..{q3:.2}, {} rounds)",
        term.name(),
        scene.size.0,
        scene.size.1,
        size.spp(),
        c / 1e6,
        g / 1e6,
        size.rounds()
    );
}

fn run(size: Size) {
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}\n{}", gpu.describe(), load_line());
    println!("CPU: {} threads", rayon::current_num_threads());
    for c in [("cornell", Term::Full), ("cornell_lamp", Term::Full), ("cornell", Term::Ao)] {
        case(&gpu, size, c);
    }
}

fn main() {
    run(Size::from_args());
}
