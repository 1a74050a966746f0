//! The GPU path tracer (`pipelines/pathtrace.lbp`, `reference --device gpu`) against the CPU
//! reference: pixel by pixel within the noise both estimate, on the scenes the reference is
//! checked on; a deliberately wrong copy fails the same comparison.

use crate::gpu_common;
use lightbench::gpu_reference::{self, Tracer};
use lightbench::reference::{self, Budget, Reference, Settings, Term};
use lightbench::scene::Scene;
use std::path::Path;

fn load(spec: &str, size: (u32, u32)) -> Scene {
    let spec = if spec.ends_with(".ron") {
        gpu_common::root().join(spec).display().to_string()
    } else {
        spec.to_string()
    };
    lightbench::scene::load::load_sized(&spec, Some(size), &[]).unwrap_or_else(|e| panic!("{spec}: {e}"))
}

fn settings(terms: &[Term], spp: u32) -> Settings {
    Settings {
        budget: Budget::Spp(spp),
        terms: terms.to_vec(),
        seed: 7,
        ..Settings::default()
    }
}

/// The GPU reference of `scene` by the path tracer at `pipeline` (in `root`'s workspace).
fn on_gpu(scene: &Scene, s: &Settings, pipeline: &Path) -> Reference {
    let gpu = gpu_common::gpu();
    let ws = lightbench_compiler::Workspace::disk();
    let tracer = Tracer { ws: &ws, pipeline };
    gpu_reference::render(&gpu, &tracer, scene, s, false).unwrap_or_else(|e| panic!("{}: {e}", scene.name))
}

/// How two estimates of one term differ, in units of their combined noise: per value the
/// z-score (mean, RMS), and the worst 8×8 block's bias (the block's summed difference over
/// its summed noise). Pixels on an edge between surfaces (`reference::edge_pixels`) are left
/// out; where neither has noise (an exact term, a black pixel) the two must agree to 1e-3.
struct Agreement {
    mean: f64,
    rms: f64,
    worst_block: f64,
    exact_off: usize,
}

fn agreement(a: &reference::TermImage, b: &reference::TermImage, edges: &[bool]) -> Agreement {
    let (w, h) = (a.mean.width as usize, a.mean.height as usize);
    let (mut z, mut exact_off) = (vec![], 0);
    let mut blocks = vec![(0.0f64, 0.0f64); w.div_ceil(8) * h.div_ceil(8)];
    for p in (0..w * h).filter(|&p| !edges[p]) {
        let (mut d_sum, mut sd) = (0.0, [0.0f64; 2]);
        // AO is grey: its three channels are one value.
        let channels = if a.term == Term::Ao { 1 } else { 3 };
        for c in 0..channels {
            let i = p * 4 + c;
            let d = a.mean.rgba[i] as f64 - b.mean.rgba[i] as f64;
            let (va, vb) = (a.variance.rgba[i] as f64, b.variance.rgba[i] as f64);
            let scale = (a.mean.rgba[i].abs() as f64).max(b.mean.rgba[i].abs() as f64);
            if va + vb <= (1e-4 * scale).powi(2) {
                exact_off += (d.abs() > 1e-3 * scale.max(1e-2)) as usize;
                continue;
            }
            z.push(d / (va + vb).sqrt());
            d_sum += d;
            sd = [sd[0] + va.sqrt(), sd[1] + vb.sqrt()];
        }
        // A path's channels move together: the noise of their sum is at most the sum of their
        // noises (exactly that for a grey path), so a block is judged by that bound.
        let block = &mut blocks[(p / w / 8) * w.div_ceil(8) + (p % w) / 8];
        *block = (block.0 + d_sum, block.1 + sd[0] * sd[0] + sd[1] * sd[1]);
    }
    let n = z.len().max(1) as f64;
    Agreement {
        mean: z.iter().sum::<f64>() / n,
        rms: (z.iter().map(|v| v * v).sum::<f64>() / n).sqrt(),
        worst_block: blocks
            .iter()
            .filter(|b| b.1 > 0.0)
            .map(|b| (b.0 / b.1.sqrt()).abs())
            .fold(0.0, f64::max),
        exact_off,
    }
}

/// Every term of the two references agrees (see `Agreement`); the failures, named.
fn compare(scene: &Scene, cpu: &Reference, gpu: &Reference) -> Vec<String> {
    let edges = reference::edge_pixels(scene);
    let mut bad = vec![];
    for t in &cpu.terms {
        let g = gpu.term(t.term).unwrap();
        let a = agreement(t, g, &edges);
        let left = edges.iter().filter(|e| **e).count();
        eprintln!(
            "{} {}: z mean {:+.3}, RMS {:.3}, worst 8×8 block {:.2}σ, {} exact values off, {left} edge pixels left out",
            scene.name,
            t.term.name(),
            a.mean,
            a.rms,
            a.worst_block,
            a.exact_off
        );
        if a.mean.abs() > 0.1 || a.rms > 1.3 || a.worst_block > 3.0 || a.exact_off > 0 {
            bad.push(format!("{} {}", scene.name, t.term.name()));
        }
    }
    bad
}

/// The scenes and terms of the comparison: the Cornell box lit by a point light, a sun, a
/// spot and an emitter, and six hard cases.
const CASES: [(&str, &[Term]); 10] = [
    ("cornell", &[Term::Direct, Term::Ao, Term::Full]),
    ("scenes/cornell_sun.ron", &[Term::Full]),
    ("scenes/cornell_spot.ron", &[Term::Full]),
    ("cornell_lamp", &[Term::Direct, Term::Full]),
    ("scenes/hard/point_in_box.ron", &[Term::Full]),
    ("scenes/hard/spot_wide.ron", &[Term::Direct, Term::Full]),
    ("scenes/hard/mirror_floor.ron", &[Term::Full]),
    ("scenes/hard/deep_range.ron", &[Term::Direct, Term::Ao]),
    ("scenes/hard/tiny_scale.ron", &[Term::Full]),
    ("scenes/hard/zero_normals.ron", &[Term::Full]),
];

#[test]
fn the_gpu_path_tracer_equals_the_cpu_reference_within_noise() {
    let pipeline = gpu_common::root().join("pipelines/pathtrace.lbp");
    let mut bad = vec![];
    for (spec, terms) in CASES {
        let scene = load(spec, (64, 64));
        let s = settings(terms, 128);
        let cpu = reference::render(&scene, &s, false);
        let gpu = on_gpu(&scene, &s, &pipeline);
        assert_eq!(gpu.spp, cpu.spp, "{spec}");
        for (a, b) in cpu.terms.iter().zip(&gpu.terms) {
            assert_eq!((a.term, a.samples), (b.term, b.samples), "{spec}");
        }
        bad.extend(compare(&scene, &cpu, &gpu));
    }
    assert!(bad.is_empty(), "the GPU path tracer differs from the CPU reference: {bad:?}");
}

/// The same comparison catches a path tracer that lets single-sided emitters light what lies
/// behind them (next-event estimation counting both sides).
#[test]
fn a_path_tracer_with_two_sided_emission_fails_the_comparison() {
    let dir = std::env::temp_dir().join(format!("lightbench-pt-mutant-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    copy_tree(&gpu_common::root().join("shaders"), &dir.join("shaders"));
    std::fs::create_dir_all(dir.join("pipelines")).unwrap();
    std::fs::copy(
        gpu_common::root().join("pipelines/pathtrace.lbp"),
        dir.join("pipelines/pathtrace.lbp"),
    )
    .unwrap();
    let lib = dir.join("shaders/lib/hit_emitters.wgsl");
    let text = std::fs::read_to_string(&lib).unwrap();
    let wrong = text.replace("let facing = select(c, abs(c), e.double_sided != 0u);", "let facing = abs(c);");
    assert_ne!(wrong, text, "the line the mutant changes is gone");
    std::fs::write(&lib, wrong).unwrap();
    // The lamp lowered to mid-height and turned to face the ceiling: below it, only its back.
    let mut scene = load("cornell_lamp", (32, 32));
    let lamp = scene.meshes.iter_mut().find(|m| m.name == "lamp").unwrap();
    lamp.transform = glam::Mat4::from_translation(glam::Vec3::new(0.0, -0.6, 0.0)) * lamp.transform;
    for t in lamp.indices.chunks_exact_mut(3) {
        t.swap(1, 2);
    }
    let s = settings(&[Term::Full], 128);
    let cpu = reference::render(&scene, &s, false);
    let right = on_gpu(&scene, &s, &gpu_common::root().join("pipelines/pathtrace.lbp"));
    assert!(compare(&scene, &cpu, &right).is_empty(), "the lamp facing the ceiling");
    let gpu = on_gpu(&scene, &s, &dir.join("pipelines/pathtrace.lbp"));
    let _ = std::fs::remove_dir_all(&dir);
    assert!(!compare(&scene, &cpu, &gpu).is_empty(), "two-sided emission passed as equal");
}

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_dir() {
            copy_tree(&e.path(), &to.join(e.file_name()));
        } else {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

/// Samples spread over frames give the image of the same samples in one frame.
#[test]
fn progressive_accumulation_is_independent_of_the_frame_pacing() {
    let scene = load("cornell_lamp", (16, 16));
    let gpu = gpu_common::gpu();
    let pipeline = gpu_common::root().join("pipelines/pathtrace.lbp");
    let read = |per_frame: i64, frames: u32| {
        let (exe, _) = lightbench::render::compile(&gpu, &pipeline, None, &scene, &[]).unwrap();
        let params = [("pt.samples".to_string(), lightbench_compiler::ir::ParamValue::Int(per_frame))];
        let ex = lightbench::render::render_with(&gpu, &exe, &scene, frames, &params).unwrap();
        (
            ex.read_texture(&gpu, "pt.mean", 0, 0).unwrap(),
            ex.read_texture(&gpu, "pt.m2", 0, 0).unwrap(),
        )
    };
    let (once, once_m2) = read(256, 1);
    let (spread, spread_m2) = read(16, 16);
    assert!(once.rgba.chunks_exact(4).all(|p| p[3] == 256.0));
    assert_eq!(once.rgba, spread.rgba, "mean and count");
    assert_eq!(once_m2.rgba, spread_m2.rgba, "squared deviations");
}
