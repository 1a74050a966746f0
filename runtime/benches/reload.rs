//! `cargo bench -p lightbench --bench reload`: the cost of a hot reload after a one-shader
//! edit against building from scratch, measured in one run, interleaved so that drift in
//! the machine's speed hits both sides alike. Prints medians and ratios (goal: replace /
//! fresh executor <= 0.2×). Needs a GPU adapter (lavapipe is enough);
//! `cargo test` runs it at its smallest.

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile_in;
use lightbench::scene::builtin;
use lightbench_compiler::vfs::{MemoryVfs, Vfs};
use lightbench_compiler::Workspace;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{Paired, Size};

const PIPELINE: &str = "mem/pipelines/deferred.ron";
const TONEMAP: &str = "mem/shaders/tonemap.wgsl";

fn median(mut v: Vec<Duration>) -> f64 {
    v.sort();
    v[v.len() / 2].as_secs_f64() * 1e3
}

fn load(vfs: &MemoryVfs, from: &Path, to: &Path) {
    for e in std::fs::read_dir(from).expect("repository files") {
        let p = e.expect("directory entry").path();
        let dest = to.join(p.file_name().expect("file name"));
        if p.is_dir() {
            load(vfs, &p, &dest);
        } else {
            vfs.write(&dest, std::fs::read_to_string(&p).expect("text file"));
        }
    }
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("repository root")
        .to_path_buf();
    let vfs = Arc::new(MemoryVfs::new());
    load(&vfs, &root.join("pipelines"), Path::new("mem/pipelines"));
    load(&vfs, &root.join("shaders"), Path::new("mem/shaders"));
    let original = vfs.read(Path::new(TONEMAP)).expect("tonemap shader");
    let gpu = Gpu::new(&DeviceOptions::default()).unwrap_or_else(|e| panic!("the benchmark needs an adapter: {e}"));
    let mut scene = builtin::cornell();
    scene.size = (256, 256);
    let ws = Workspace::new(vfs.clone());
    let compile = |ws: &Workspace| {
        compile_in(ws, &gpu, Path::new(PIPELINE), None, &scene, &[])
            .unwrap_or_else(|e| panic!("{e}"))
            .0
    };
    let exe = compile(&ws);
    let mut ex = Executor::new(&gpu, &exe, &scene).expect("executor");
    let rounds = Size::from_args().pick(12, 1);
    let (mut replace, mut fresh, mut recompile, mut full_compile) = (vec![], vec![], vec![], vec![]);
    let mut built = vec![];
    for round in 0..rounds + 2 {
        // A new constant each round: a new module, so every replace really rebuilds a pipeline.
        let factor = format!("vec3<f32>(1.0)) * {:.4}, 1.0);", 0.5 + round as f64 * 1e-3);
        vfs.write(TONEMAP, original.replace("vec3<f32>(1.0)), 1.0);", &factor));
        let t = Instant::now();
        let edited = compile(&ws);
        let t_recompile = t.elapsed();
        let t = Instant::now();
        let report = ex.replace(&gpu, &edited).expect("replace");
        let t_replace = t.elapsed();
        ex.render_frame(&gpu, &ex.inputs(0.0)).expect("frame after replace");
        let t = Instant::now();
        let whole = compile(&Workspace::new(vfs.clone()));
        let t_full = t.elapsed();
        let t = Instant::now();
        let new = Executor::new(&gpu, &whole, &scene).expect("fresh executor");
        let t_fresh = t.elapsed();
        drop(new);
        if round >= 2 {
            // The first rounds warm the driver's caches and the allocator.
            replace.push(t_replace);
            fresh.push(t_fresh);
            recompile.push(t_recompile);
            full_compile.push(t_full);
            built.push(report.pipelines_built.len());
        }
    }
    let ms = |v: &[Duration]| v.iter().map(|d| d.as_secs_f64() * 1e3).collect::<Vec<f64>>();
    let swap = Paired {
        a: ms(&fresh),
        b: ms(&replace),
    };
    let recompiled = Paired {
        a: ms(&full_compile),
        b: ms(&recompile),
    };
    let (r, f, rc, fc) = (median(replace), median(fresh), median(recompile), median(full_compile));
    println!("adapter: {} ({:?})", gpu.info.name, gpu.info.backend);
    println!(
        "pipeline `deferred`, scene cornell 256×256, {} passes, {rounds} rounds; pipelines rebuilt per replace: {:?}",
        exe.plan.passes.len(),
        built.iter().collect::<std::collections::BTreeSet<_>>()
    );
    println!("Executor::replace after a one-shader edit: {r:>9.3} ms (median)");
    println!("Executor::new from scratch:                {f:>9.3} ms (median)");
    let (q1, m, q3) = swap.ratio();
    println!("ratio replace / new, per round:            {m:>9.3}x (quartiles {q1:.3}-{q3:.3}; goal <= 0.2x)");
    println!("workspace recompile of the edited pipeline:{rc:>9.3} ms (median)");
    println!("compile in a fresh workspace:              {fc:>9.3} ms (median)");
    let (q1, m, q3) = recompiled.ratio();
    println!("ratio recompile / fresh compile, per round:{m:>9.3}x (quartiles {q1:.3}-{q3:.3})");
}
