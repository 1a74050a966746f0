//! `cargo bench -p lightbench --bench lighting`: what the shadow and lighting variants of
//! `pipelines/deferred.ron` cost on the adapter at hand. Needs a GPU adapter (lavapipe is
//! enough); `cargo test` runs all four parts at their smallest.
//!
//! 1. Point-light shadows, seed 004 §4.5 style: the four `cube_shadow` options on the Cornell
//!    box and the colonnade (with a point light among its columns) at cube resolutions 256,
//!    512 and 1024 (the bench edits the pipeline's map sizes in memory): shadow-pass GPU ms,
//!    their CPU encode µs, and wall-clock frame ms in 8 interleaved rounds of a frame of each
//!    option (medians), each with the per-round speed-up over `classic` (median [quartiles]),
//!    beside the seed's published single-pass speed-ups.
//! 2. Lighting models, seed 003 Fig. 6.1 style: the four `lighting` options on `many_lights`
//!    with 1, 10, 100 and 1000 lights at three resolutions: frame GPU ms, and where deferred
//!    overtakes forward.
//! 3. Merged repetitions (`-- merge`): the deferred models with 100 and 1000 lights at 512×384,
//!    a light pass's repetitions sharing one render pass (the default) against a render pass
//!    each (`Executor::set_merge(false)`), in interleaved rounds: the per-round ratios of frame
//!    GPU and wall ms and of the light passes' GPU ms (median and quartiles); and untimed,
//!    where the light pass also continues ambient's render pass (`continues`): frame wall ms
//!    merged vs apart.
//! 4. Area lights (`-- area`): the `area_light` pass (`area_lights = ltc`; the same with the
//!    fit's residual off, `area.residual` 0, as the baseline; and `ltc_shadowed`) on the Cornell
//!    box with 2, 32 and 512 emissive triangles (a grid of small lamps under the ceiling) at
//!    128×128, 256×256 and 512×512: pass GPU ms and µs per triangle.
//!
//! Every pass runs every frame (no reuse), each frame waited for; figures are means over the
//! frames after a warm-up.

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::scene::{builtin, Scene};
use lightbench_compiler::ir::ParamValue;
use lightbench_compiler::vfs::MemoryVfs;
use lightbench_compiler::workspace::Workspace;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{load_line, quartiles, Size};

/// The bench, or its smoke run under `cargo test` (small sizes, one of each).
fn full() -> bool {
    Size::from_args() == Size::Full
}

/// Means over one frame's passes.
#[derive(Clone, Copy, Default)]
struct Cost {
    /// GPU ms of the passes picked.
    picked_ms: f64,
    /// CPU encode µs of the passes picked.
    picked_encode_us: f64,
    /// GPU ms of every pass.
    frame_gpu_ms: f64,
    /// Wall-clock ms of `render_frame`, each frame waited for (encode, submit, wait,
    /// timestamp read-back).
    frame_wall_ms: f64,
}

/// The bundled pipelines and shaders in memory, with `edit` applied to `deferred.ron`.
fn project(edit: impl Fn(String) -> String) -> Workspace {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let vfs = Arc::new(MemoryVfs::new());
    fn add(vfs: &MemoryVfs, from: &Path, to: &Path) {
        for e in std::fs::read_dir(from).expect("read_dir") {
            let p = e.expect("entry").path();
            let dest = to.join(p.file_name().expect("name"));
            if p.is_dir() {
                add(vfs, &p, &dest);
            } else {
                vfs.write(&dest, std::fs::read_to_string(&p).expect("read"));
            }
        }
    }
    add(&vfs, &root.join("shaders"), Path::new("mem/shaders"));
    add(&vfs, &root.join("pipelines"), Path::new("mem/pipelines"));
    let text = std::fs::read_to_string(root.join("pipelines/deferred.ron")).expect("deferred.ron");
    vfs.write("mem/pipelines/deferred.ron", edit(text));
    Workspace::new(vfs)
}

/// Parameters set on the executor before a measurement (`Executor::set_param`).
type Set<'a> = [(&'a str, ParamValue)];

/// An executor for these variants, parameters, merging and timing, warmed by one frame.
fn executor(gpu: &Gpu, ws: &Workspace, scene: &Scene, (variants, params, merge, timed): (&[(&str, &str)], &Set, bool, bool)) -> Executor {
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let pipeline = Path::new("mem/pipelines/deferred.ron");
    let (exe, _) = lightbench::render::compile_in(ws, gpu, pipeline, None, scene, &v).unwrap_or_else(|e| panic!("{e}"));
    for c in &exe.plan.variants {
        if let Some((_, want)) = variants.iter().find(|(k, _)| *k == c.variant) {
            assert_eq!(c.option, *want, "{} fell back", c.variant);
        }
    }
    let mut ex = Executor::new(gpu, &exe, scene).expect("executor");
    for (name, value) in params {
        ex.set_param(name, value.clone()).expect("a parameter of the pipeline");
    }
    ex.set_reuse(false);
    ex.set_merge(merge);
    ex.set_timing(timed);
    // Each frame waited for: a frame's wall time is its cost, timed or not.
    ex.set_frames_in_flight(0);
    ex.render_frame(gpu, &ex.inputs(0.0)).expect("warm-up frame");
    ex
}

/// Means over frames `first..first + frames`.
fn cost(gpu: &Gpu, ex: &mut Executor, (first, frames): (u32, u32), pick: &dyn Fn(&str) -> bool) -> Cost {
    let mut sum = Cost::default();
    for f in first..first + frames {
        let inputs = ex.inputs(f as f32 / 60.0);
        let start = Instant::now();
        ex.render_frame(gpu, &inputs).expect("frame");
        sum.frame_wall_ms += start.elapsed().as_secs_f64() * 1e3;
        for t in &ex.last_timings {
            let ms = t.gpu_ms.unwrap_or(0.0);
            sum.frame_gpu_ms += ms;
            if pick(&t.pass) {
                sum.picked_ms += ms;
                sum.picked_encode_us += t.cpu_encode_us;
            }
        }
    }
    let n = frames as f64;
    Cost {
        picked_ms: sum.picked_ms / n,
        picked_encode_us: sum.picked_encode_us / n,
        frame_gpu_ms: sum.frame_gpu_ms / n,
        frame_wall_ms: sum.frame_wall_ms / n,
    }
}

const CUBE_OPTIONS: [&str; 4] = ["classic", "multiview", "instanced", "dual_paraboloid"];

/// `deferred.ron` with point-light shadow maps of `n`² texels per face (the atlas 3n × 2n).
fn with_cube_size(n: u32) -> impl Fn(String) -> String {
    move |text: String| {
        let edited = text
            .replace("size: Fixed(512, 512), layers: 6", &format!("size: Fixed({n}, {n}), layers: 6"))
            .replace("size: Fixed(1536, 1024)", &format!("size: Fixed({}, {})", 3 * n, 2 * n))
            .replace("size: Fixed(512, 512), layers: 2", &format!("size: Fixed({n}, {n}), layers: 2"));
        assert!(n == 512 || edited != text, "the cube map sizes were not found in deferred.ron");
        edited
    }
}

fn cube_shadows(gpu: &Gpu) {
    println!(
        "Point-light shadows (seed 004 §4.5): shadow passes GPU ms / their CPU encode µs / frame wall ms, × classic in brackets ({})",
        load_line()
    );
    let mut colonnade = builtin::colonnade();
    colonnade.size = if full() { (256, 128) } else { (64, 32) };
    colonnade.lights.push(lightbench::scene::Light::point(
        glam::Vec3::new(0.0, 2.0, 0.0),
        glam::Vec3::ONE,
        20.0,
        12.0,
    ));
    let mut cornell = builtin::cornell();
    if !full() {
        cornell.size = (64, 64);
    }
    let scenes = [cornell, colonnade];
    let is_shadow = |p: &str| p.starts_with("shadow_cube") || p.starts_with("shadow_paraboloid");
    for scene in &scenes {
        for n in if full() { vec![256, 512, 1024] } else { vec![64] } {
            let ws = project(with_cube_size(n));
            println!("  {} ({}×{}), cube {n}²:", scene.name, scene.size.0, scene.size.1);
            let rounds = if full() { 8 } else { 1 };
            let mut sides: Vec<Executor> = CUBE_OPTIONS
                .iter()
                .map(|o| executor(gpu, &ws, scene, (&[("cube_shadow", o)], &[], true, true)))
                .collect();
            // Rounds of a frame of each option, the order turning from round to round.
            let mut costs: Vec<Vec<Cost>> = vec![vec![]; CUBE_OPTIONS.len()];
            for round in 0..rounds {
                for k in 0..sides.len() {
                    let i = (k + round) % sides.len();
                    costs[i].push(cost(gpu, &mut sides[i], (1 + round as u32, 1), &is_shadow));
                }
            }
            // Speed-up over classic, per round: classic's figure over the option's.
            let cell = |i: usize, of: fn(&Cost) -> f64| {
                let per_round: Vec<f64> = costs[0].iter().zip(&costs[i]).map(|(b, c)| of(b) / of(c).max(1e-9)).collect();
                let (q1, m, q3) = quartiles(per_round);
                let value = quartiles(costs[i].iter().map(of).collect()).1;
                format!("{value:>8.2} ({m:.2}× [{q1:.2}–{q3:.2}])")
            };
            for (i, option) in CUBE_OPTIONS.iter().enumerate() {
                println!(
                    "    {option:<16} {:>28} ms  {:>28} µs  {:>28} ms",
                    cell(i, |c| c.picked_ms),
                    cell(i, |c| c.picked_encode_us),
                    cell(i, |c| c.frame_wall_ms)
                );
            }
        }
    }
    println!("  (medians of interleaved rounds of a frame each; × classic: how many times faster than classic, per round. Seed 004 §4.5, on its GPUs: single-pass");
    println!("   methods 1.27×–3.87× the FPS of 6-pass cube shadows; the goal here: single-pass ≥ 1.5× on");
    println!("   the colonnade. lavapipe rasterizes on the CPU, where the saving is in vertex work and passes.)");
}

const MODELS: [&str; 4] = ["forward_single", "forward_multi", "deferred_fullscreen", "deferred_volumes"];

fn lighting_models(gpu: &Gpu) {
    println!(
        "Lighting models (seed 003 Fig. 6.1): frame GPU ms on many_lights (point lights, no shadows); per light count, the four models in interleaved rounds of a frame each ({}), the order rotating: medians ({})",
        if full() { "4 rounds, 2 at 1000 lights" } else { "1 round" },
        load_line()
    );
    let ws = project(|t| t);
    let sizes = if full() {
        vec![(128, 96), (256, 192), (512, 384)]
    } else {
        vec![(32, 24)]
    };
    for (w, h) in sizes {
        println!("  {w}×{h}:");
        print!("    {:<20}", "lights");
        let counts = if full() { vec![1usize, 10, 100, 1000] } else { vec![1, 10] };
        for &n in &counts {
            print!(" {n:>10}");
        }
        println!();
        // Per light count, per model: the median frame GPU ms.
        let columns: Vec<Vec<f64>> = counts
            .iter()
            .map(|&n| {
                let mut scene = builtin::many_lights(n);
                scene.size = (w, h);
                let rounds = if !full() {
                    1
                } else if n >= 1000 {
                    2
                } else {
                    4
                };
                let mut ex: Vec<Executor> = MODELS
                    .iter()
                    .map(|m| executor(gpu, &ws, &scene, (&[("lighting", m)], &[], true, true)))
                    .collect();
                let mut ms: Vec<Vec<f64>> = vec![vec![]; MODELS.len()];
                for r in 0..rounds {
                    for k in 0..MODELS.len() {
                        let i = (k + r) % MODELS.len();
                        ms[i].push(cost(gpu, &mut ex[i], (r as u32 + 1, 1), &|_| false).frame_gpu_ms);
                    }
                }
                ms.into_iter().map(|v| quartiles(v).1).collect()
            })
            .collect();
        let table: Vec<Vec<f64>> = (0..MODELS.len()).map(|m| columns.iter().map(|c| c[m]).collect()).collect();
        for (model, row) in MODELS.iter().zip(&table) {
            print!("    {model:<20}");
            for ms in row {
                print!(" {ms:>10.2}");
            }
            println!();
        }
        // From where on the faster deferred model beats the faster forward one.
        let ahead: Vec<bool> = (0..counts.len())
            .map(|i| table[2][i].min(table[3][i]) < table[0][i].min(table[1][i]))
            .collect();
        match (0..counts.len()).find(|&i| ahead[i..].iter().all(|a| *a)) {
            Some(i) => println!("    deferred is ahead from {} lights on", counts[i]),
            None => println!("    forward is still ahead at {} lights", counts[counts.len() - 1]),
        }
    }
    println!("  (seed 003 Fig. 6.1, GeForce 560 Ti: forward wins for a few lights, deferred from a few tens on)");
}

fn merged_repetitions(gpu: &Gpu) {
    let (side, counts, rounds) = if full() {
        ((512, 384), vec![100usize, 1000], 12)
    } else {
        ((64, 48), vec![100], 2)
    };
    println!(
        "Merged repetitions: light passes sharing one render pass (m) vs one render pass per light (a), {}×{}, many_lights;",
        side.0, side.1
    );
    println!("  each figure the median [quartiles] of the per-round ratio m / a over {rounds} interleaved rounds of a frame each, frames waited for ({})", load_line());
    println!(
        "    {:<20} {:>6} {:>24} {:>24} {:>24} {:>24}",
        "model", "lights", "frame GPU ms", "frame wall ms", "light-pass GPU ms", "untimed wall (m+c / a)"
    );
    let ws = project(|t| t);
    let lights = |p: &str| p.starts_with("light_") || p.starts_with("volume_");
    for model in ["deferred_fullscreen", "deferred_volumes"] {
        for &n in &counts {
            let mut scene = builtin::many_lights(n);
            scene.size = side;
            let v = [("lighting", model)];
            // Timed; and untimed, where merging also lets the light pass continue ambient's
            // render pass (`continues`).
            let mut m = executor(gpu, &ws, &scene, (&v, &[], true, true));
            let mut a = executor(gpu, &ws, &scene, (&v, &[], false, true));
            let mut mc = executor(gpu, &ws, &scene, (&v, &[], true, false));
            let mut au = executor(gpu, &ws, &scene, (&v, &[], false, false));
            let mut ratios: [Vec<f64>; 4] = Default::default();
            let mut per_light = vec![];
            for round in 0..rounds {
                let f = (1 + round, 1);
                // Alternating which side goes first, so that neither is always second.
                let (cm, ca, cmc, cau) = if round % 2 == 0 {
                    let (cm, ca) = (cost(gpu, &mut m, f, &lights), cost(gpu, &mut a, f, &lights));
                    (cm, ca, cost(gpu, &mut mc, f, &lights), cost(gpu, &mut au, f, &lights))
                } else {
                    let (ca, cm) = (cost(gpu, &mut a, f, &lights), cost(gpu, &mut m, f, &lights));
                    let cau = cost(gpu, &mut au, f, &lights);
                    (cm, ca, cost(gpu, &mut mc, f, &lights), cau)
                };
                ratios[0].push(cm.frame_gpu_ms / ca.frame_gpu_ms);
                ratios[1].push(cm.frame_wall_ms / ca.frame_wall_ms);
                ratios[2].push(cm.picked_ms / ca.picked_ms);
                ratios[3].push(cmc.frame_wall_ms / cau.frame_wall_ms);
                per_light.push((cm.picked_ms / n as f64, ca.picked_ms / n as f64));
            }
            let cell = |v: &Vec<f64>| {
                let (q1, m, q3) = quartiles(v.clone());
                format!("{m:.2}× [{q1:.2}–{q3:.2}]")
            };
            println!(
                "    {model:<20} {n:>6} {:>24} {:>24} {:>24} {:>24}",
                cell(&ratios[0]),
                cell(&ratios[1]),
                cell(&ratios[2]),
                cell(&ratios[3])
            );
            // What dominates: each light's shading, the same work merged or not.
            let (m, a) = (
                quartiles(per_light.iter().map(|p| p.0).collect()).1,
                quartiles(per_light.iter().map(|p| p.1).collect()).1,
            );
            println!("      a light's pass: {m:.3} GPU ms merged, {a:.3} apart (medians): its shading, which merging does not change");
        }
    }
}

/// The Cornell box with `quads` small emissive quads (two triangles each) under its ceiling.
fn lamps(quads: usize, size: u32) -> Scene {
    let mut s = builtin::cornell();
    s.size = (size, size);
    let mut lamp = lightbench::scene::Material::color("lamp", [0.8; 3], 1.0);
    lamp.emissive = [4.0, 3.5, 3.0];
    let side = (quads as f32).sqrt().ceil() as usize;
    for k in 0..quads {
        let (mut v, mut i) = (vec![], vec![]);
        let at = |n: usize| -0.6 + 1.2 * (n as f32 + 0.5) / side as f32;
        let c = glam::Vec3::new(at(k % side), 1.98, at(k / side));
        let half = 0.5 / side as f32;
        lightbench::scene::geometry::quad(c, glam::Vec3::X * half, glam::Vec3::Z * half, &mut v, &mut i);
        s.meshes
            .push(lightbench::scene::Mesh::new("lamp", v, i, s.materials.len(), glam::Mat4::IDENTITY));
    }
    s.materials.push(lamp);
    s
}

fn area_lights(gpu: &Gpu) {
    let rounds = if full() { 3 } else { 1 };
    println!(
        "Area lights: the area_light pass on the Cornell box with emissive triangles under the ceiling; per size and count, the options in interleaved rounds of a frame each ({rounds} rounds), the order rotating: medians ({})",
        load_line()
    );
    println!(
        "    {:<16} {:<10} {:>10} {:>14} {:>18}",
        "area_lights", "size", "triangles", "pass GPU ms", "µs per triangle"
    );
    let ws = project(|t| t);
    // The baseline: the fitted lobe alone (`area.residual` 0), the same pipeline otherwise.
    let fit_alone = [("area.residual", ParamValue::Int(0))];
    let runs: [(&str, &str, &Set, usize); 3] = [
        ("ltc", "ltc", &[], 256),
        ("ltc, residual 0", "ltc", &fit_alone, 256),
        // Screen-space shadows march 4 segments per triangle and pixel: not past 32 triangles here.
        ("ltc_shadowed", "ltc_shadowed", &[], 16),
    ];
    for size in if full() { vec![128u32, 256, 512] } else { vec![32] } {
        for quads in if full() { vec![1usize, 16, 256] } else { vec![1] } {
            let scene = lamps(quads, size);
            let here: Vec<_> = runs.iter().filter(|r| quads <= r.3).collect();
            let mut ex: Vec<Executor> = here
                .iter()
                .map(|(_, option, params, _)| executor(gpu, &ws, &scene, (&[("area_lights", *option)][..], params, true, true)))
                .collect();
            let mut ms: Vec<Vec<f64>> = vec![vec![]; here.len()];
            for r in 0..rounds {
                for k in 0..here.len() {
                    let i = (k + r) % here.len();
                    ms[i].push(cost(gpu, &mut ex[i], (r as u32 + 1, 1), &|p| p == "area_light").picked_ms);
                }
            }
            for ((label, ..), v) in here.iter().zip(ms) {
                let pass = quartiles(v).1;
                let per = pass * 1e3 / (2 * quads) as f64;
                println!(
                    "    {label:<16} {:<10} {:>10} {pass:>14.2} {per:>18.1}",
                    format!("{size}²"),
                    2 * quads
                );
            }
        }
    }
}

fn main() {
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let only = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let want = |name: &str| only.as_deref().is_none_or(|o| name.contains(o));
    if want("shadows") {
        cube_shadows(&gpu);
    }
    if want("models") {
        lighting_models(&gpu);
    }
    if want("merge") {
        merged_repetitions(&gpu);
    }
    if want("area") {
        area_lights(&gpu);
    }
}
