//! `cargo bench -p lightbench --bench diff`: what `lightbench diff` costs beyond rendering the
//! two sides — reading back, metrics (RMSE, FLIP, SSIM), heat-maps, side-by-side PNGs and the
//! reports — for `deferred.ron` on the Cornell box at 512×512 (the output and 12 more resource
//! slices: G-buffer, depth, six cube faces, HDR, luminance). Goal: under 20% of the two
//! renders' time, as the median and quartiles of the per-round ratio from interleaved rounds.
//! Needs a GPU adapter (lavapipe is enough); `cargo test` runs it at its smallest.

use lightbench::diff::{self, report, spec, Options, Planned};
use lightbench::gpu::{DeviceOptions, Gpu};
use lightbench::scene::builtin;
use std::path::Path;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{interleaved, ms, quartiles, Size};

fn main() {
    let size = Size::from_args();
    // `lightbench diff`'s default frames; the smoke run: one frame, one round, 64×64.
    let (frames, rounds, side_px) = (size.pick(8, 1), size.pick(8, 1), size.pick(512, 64));
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let mut scene = builtin::cornell();
    scene.size = (side_px, side_px);
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
        frames,
        resources: None,
        out: out.clone(),
        fail_above: vec![],
    };
    let mut slices = 0;
    let p = interleaved(
        rounds,
        // Rendering alone, both sides' frames waited for (the diff waits for them too: it
        // reads them back).
        || {
            ms(|| {
                let (mut ea, mut eb, _) = diff::render(&gpu, (&a, &b), &scene, frames).expect("render");
                ea.wait_idle(&gpu).expect("idle");
                eb.wait_idle(&gpu).expect("idle");
            })
        },
        || {
            ms(|| {
                let r = diff::run(&gpu, (&a, &b), &scene, &opts).expect("diff");
                let md = report::markdown(&r);
                let html = report::html(&r, &out).expect("html");
                slices = r.images.len();
                assert!(!md.is_empty() && !html.is_empty());
            })
        },
    );
    println!(
        "diff of deferred.ron (cube_shadow classic vs multiview), Cornell box {side_px}×{side_px}, {frames} frames a side, {slices} slices compared, ms:"
    );
    println!("{}", p.report(("rendering both sides", "the whole diff"), "ms"));
    let (q1, m, q3) = p.ratio();
    println!(
        "  beyond rendering: {:.0}% of the renders (quartiles {:.0}–{:.0}%; goal < 20%)",
        100.0 * (m - 1.0),
        100.0 * (q1 - 1.0),
        100.0 * (q3 - 1.0)
    );
    breakdown(&gpu, (&a, &b), &scene, (&opts, rounds));
    let _ = std::fs::remove_dir_all(&out);
}

/// What dominates the diff beyond rendering: its stages timed apart (medians over `rounds`),
/// the rendering first (frames waited for).
fn breakdown(gpu: &Gpu, (a, b): (&Planned, &Planned), scene: &lightbench::scene::Scene, (opts, rounds): (&Options, usize)) {
    let (pa, pb) = (&a.exe.plan, &b.exe.plan);
    let (names, _) = diff::pairs(pa, pb, None).expect("pairs");
    let mut stages: [Vec<f64>; 3] = Default::default();
    for _ in 0..rounds {
        let t = std::time::Instant::now();
        let (mut ea, mut eb, _) = diff::render(gpu, (a, b), scene, opts.frames).expect("render");
        ea.wait_idle(gpu).expect("idle");
        eb.wait_idle(gpu).expect("idle");
        stages[0].push(t.elapsed().as_secs_f64() * 1e3);
        let t = std::time::Instant::now();
        let images = diff::compare_all(gpu, (&ea, &eb), &names, &opts.out).expect("compare");
        stages[1].push(t.elapsed().as_secs_f64() * 1e3);
        let mut r = diff::structure(a, b, &scene.name, scene.size);
        r.images = images;
        stages[2].push(ms(|| {
            let _ = report::markdown(&r);
            report::html(&r, &opts.out).expect("html");
        }));
    }
    let [render, compare, reports] = stages.map(|v| quartiles(v).1);
    println!(
        "  by stage (medians): rendering {render:.1} ms; reading back and comparing {} resources (metrics, heat-maps, PNGs on rayon's threads) {compare:.1} ms = {:.0}% of the renders; reports {reports:.1} ms",
        names.len(),
        100.0 * compare / render
    );
}
