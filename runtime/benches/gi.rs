//! `cargo bench -p lightbench --bench gi`: seed 000 Table 7.1 on the adapter at hand, for
//! what exists so far — frame time of `pipelines/deferred_gi.ron` with no indirect light
//! (None), indirect specular (IS: SSR with the RSM fallback), ambient occlusion (AO: SSAO),
//! indirect diffuse (ID, the seed's fixed 200 samples) and their combinations, as a ratio to
//! None beside the seed's published ratio, and the AO rows again with multi-view AO (the seed's
//! technique) and AO volumes; then `fixed` against `temporal` indirect diffuse: time
//! per frame, ratio, and the temporal result's error to `fixed` after 32 frames. The Cornell
//! box with a spot light at 128×128, every pass every frame. Needs a GPU adapter (lavapipe is
//! enough); `cargo test` runs it at its smallest (32×32, a frame each).

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use lightbench::scene::Scene;
use std::path::Path;
use std::time::Instant;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::Size;

const SCENE: &str = "Scene(
    name: \"gi\",
    size: (128, 128),
    builtin: \"cornell\",
    lights: [Spot(position: (0.0, 1.9, 0.3), direction: (0.0, -1.0, -0.1), inner: 40.0, outer: 60.0, intensity: 3.0, range: 8.0)],
    effects: [Shadows, IndirectDiffuse],
)
";

/// Mean ms per frame over `frames` frames, and the executor after them.
fn frames(gpu: &Gpu, scene: &Scene, option: &str, frames: u32) -> (f64, Executor) {
    frames_ao(gpu, scene, (option, "ssao"), frames)
}

/// `frames` with the AO technique chosen too.
fn frames_ao(gpu: &Gpu, scene: &Scene, (option, ao): (&str, &str), frames: u32) -> (f64, Executor) {
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred_gi.ron");
    let v = [
        ("indirect_diffuse".to_string(), option.to_string()),
        ("ao".to_string(), ao.to_string()),
    ];
    let (exe, _) = compile(gpu, &pipeline, None, scene, &v).expect("compile");
    run(gpu, &exe, scene, frames)
}

fn run(gpu: &Gpu, exe: &lightbench_compiler::Executable, scene: &Scene, frames: u32) -> (f64, Executor) {
    let mut ex = Executor::new(gpu, exe, scene).expect("executor");
    ex.set_reuse(false);
    ex.render_frame(gpu, &ex.inputs(0.0)).expect("warm-up frame");
    let t = Instant::now();
    for f in 1..=frames {
        ex.render_frame(gpu, &ex.inputs(f as f32 / 60.0)).expect("frame");
    }
    ex.wait_idle(gpu).expect("idle"); // the frames' cost, not their submission's
    (t.elapsed().as_secs_f64() * 1e3 / frames as f64, ex)
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
    let (none, _) = frames(&gpu, &scene, "off", n);
    let (fixed, fx) = frames(&gpu, &scene, "fixed", n);
    let (temporal, _) = frames(&gpu, &scene, "temporal", n);
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
    let (is, _) = frames(&gpu, &is_scene, "off", n);
    let (is_id, _) = frames(&gpu, &is_scene, "fixed", n);
    let (ao, _) = frames(&gpu, &ao_scene, "off", n);
    let (ao_id, _) = frames(&gpu, &ao_scene, "fixed", n);
    let (is_ao, _) = frames(&gpu, &is_ao_scene, "off", n);
    let (is_ao_id, _) = frames(&gpu, &is_ao_scene, "fixed", n);
    let (mvao, _) = frames_ao(&gpu, &ao_scene, ("off", "mvao"), n);
    let (mvao_id, _) = frames_ao(&gpu, &ao_scene, ("fixed", "mvao"), n);
    let (aov, _) = frames_ao(&gpu, &ao_scene, ("off", "aov"), n);
    println!("Table 7.1, {side}×{side}, Cornell box + spot light (ID: fixed 200 samples; AO: SSAO + bilateral blur unless named)");
    println!("  {:<14} {:>9} {:>10}", "", "ms/frame", "× None");
    let rows = [
        ("None", none),
        ("IS", is),
        ("AO", ao),
        ("ID", fixed),
        ("IS+AO", is_ao),
        ("IS+ID", is_id),
        ("AO+ID", ao_id),
        ("IS+AO+ID", is_ao_id),
        ("ID (temporal)", temporal),
        ("AO (mvao)", mvao),
        ("AO (mvao)+ID", mvao_id),
        ("AO (aov)", aov),
    ];
    for (name, ms) in rows {
        println!("  {name:<14} {ms:>9.2} {:>10.2}", ms / none);
    }
    println!("  (the seed, on a GPU: ID ≈ 2.5× None)");
    let reference = fx.read_texture(&gpu, "gi.indirect", 0, 0).expect("read fixed");
    let (_, tx) = frames(&gpu, &scene, "temporal", size.pick(32, 2));
    let acc = tx.read_texture(&gpu, "gi.history", 0, 0).expect("read temporal");
    let (_, one) = frames(&gpu, &scene, "temporal", 0);
    let first = one.read_texture(&gpu, "gi.history", 0, 0).expect("read temporal");
    println!("fixed vs temporal indirect diffuse:");
    println!(
        "  time per frame: fixed {fixed:.2} ms, temporal {temporal:.2} ms, temporal is {:.2}× cheaper in total frame time",
        fixed / temporal
    );
    println!(
        "  the indirect diffuse part alone (frame time minus None): fixed {:.2} ms, temporal {:.2} ms, {:.1}× cheaper (goal: 10×)",
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
