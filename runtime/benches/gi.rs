//! `cargo bench -p lightbench --bench gi`: seed 000 Table 7.1 on the adapter at hand, for
//! what exists so far — frame time of `pipelines/deferred_gi.ron` with no indirect light
//! (None), indirect specular (IS: SSR with the RSM fallback), ambient occlusion (AO: SSAO),
//! indirect diffuse (ID, the seed's fixed 200 samples) and their combinations, as a ratio to
//! None beside the seed's published ratio, and the AO rows again with multi-view AO (the seed's
//! technique) and AO volumes; then `fixed` against `temporal` indirect diffuse: time
//! per frame, ratio, and the temporal result's error to `fixed` after 32 frames. The Cornell
//! box with a spot light at 128×128, every pass every frame; the rows run in interleaved
//! rounds of a frame each (waited for), the order rotating: figures are medians, ratios the
//! median and quartiles of the per-round ratio. Needs a GPU adapter (lavapipe is enough);
//! `cargo test` runs it at its smallest (32×32, a round).

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use lightbench::scene::Scene;
use std::path::Path;
use std::time::Instant;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{quartiles, Size};

const SCENE: &str = "Scene(
    name: \"gi\",
    size: (128, 128),
    builtin: \"cornell\",
    lights: [Spot(position: (0.0, 1.9, 0.3), direction: (0.0, -1.0, -0.1), inner: 40.0, outer: 60.0, intensity: 3.0, range: 8.0)],
    effects: [Shadows, IndirectDiffuse],
)
";

/// An executor of `deferred_gi.ron` with this indirect diffuse option and AO technique, after
/// a warm-up frame.
fn executor(gpu: &Gpu, scene: &Scene, (option, ao): (&str, &str)) -> Executor {
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred_gi.ron");
    let v = [
        ("indirect_diffuse".to_string(), option.to_string()),
        ("ao".to_string(), ao.to_string()),
    ];
    let (exe, _) = compile(gpu, &pipeline, None, scene, &v).expect("compile");
    let mut ex = Executor::new(gpu, &exe, scene).expect("executor");
    ex.set_reuse(false);
    ex.render_frame(gpu, &ex.inputs(0.0)).expect("warm-up frame");
    ex
}

/// Wall ms of frame `f`, waited for: the frame's cost, not its submission's.
fn frame_ms(gpu: &Gpu, ex: &mut Executor, f: usize) -> f64 {
    let t = Instant::now();
    ex.render_frame(gpu, &ex.inputs(f as f32 / 60.0)).expect("frame");
    ex.wait_idle(gpu).expect("idle");
    t.elapsed().as_secs_f64() * 1e3
}

/// `frames` frames more of an executor (an accumulation run).
fn run(gpu: &Gpu, ex: &mut Executor, frames: usize) {
    for f in 1..=frames {
        frame_ms(gpu, ex, f);
    }
}

fn rmse(a: &[f32], b: &[f32]) -> f64 {
    let sum: f64 = a
        .chunks_exact(4)
        .zip(b.chunks_exact(4))
        .flat_map(|(p, q)| (0..3).map(move |c| ((p[c] - q[c]) as f64).powi(2)))
        .sum();
    (sum / (a.len() / 4 * 3).max(1) as f64).sqrt()
}

fn main() {
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let dir = std::env::temp_dir().join(format!("lightbench-bench-gi-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let size = Size::from_args();
    // The smoke run: 32×32, one frame a configuration.
    let (n, side) = (size.pick(8, 1), size.pick(128, 32));
    let scene_text = SCENE.replace("size: (128, 128)", &format!("size: ({side}, {side})"));
    std::fs::write(dir.join("gi.ron"), &scene_text).expect("scene");
    let scene = lightbench::scene::load(dir.join("gi.ron").to_str().expect("path")).expect("scene");
    // The other rows: the same scene calling for SSR (IS) and/or ambient occlusion (AO) too.
    let with = |effects: &str, tag: &str| {
        let text = scene_text.replace(
            "effects: [Shadows, IndirectDiffuse]",
            &format!("effects: [Shadows, IndirectDiffuse, {effects}]"),
        );
        std::fs::write(dir.join(format!("{tag}.ron")), text).expect("scene");
        lightbench::scene::load(dir.join(format!("{tag}.ron")).to_str().expect("path")).expect("scene")
    };
    let (is_scene, ao_scene, is_ao_scene) = (
        with("Ssr", "is"),
        with("AmbientOcclusion", "ao"),
        with("Ssr, AmbientOcclusion", "isao"),
    );
    let rows: [(&str, &Scene, (&str, &str)); 12] = [
        ("None", &scene, ("off", "ssao")),
        ("IS", &is_scene, ("off", "ssao")),
        ("AO", &ao_scene, ("off", "ssao")),
        ("ID", &scene, ("fixed", "ssao")),
        ("IS+AO", &is_ao_scene, ("off", "ssao")),
        ("IS+ID", &is_scene, ("fixed", "ssao")),
        ("AO+ID", &ao_scene, ("fixed", "ssao")),
        ("IS+AO+ID", &is_ao_scene, ("fixed", "ssao")),
        ("ID (temporal)", &scene, ("temporal", "ssao")),
        ("AO (mvao)", &ao_scene, ("off", "mvao")),
        ("AO (mvao)+ID", &ao_scene, ("fixed", "mvao")),
        ("AO (aov)", &ao_scene, ("off", "aov")),
    ];
    let mut ex: Vec<Executor> = rows.iter().map(|(_, sc, o)| executor(&gpu, sc, *o)).collect();
    // Interleaved rounds of a frame of each row, the order rotating from round to round.
    let mut ms: Vec<Vec<f64>> = vec![vec![]; rows.len()];
    for r in 0..n {
        for k in 0..rows.len() {
            let i = (k + r) % rows.len();
            ms[i].push(frame_ms(&gpu, &mut ex[i], r + 1));
        }
    }
    let median = |i: usize| quartiles(ms[i].clone()).1;
    let ratio = |i: usize, to: usize| quartiles(ms[i].iter().zip(&ms[to]).map(|(a, b)| a / b).collect());
    println!(
        "Table 7.1, {side}×{side}, Cornell box + spot light (ID: fixed 200 samples; AO: SSAO + bilateral blur unless named); wall ms per frame waited for, medians of {n} interleaved rounds of a frame per row; × None: median [quartiles] of the per-round ratio ({})",
        common::load_line()
    );
    println!("  {:<14} {:>9} {:>22}", "", "ms/frame", "× None");
    for (i, (name, _, _)) in rows.iter().enumerate() {
        let (q1, m, q3) = ratio(i, 0);
        println!("  {name:<14} {:>9.2} {:>22}", median(i), format!("{m:.2} [{q1:.2}–{q3:.2}]"));
    }
    println!("  (the seed, on a GPU: ID ≈ 2.5× None)");
    let (none, fixed, temporal) = (median(0), median(3), median(8));
    let reference = ex[3].read_texture(&gpu, "gi.indirect", 0, 0).expect("read fixed");
    let mut tx = executor(&gpu, &scene, ("temporal", "ssao"));
    run(&gpu, &mut tx, size.pick(32, 2));
    let acc = tx.read_texture(&gpu, "gi.history", 0, 0).expect("read temporal");
    let one = executor(&gpu, &scene, ("temporal", "ssao"));
    let first = one.read_texture(&gpu, "gi.history", 0, 0).expect("read temporal");
    let (q1, m, q3) = ratio(3, 8);
    println!("fixed vs temporal indirect diffuse:");
    println!(
        "  time per frame: fixed {fixed:.2} ms, temporal {temporal:.2} ms, temporal is {m:.2}× [{q1:.2}–{q3:.2}] cheaper in total frame time"
    );
    println!(
        "  the indirect diffuse part alone (frame time minus None, medians): fixed {:.2} ms, temporal {:.2} ms, {:.1}× cheaper (goal: 10×)",
        fixed - none,
        temporal - none,
        (fixed - none) / (temporal - none).max(1e-6)
    );
    println!(
        "  RMSE to fixed: temporal after 1 frame {:.4}, after {} frames {:.4}",
        rmse(&first.rgba, &reference.rgba),
        size.pick(32, 2),
        rmse(&acc.rgba, &reference.rgba)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
