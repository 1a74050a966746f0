//! `cargo bench -p lightbench --bench diff`: what `lightbench diff` costs beyond rendering the
//! two sides — reading back, metrics (RMSE, FLIP, SSIM), heat-maps, side-by-side PNGs and the
//! reports — for `deferred.ron` on the Cornell box at 512×512 (the output and 13 more resource
//! slices: G-buffer, depth, six cube faces, HDR, luminance tiles and value), in two cases:
//! classic against multiview cube shadows (every slice equal, as a variant that should not
//! change the image leaves it) and 3×3 PCF of the cube shadows off against on (the output and
//! the HDR image differ). Goal: under 20% of the two renders' time, as the median and
//! quartiles of the per-round ratio from interleaved rounds; then the stages timed apart.
//! Needs a GPU adapter (lavapipe is enough); `cargo test` runs it at its smallest.

use lightbench::diff::{self, report, spec, Options, Planned};
use lightbench::gpu::{DeviceOptions, Gpu};
use lightbench::scene::{builtin, Scene};
use lightbench_compiler::Workspace;
use std::path::Path;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{interleaved, ms, quartiles, Size};

/// One side as `lightbench diff` plans it: `deferred.ron@settings`.
fn side(gpu: &Gpu, scene: &Scene, settings: &str) -> Planned {
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
    let side = spec::parse(&format!("{}@{settings}", pipeline.display())).expect("side");
    let c = lightbench::render::plan_configured(&Workspace::disk(), (&pipeline, None), (&gpu.profile, scene), &side.settings)
        .unwrap_or_else(|e| panic!("{e}"));
    Planned {
        side,
        exe: c.exe,
        params: c.params,
    }
}

fn main() {
    let size = Size::from_args();
    // `lightbench diff`'s default frames; the smoke run: one frame, one round, 64×64.
    let (frames, rounds, side_px) = (size.pick(8, 1), size.pick(8, 1), size.pick(512, 64));
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let mut scene = builtin::cornell();
    scene.size = (side_px, side_px);
    let out = std::env::temp_dir().join(format!("lightbench-bench-diff-{}", std::process::id()));
    let opts = Options {
        frames,
        resources: None,
        out: out.clone(),
        fail_above: vec![],
    };
    for (a, b) in [
        ("cube_shadow=classic", "cube_shadow=multiview"),
        ("cube.pcf=false", "cube.pcf=true"),
    ] {
        let sides = (side(&gpu, &scene, a), side(&gpu, &scene, b));
        case(&gpu, &scene, (&sides.0, &sides.1), (&opts, rounds));
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// A side's settings, as given after the `@`.
fn settings(p: &Planned) -> &str {
    p.side.label.rsplit('@').next().unwrap_or(&p.side.label)
}

/// The whole diff against rendering alone, in interleaved rounds; then its stages.
fn case(gpu: &Gpu, scene: &Scene, (a, b): (&Planned, &Planned), (opts, rounds): (&Options, usize)) {
    let (mut slices, mut differ) = (0, 0);
    let p = interleaved(
        rounds,
        // Rendering alone, both sides' frames waited for (the diff waits for them too: it
        // reads them back).
        || {
            ms(|| {
                let (mut ea, mut eb, _) = diff::render(gpu, (a, b), scene, opts.frames).expect("render");
                ea.wait_idle(gpu).expect("idle");
                eb.wait_idle(gpu).expect("idle");
            })
        },
        || {
            ms(|| {
                let r = diff::run(gpu, (a, b), scene, opts).expect("diff");
                let md = report::markdown(&r);
                let html = report::html(&r, &opts.out).expect("html");
                slices = r.images.len();
                differ = r.images.iter().filter(|i| i.metrics.max_abs > 0.0).count();
                assert!(!md.is_empty() && !html.is_empty());
            })
        },
    );
    let (w, h) = scene.size;
    println!(
        "diff of deferred.ron, {} against {}, Cornell box {w}×{h}, {} frames a side, {slices} slices compared ({differ} differing), ms:",
        settings(a),
        settings(b),
        opts.frames
    );
    println!("{}", p.report(("rendering both sides", "the whole diff"), "ms"));
    let (q1, m, q3) = p.ratio();
    println!(
        "  beyond rendering: {:.0}% of the renders (quartiles {:.0}–{:.0}%; goal < 20%)",
        100.0 * (m - 1.0),
        100.0 * (q1 - 1.0),
        100.0 * (q3 - 1.0)
    );
    breakdown(gpu, (a, b), scene, (opts, rounds));
}

/// What dominates the diff beyond rendering: its stages timed apart (medians over `rounds`),
/// the rendering first (frames waited for).
fn breakdown(gpu: &Gpu, (a, b): (&Planned, &Planned), scene: &Scene, (opts, rounds): (&Options, usize)) {
    let (pa, pb) = (&a.exe.plan, &b.exe.plan);
    let (names, _) = diff::pairs(pa, pb, None).expect("pairs");
    let mut stages: [Vec<f64>; 4] = Default::default();
    for _ in 0..rounds {
        let t = std::time::Instant::now();
        let (mut ea, mut eb, _) = diff::render(gpu, (a, b), scene, opts.frames).expect("render");
        ea.wait_idle(gpu).expect("idle");
        eb.wait_idle(gpu).expect("idle");
        stages[0].push(t.elapsed().as_secs_f64() * 1e3);
        let t = std::time::Instant::now();
        let images = diff::compare_all(gpu, (&ea, &eb), &names, &opts.out).expect("compare");
        stages[1].push(t.elapsed().as_secs_f64() * 1e3);
        // FLIP of the output alone (where the sides differ: equal ones are not measured).
        let (oa, ob) = (ea.read_texture(gpu, names[0].0, 0, 0), eb.read_texture(gpu, names[0].1, 0, 0));
        let (oa, ob) = (oa.expect("output"), ob.expect("output"));
        stages[3].push(ms(|| drop(diff::metrics::flip(&oa, &ob))));
        let mut r = diff::structure(a, b, &scene.name, scene.size);
        r.images = images;
        stages[2].push(ms(|| {
            let _ = report::markdown(&r);
            report::html(&r, &opts.out).expect("html");
        }));
    }
    let [render, compare, reports, flip] = stages.map(|v| quartiles(v).1);
    println!(
        "  by stage (medians): rendering {render:.1} ms; reading back and comparing {} resources (metrics, heat-maps, PNGs on rayon's threads) {compare:.1} ms = {:.0}% of the renders; reports {reports:.1} ms",
        names.len(),
        100.0 * compare / render
    );
    println!(
        "  FLIP of the output alone, were the sides to differ: {flip:.1} ms on one core = {:.0}% of the renders (the comparing's critical path where they do)",
        100.0 * flip / render
    );
}
