//! `cargo bench -p lightbench --bench diff`: what `lightbench diff` costs beyond rendering the
//! two sides — reading back, metrics (RMSE, FLIP, SSIM), heat-maps, side-by-side PNGs and the
//! reports — for `deferred.ron` on the Cornell box at 512×512 (the output and 12 more resource
//! slices: G-buffer, depth, six cube faces, HDR, luminance). Goal: under 20% of the two
//! renders' time. Not a test; needs a GPU adapter (lavapipe is enough).

use lightbench::diff::{self, report, spec, Options, Planned};
use lightbench::gpu::{DeviceOptions, Gpu};
use lightbench::scene::builtin;
use std::path::Path;
use std::time::Instant;

/// `lightbench diff`'s default.
const FRAMES: u32 = 8;
const ROUNDS: u32 = 3;

fn main() {
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let mut scene = builtin::cornell();
    scene.size = (512, 512);
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
    let side = |config: &str| {
        let variants = vec![("cube_shadow".to_string(), config.to_string())];
        let (exe, _) = lightbench::render::compile(&gpu, &pipeline, None, &scene, &variants).expect("compile");
        let text = format!("{}@cube_shadow={config}", pipeline.display());
        Planned {
            side: spec::parse(&text).expect("side"),
            exe,
            params: vec![],
        }
    };
    let (a, b) = (side("classic"), side("multiview"));
    let out = std::env::temp_dir().join(format!("lightbench-bench-diff-{}", std::process::id()));
    let opts = Options {
        frames: FRAMES,
        resources: None,
        out: out.clone(),
        fail_above: vec![],
    };
    let (mut t_render, mut t_diff, mut slices) = (0.0, 0.0, 0);
    for _ in 0..ROUNDS {
        let start = Instant::now();
        diff::render(&gpu, (&a, &b), &scene, FRAMES).expect("render");
        t_render += start.elapsed().as_secs_f64();
        let start = Instant::now();
        let r = diff::run(&gpu, (&a, &b), &scene, &opts).expect("diff");
        let md = report::markdown(&r);
        let html = report::html(&r, &out).expect("html");
        t_diff += start.elapsed().as_secs_f64();
        slices = r.images.len();
        assert!(!md.is_empty() && !html.is_empty());
    }
    let (render_ms, diff_ms) = (t_render * 1e3 / ROUNDS as f64, t_diff * 1e3 / ROUNDS as f64);
    println!(
        "diff of deferred.ron (cube_shadow classic vs multiview), Cornell box 512×512, {FRAMES} frames a side, {slices} slices compared:"
    );
    println!("  rendering both sides       {render_ms:>8.1} ms");
    println!("  the whole diff             {diff_ms:>8.1} ms");
    println!(
        "  overhead beyond rendering  {:>8.1} ms = {:.0}% of the renders (goal < 20%)",
        diff_ms - render_ms,
        100.0 * (diff_ms - render_ms) / render_ms
    );
    let _ = std::fs::remove_dir_all(&out);
}
