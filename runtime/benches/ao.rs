//! `cargo bench -p lightbench --bench ao`: seed 003 Tables 6.6 and 6.7 on the adapter at hand
//! — GPU time of each SSAO preset (all AO passes, and the SSAO buffer alone) and each AOV
//! preset at three resolutions, with ratios to SSAO1, and GTAO (the modern baseline) at its
//! defaults and at 2 slices × 8 steps beside them — and multi-view AO's cost per light
//! (seed 000 §6.3.2): its passes with 0 to 3 directional or spot lights beyond the camera.
//! `pipelines/deferred_gi.ron` on the Cornell box; GPU time from timestamp queries, every pass
//! every frame. The setups of a table run in interleaved rounds of a frame each, the order
//! rotating, after a warm-up: figures are medians, ratios the median and quartiles of the
//! per-round ratio. Needs a GPU adapter (lavapipe is enough); `cargo test` runs it at its
//! smallest (32×24, one round).

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use std::path::{Path, PathBuf};

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{quartiles, Size};

/// Interleaved rounds, a frame of each setup per round: 6 (1 in the smoke run).
fn rounds() -> usize {
    Size::from_args().pick(6, 1)
}

/// The tables' resolutions (one small one in the smoke run).
fn resolutions() -> Vec<(u32, u32)> {
    Size::from_args().pick(vec![(128, 96), (256, 192), (512, 384)], vec![(32, 24)])
}

/// An executor of `deferred_gi.ron` for the scene file, with these variants and parameters,
/// every pass every frame, after a warm-up frame.
fn executor(gpu: &Gpu, scene: &Path, variants: &[(&str, &str)], params: &[(&str, &str)]) -> Executor {
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred_gi.ron");
    let scene = lightbench::scene::load(scene.to_str().expect("path")).expect("scene");
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let (exe, _) = compile(gpu, &pipeline, None, &scene, &v).expect("compile");
    let mut ex = Executor::new(gpu, &exe, &scene).expect("executor");
    ex.set_reuse(false);
    let set: Vec<(String, String)> = params.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    for (name, value) in lightbench::render::parse_params(&exe.plan, &set).expect("params") {
        ex.set_param(&name, value).expect("param");
    }
    ex.render_frame(gpu, &ex.inputs(0.0)).expect("warm-up frame");
    ex
}

/// Per setup, per round, the GPU ms of the passes of each of `picks`: the setups in
/// interleaved rounds of a frame each, the order rotating from round to round.
fn interleaved(gpu: &Gpu, setups: &mut [Executor], picks: &[&dyn Fn(&str) -> bool]) -> Vec<Vec<Vec<f64>>> {
    let mut got = vec![vec![]; setups.len()];
    for r in 0..rounds() {
        for k in 0..setups.len() {
            let i = (k + r) % setups.len();
            let ex = &mut setups[i];
            ex.render_frame(gpu, &ex.inputs((r + 1) as f32 / 60.0)).expect("frame");
            let sum = |pick: &&dyn Fn(&str) -> bool| {
                ex.last_timings
                    .iter()
                    .filter(|t| pick(&t.pass))
                    .filter_map(|t| t.gpu_ms)
                    .sum::<f64>()
            };
            got[i].push(picks.iter().map(sum).collect());
        }
    }
    got
}

/// The median of one pick's figures over the rounds.
fn median(rounds: &[Vec<f64>], pick: usize) -> f64 {
    quartiles(rounds.iter().map(|r| r[pick]).collect()).1
}

/// The per-round ratio of one pick's figures, `of` over `to`: "median× [quartiles]".
fn ratio(of: &[Vec<f64>], to: &[Vec<f64>], pick: usize) -> String {
    let (q1, m, q3) = quartiles(of.iter().zip(to).map(|(a, b)| a[pick] / b[pick]).collect());
    format!("{m:.2}× [{q1:.2}–{q3:.2}]")
}

fn is_ao_pass(name: &str) -> bool {
    ["ssao", "ao_", "mvao_", "aov", "gtao"].iter().any(|p| name.starts_with(p))
}

/// A Cornell box scene file of this size calling for AO, with these lights.
fn scene(dir: &Path, (w, h): (u32, u32), lights: &str) -> PathBuf {
    let path = dir.join(format!("ao_{w}x{h}_{}.ron", lights.len()));
    let text = format!("Scene(name: \"ao\", size: ({w}, {h}), builtin: \"cornell\", lights: [{lights}], effects: [AmbientOcclusion])\n");
    std::fs::write(&path, text).expect("scene");
    path
}

/// A table row: its label, variants and parameters.
type Setup<'a> = (&'a str, Vec<(&'a str, &'a str)>, Vec<(&'a str, &'a str)>);

fn presets(gpu: &Gpu, dir: &Path) {
    println!(
        "Tables 6.6 and 6.7: AO GPU ms per frame, all AO passes (the SSAO buffer alone), medians of {} interleaved rounds of a frame per preset; × SSAO1: median [quartiles] of the per-round ratio ({})",
        rounds(),
        common::load_line()
    );
    let light = "Point(position: (0.0, 1.8, 0.0), intensity: 4.0, range: 6.0)";
    let ssao = ["ssao1", "ssao2", "ssao3", "ssao4", "ssao5"].map(|p| (p, vec![("ao", "ssao"), ("ao_preset", p)], vec![]));
    let aov = ["aov1", "aov2", "aov3"].map(|p| (p, vec![("ao", "aov"), ("aov_preset", p)], vec![]));
    // GTAO: defaults (4 slices × 16 steps), then 2 × 8 (per-pass values of its pass).
    let gtao = [
        ("gtao", vec![("ao", "gtao")], vec![]),
        (
            "gtao2x8",
            vec![("ao", "gtao")],
            vec![("ao.gtao.slices", "2"), ("ao.gtao.steps", "8")],
        ),
    ];
    let setups: Vec<Setup> = ssao.into_iter().chain(aov).chain(gtao).collect();
    for (w, h) in resolutions() {
        let s = scene(dir, (w, h), light);
        let mut ex: Vec<Executor> = setups.iter().map(|(_, v, p)| executor(gpu, &s, v, p)).collect();
        let buffer = |n: &str| n == "ssao";
        let got = interleaved(gpu, &mut ex, &[&is_ao_pass, &buffer]);
        println!("  {w}×{h}:");
        for (i, (label, _, _)) in setups.iter().enumerate() {
            let alone = match label.starts_with("ssao") {
                true => format!(" ({:.2})", median(&got[i], 1)),
                false => String::new(),
            };
            let x = if i == 0 { "1.00×".to_string() } else { ratio(&got[i], &got[0], 0) };
            println!("    {label:<8} {:>8.2}{alone:<9} {x:>22}", median(&got[i], 0));
        }
    }
    println!("  (the seed, GeForce 560 Ti, 800×600: SSAO1 5.95 ms … SSAO5 12.06 ms; AOV1 5.8–192 ms by scene)");
}

fn views(gpu: &Gpu, dir: &Path) {
    println!(
        "Multi-view AO cost per light (256×192; mvao passes and the RSMs they need; medians of {} interleaved rounds):",
        rounds()
    );
    let spot = |x: f32| {
        format!("Spot(position: ({x}, 1.9, 0.3), direction: (0.0, -1.0, -0.1), inner: 40.0, outer: 60.0, intensity: 1.0, range: 8.0)")
    };
    let mut ex: Vec<Executor> = (0..=3usize)
        .map(|n| {
            let lights: Vec<String> = (0..n).map(|i| spot(-0.5 + 0.5 * i as f32)).collect();
            executor(gpu, &scene(dir, (256, 192), &lights.join(", ")), &[("ao", "mvao")], &[])
        })
        .collect();
    let got = interleaved(gpu, &mut ex, &[&|p: &str| p.starts_with("mvao_") || p == "rsm"]);
    let camera = median(&got[0], 0);
    for (n, g) in got.iter().enumerate() {
        let ms = median(g, 0);
        println!(
            "  camera + {n} light view(s): {ms:>7.2} ms, +{:.2} ms over the camera alone",
            ms - camera
        );
    }
    println!("  per additional light: {:.2} ms on average", (median(&got[3], 0) - camera) / 3.0);
}

fn main() {
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let dir = std::env::temp_dir().join(format!("lightbench-bench-ao-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    presets(&gpu, &dir);
    views(&gpu, &dir);
    let _ = std::fs::remove_dir_all(&dir);
}
