//! `cargo bench -p lightbench --bench ao`: seed 003 Tables 6.6 and 6.7 on the adapter at hand
//! — GPU time of each SSAO preset (all AO passes, and the SSAO buffer alone) and each AOV
//! preset at three resolutions, with ratios to SSAO1, and GTAO (the modern baseline) at its
//! defaults and at 2 slices × 8 steps beside them — and multi-view AO's cost per light
//! (seed 000 §6.3.2): its passes with 0 to 3 directional or spot lights beyond the camera.
//! `pipelines/deferred_gi.ron` on the Cornell box; GPU time from timestamp queries, the mean
//! over the frames after a warm-up, every pass every frame. Needs a GPU adapter (lavapipe is
//! enough); `cargo test` runs it at its smallest (32×24, one frame).

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use std::path::{Path, PathBuf};

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::Size;

/// Frames measured after the warm-up: 4 (1 in the smoke run).
fn frames() -> u32 {
    Size::from_args().pick(4, 1)
}

/// The tables' resolutions (one small one in the smoke run).
fn resolutions() -> Vec<(u32, u32)> {
    Size::from_args().pick(vec![(128, 96), (256, 192), (512, 384)], vec![(32, 24)])
}

/// Mean GPU ms per frame of the passes `pick` selects.
fn gpu_ms(gpu: &Gpu, scene: &Path, variants: &[(&str, &str)], pick: impl Fn(&str) -> bool) -> f64 {
    gpu_ms_with(gpu, scene, variants, &[], pick)
}

/// `gpu_ms` with parameter overrides.
fn gpu_ms_with(gpu: &Gpu, scene: &Path, variants: &[(&str, &str)], params: &[(&str, &str)], pick: impl Fn(&str) -> bool) -> f64 {
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
    let mut total = 0.0;
    for f in 1..=frames() {
        ex.render_frame(gpu, &ex.inputs(f as f32 / 60.0)).expect("frame");
        total += ex
            .last_timings
            .iter()
            .filter(|t| pick(&t.pass))
            .filter_map(|t| t.gpu_ms)
            .sum::<f64>();
    }
    total / frames() as f64
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

fn presets(gpu: &Gpu, dir: &Path) {
    println!("Tables 6.6 and 6.7: AO GPU ms per frame (all AO passes / the SSAO buffer alone), × SSAO1 in brackets");
    print!("  {:<7}", "preset");
    for (w, h) in resolutions() {
        print!(" {:>28}", format!("{w}×{h}"));
    }
    println!();
    let light = "Point(position: (0.0, 1.8, 0.0), intensity: 4.0, range: 6.0)";
    let scenes: Vec<PathBuf> = resolutions().into_iter().map(|r| scene(dir, r, light)).collect();
    // SSAO1 first: its times are the baseline of every ratio at that resolution.
    let mut base: Vec<f64> = vec![];
    for p in ["ssao1", "ssao2", "ssao3", "ssao4", "ssao5"] {
        print!("  {p:<7}");
        for (i, s) in scenes.iter().enumerate() {
            let all = gpu_ms(gpu, s, &[("ao", "ssao"), ("ao_preset", p)], is_ao_pass);
            let buffer = gpu_ms(gpu, s, &[("ao", "ssao"), ("ao_preset", p)], |n| n == "ssao");
            if p == "ssao1" {
                base.push(all);
            }
            print!(" {:>28}", format!("{all:.2} / {buffer:.2} [{:.2}×]", all / base[i]));
        }
        println!();
    }
    for p in ["aov1", "aov2", "aov3"] {
        print!("  {p:<7}");
        for (s, b) in scenes.iter().zip(&base) {
            let all = gpu_ms(gpu, s, &[("ao", "aov"), ("aov_preset", p)], is_ao_pass);
            print!(" {:>28}", format!("{all:.2} [{:.2}×]", all / b));
        }
        println!();
    }
    // GTAO: defaults (4 slices × 16 steps), then 2 × 8 (per-pass values of its pass).
    for (label, extra) in [("gtao", vec![]), ("gtao2x8", vec![("ao.gtao.slices", "2"), ("ao.gtao.steps", "8")])] {
        print!("  {label:<7}");
        for (s, b) in scenes.iter().zip(&base) {
            let all = gpu_ms_with(gpu, s, &[("ao", "gtao")], &extra, is_ao_pass);
            print!(" {:>28}", format!("{all:.2} [{:.2}×]", all / b));
        }
        println!();
    }
    println!("  (the seed, GeForce 560 Ti, 800×600: SSAO1 5.95 ms … SSAO5 12.06 ms; AOV1 5.8–192 ms by scene)");
}

fn views(gpu: &Gpu, dir: &Path) {
    println!("Multi-view AO cost per light (256×192; mvao passes and the RSMs they need):");
    let spot = |x: f32| {
        format!("Spot(position: ({x}, 1.9, 0.3), direction: (0.0, -1.0, -0.1), inner: 40.0, outer: 60.0, intensity: 1.0, range: 8.0)")
    };
    let mut first = None;
    let mut last = 0.0;
    for n in 0..=3usize {
        let lights: Vec<String> = (0..n).map(|i| spot(-0.5 + 0.5 * i as f32)).collect();
        let s = scene(dir, (256, 192), &lights.join(", "));
        let ms = gpu_ms(gpu, &s, &[("ao", "mvao")], |p| p.starts_with("mvao_") || p == "rsm");
        let b = *first.get_or_insert(ms);
        println!(
            "  camera + {n} light view(s): {ms:>7.2} ms, +{:.2} ms over the camera alone",
            ms - b
        );
        last = ms;
    }
    println!("  per additional light: {:.2} ms on average", (last - first.unwrap_or(0.0)) / 3.0);
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
