//! `cargo bench -p lightbench --bench reference`: the reference path tracer on this machine.
//! First, the Cornell box at 128² and 64 samples per pixel, term by term and all together:
//! seconds and camera-ray samples per second, and the same AO run on one thread as the
//! baseline (the ratio is rayon's speed-up). Second, the goal: a converged 128² AO reference
//! (per-pixel relative standard error ≤ 2%) in under a minute on 2 cores — a 64-spp pilot tells
//! how many samples the worst pixel needs, the final run is timed and checked, and its time
//! is printed as a ratio to the minute. Third, `full` at 128² and 256 spp in paths per second,
//! against the figure the code before emitter sampling and the per-vertex BRDF constants
//! measured on the machine the README names (a recorded baseline: that code is gone). Fourth,
//! the emitter-lit Cornell box (`builtin::cornell_lamp`): a 64-spp pilot with emitters sampled
//! and a 1024-spp one with BRDF sampling alone (the same run's baseline), each predicting from its worst,
//! 99th-percentile and median pixel the time to a 2% relative standard error, and the 99th
//! percentile rendered to 2% with `Budget::Error` to check the prediction. Fifth, `full` on
//! the three scenes issue 60 names (the Cornell box, the emitter-lit box, and the Cornell box
//! with a sphere of a million triangles in it), the integrator of paths in SIMD lanes against
//! the scalar one: paths per second of the render loop alone in interleaved rounds and, where
//! valgrind is installed, instructions per path. `-- speed` runs the third alone, `-- paths`
//! the fifth.
//! `cargo test` runs it at its smallest (16², a few samples, no callgrind).

use lightbench::reference::{self, world::World, Budget, Integrator, Reference, Settings, Term};
use lightbench::scene::{builtin, geometry, Mesh, Scene};
use std::time::Instant;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::Size;

/// The bench's figure, or its smoke run's (16², few samples) under `cargo test`.
fn pick<T>(full: T, smoke: T) -> T {
    Size::from_args().pick(full, smoke)
}

const GOAL_SECONDS: f64 = 60.0;
const TARGET: f64 = 0.02;
/// Pixels darker than this are reported but not held to the target: their relative error
/// needs (1 − p)/(p · 0.02²) samples, without bound as AO → 0.
const DARK: f32 = 0.1;

fn settings(terms: &[Term], spp: u32) -> Settings {
    Settings {
        budget: Budget::Spp(spp),
        terms: terms.to_vec(),
        ..Settings::default()
    }
}

/// Largest relative standard error over pixels at least `DARK`, and how many are darker.
fn worst(r: &Reference) -> (f64, usize) {
    let t = r.term(Term::Ao).expect("ao");
    let mut worst = 0.0f64;
    let mut dark = 0;
    for (m, v) in t.mean.rgba.chunks_exact(4).zip(t.variance.rgba.chunks_exact(4)) {
        if m[0] < DARK {
            dark += 1;
            continue;
        }
        worst = worst.max((v[0] as f64).sqrt() / m[0] as f64);
    }
    (worst, dark)
}

/// `full` paths per second on the Cornell box at 128², 256 spp, measured with the code of
/// commit 9bcb4da (before emitters were sampled) on the README's machine (2 cores): its
/// `reference --terms full --spp 256` binary run alternately with this code's, 4 runs each.
const BASELINE_PATHS_PER_SECOND: f64 = 2.01e6;

/// Relative standard errors of `full` at the percentiles asked for, over lit pixels.
fn errors(r: &Reference, percentiles: &[f64]) -> Vec<f64> {
    let e = r.term(Term::Full).expect("full").relative_errors();
    percentiles.iter().map(|&p| reference::percentile_of(&e, p)).collect()
}

fn full_speed() {
    let (side, spp) = (pick(128, 16), pick(256, 4));
    let mut scene = builtin::cornell();
    scene.size = (side, side);
    // The best of three (the first run also starts rayon's threads).
    let s = (0..3)
        .map(|_| reference::render(&scene, &settings(&[Term::Full], spp), false).seconds)
        .fold(f64::INFINITY, f64::min);
    let rate = (side * side * spp) as f64 / s;
    println!(
        "full, Cornell box {side}x{side}, {spp} spp: {s:.2} s (best of 3), {:.2} M paths/s",
        rate / 1e6
    );
    println!(
        "  recorded baseline {:.2} M paths/s: {:.2}x (goal 2.0x)",
        BASELINE_PATHS_PER_SECOND / 1e6,
        rate / BASELINE_PATHS_PER_SECOND
    );
}

fn emitters() {
    let side = pick(128, 16);
    let mut scene = builtin::cornell_lamp();
    scene.size = (side, side);
    println!("Emitter-lit Cornell box {side}x{side} (full): seconds to a 2% relative standard error, predicted from a pilot");
    let percentiles = [100.0, 99.0, 50.0];
    let mut predicted_p99 = 0.0;
    // BRDF sampling alone needs a longer pilot: at 64 spp most pixels have met the lamp once
    // or never, and every error reads ~1.
    for (sample_emitters, pilot) in [(false, pick(1024, 16)), (true, pick(64, 4))] {
        let s = Settings {
            sample_emitters,
            ..settings(&[Term::Full], pilot)
        };
        let r = reference::render(&scene, &s, false);
        let e = errors(&r, &percentiles);
        let need: Vec<f64> = e.iter().map(|e| r.seconds * (e / TARGET).powi(2)).collect();
        let what = if sample_emitters {
            "emitters sampled (MIS)"
        } else {
            "BRDF sampling alone (baseline)"
        };
        println!(
            "  {what:<32} pilot {pilot} spp {:.2} s; worst {:.0} s, 99th percentile {:.0} s, median {:.1} s",
            r.seconds, need[0], need[1], need[2]
        );
        if sample_emitters {
            predicted_p99 = need[1];
        }
    }
    let s = Settings {
        budget: Budget::Error {
            target: TARGET,
            percentile: 99.0,
            max_spp: pick(1 << 20, 16),
        },
        ..settings(&[Term::Full], pick(64, 4))
    };
    let r = reference::render(&scene, &s, false);
    let reached = r.reached.expect("an error budget");
    println!(
        "  rendered to 2% at the 99th percentile: {} spp in {:.1} s (predicted {predicted_p99:.1} s), reached {:.4}",
        r.spp, r.seconds, reached.error
    );
}

/// The scenes `-- paths` measures, by name: the Cornell box, the emitter-lit box, and the
/// Cornell box with a sphere of `rings` × 2`rings` × 2 triangles floating in it (a million in
/// the bench, whose tree a ray goes deeper into than the box's few nodes).
fn path_scene(name: &str, rings: u32) -> Option<Scene> {
    match name {
        "cornell" => Some(builtin::cornell()),
        "cornell_lamp" => Some(builtin::cornell_lamp()),
        "million" => {
            let mut scene = builtin::cornell();
            let (vertices, indices) = geometry::sphere(0.35, rings, 2 * rings);
            let at = glam::Mat4::from_translation(glam::Vec3::new(0.3, 1.2, 0.1));
            scene.meshes.push(Mesh::new("ball", vertices, indices, 0, at));
            Some(scene)
        }
        _ => None,
    }
}

const PATH_SCENES: [&str; 3] = ["cornell", "cornell_lamp", "million"];

/// Seconds of one `full` render of `scene` (in `world`, built from it) at `side`² and `spp` by
/// `integrator`, the BVH's build left out.
fn full_seconds(scene: &Scene, world: &World, side: u32, spp: u32, integrator: Integrator) -> f64 {
    let mut scene = scene.clone();
    scene.size = (side, side);
    let s = Settings {
        integrator,
        ..settings(&[Term::Full], spp)
    };
    reference::render_in(world, &scene, &s, false).seconds
}

/// Paths per second (millions) of the render loop alone: a round renders `spp` and 3 × `spp`
/// samples in a world built once, and the second's extra time is what its extra paths took
/// (what each render spends before its first path cancels).
fn loop_rate(scene: &Scene, world: &World, side: u32, spp: u32, integrator: Integrator) -> f64 {
    let one = full_seconds(scene, world, side, spp, integrator);
    let three = full_seconds(scene, world, side, 3 * spp, integrator);
    (side * side * 2 * spp) as f64 / (three - one).max(1e-9) / 1e6
}

const INTEGRATORS: [(Integrator, &str); 2] = [(Integrator::Scalar, "scalar"), (Integrator::Lanes, "lanes")];

/// Instructions callgrind counts in a child process running this bench in its
/// `LB_PATHS_SCENE` mode: one `full` render of that scene at 32² and `spp` by `integrator`.
fn counted(name: &str, rings: u32, spp: u32, integrator: usize) -> Result<u64, String> {
    let env = [
        ("LB_PATHS_SCENE", name.to_string()),
        ("LB_PATHS_RINGS", rings.to_string()),
        ("LB_PATHS_SPP", spp.to_string()),
        ("LB_PATHS_INTEGRATOR", INTEGRATORS[integrator].1.to_string()),
    ];
    common::count_self(&env, None)
}

/// The child's side of `counted`: whether this process is one (it has rendered, or exited
/// with an error on settings it cannot read).
fn counted_child() -> bool {
    let Ok(name) = std::env::var("LB_PATHS_SCENE") else {
        return false;
    };
    let number = |key: &str| std::env::var(key).ok().and_then(|v| v.parse::<u32>().ok());
    let integrator = std::env::var("LB_PATHS_INTEGRATOR").ok();
    let integrator = INTEGRATORS.iter().find(|(_, n)| Some(*n) == integrator.as_deref());
    match (
        path_scene(&name, number("LB_PATHS_RINGS").unwrap_or(0)),
        number("LB_PATHS_SPP"),
        integrator,
    ) {
        (Some(scene), Some(spp), Some(&(integrator, _))) => {
            full_seconds(&scene, &World::new(&scene), 32, spp, integrator);
        }
        _ => {
            eprintln!("LB_PATHS_SCENE={name}: not a scene of `-- paths`, or LB_PATHS_SPP or LB_PATHS_INTEGRATOR unset");
            std::process::exit(2);
        }
    }
    true
}

/// Instructions per path of integrator `k` on scene `name`: 24 spp less 8 at 32², so that the
/// build and the process's start cancel.
fn per_path(name: &str, rings: u32, k: usize) -> Result<f64, String> {
    Ok((counted(name, rings, 24, k)? as f64 - counted(name, rings, 8, k)? as f64) / (32.0 * 32.0 * 16.0))
}

/// `full` on the three scenes by both integrators: paths per second in interleaved rounds
/// (each side's median and quartiles, and those of the per-round ratio) and instructions per
/// path.
fn paths() {
    let size = Size::from_args();
    let (side, spp, rounds, rings) = (pick(128, 16), pick(16, 1), pick(9, 1), pick(500, 16));
    println!(
        "full, render loop alone, lanes against scalar ({side}x{side}, {spp} and {} spp per round; goal: lanes >= 1.5x scalar)",
        3 * spp
    );
    for name in PATH_SCENES {
        let scene = path_scene(name, rings).expect("a path scene");
        let world = World::new(&scene);
        let rate = |k: usize| loop_rate(&scene, &world, side, spp, INTEGRATORS[k].0);
        let paired = common::interleaved(rounds, || rate(0), || rate(1));
        println!("{name} ({} triangles):", world.triangles());
        println!("{}", paired.report(("scalar", "lanes"), "M paths/s"));
        if size == Size::Smoke {
            println!("  instructions not counted in the smoke run");
            continue;
        }
        match (per_path(name, rings, 0), per_path(name, rings, 1)) {
            (Ok(a), Ok(b)) => println!(
                "  instructions per path (callgrind): scalar {a:.0}, lanes {b:.0}, ratio {:.3}x",
                a / b
            ),
            (Err(e), _) | (_, Err(e)) => println!("  instructions not counted: {e}"),
        }
    }
}

fn main() {
    if counted_child() {
        return;
    }
    // `-- paths`: the three scenes' paths per second and instructions alone.
    if std::env::args().skip(1).any(|a| a == "paths") {
        paths();
        return;
    }
    full_speed();
    // `-- speed`: the paths per second alone (a minute, not ten).
    if std::env::args().skip(1).any(|a| a == "speed") {
        return;
    }
    emitters();
    let (side, spp) = (pick(128, 16), pick(64, 4));
    let mut scene = builtin::cornell();
    scene.size = (side, side);
    let pixels = (side * side) as f64;
    println!(
        "Cornell box {side}x{side}, {spp} spp ({} triangles)",
        reference::world::World::new(&scene).triangles()
    );
    let all = [Term::Direct, Term::Ao, Term::IndirectDiffuse, Term::IndirectSpecular, Term::Full];
    let mut ao_seconds = 0.0;
    for terms in all.iter().map(|t| vec![*t]).chain([all.to_vec()]) {
        let start = Instant::now();
        let r = reference::render(&scene, &settings(&terms, spp), false);
        let s = start.elapsed().as_secs_f64();
        let samples: f64 = terms
            .iter()
            .map(|t| if *t == Term::Direct { pixels } else { pixels * spp as f64 })
            .sum();
        let names: Vec<&str> = terms.iter().map(|t| t.name()).collect();
        println!("  {:<55} {s:>7.3} s  {:>6.2} M samples/s", names.join("+"), samples / s / 1e6);
        if terms == [Term::Ao] {
            ao_seconds = s;
        }
        assert_eq!(r.spp, spp);
    }
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("pool");
    let start = Instant::now();
    one.install(|| reference::render(&scene, &settings(&[Term::Ao], spp), false));
    let single = start.elapsed().as_secs_f64();
    println!(
        "  ao on 1 thread (baseline): {single:.3} s; {} threads: {ao_seconds:.3} s, {:.2}x faster",
        rayon::current_num_threads(),
        single / ao_seconds
    );

    println!("Converged AO at {side}x{side}, radius 0.5 (goal: relative standard error <= 2% per pixel in < {GOAL_SECONDS} s)");
    let start = Instant::now();
    let pilot = reference::render(&scene, &settings(&[Term::Ao], spp), false);
    let (w, dark) = worst(&pilot);
    // The smoke run stops at 16 spp (its figure is not the goal's).
    let need = ((spp as f64 * (w / TARGET).powi(2)).ceil() as u32)
        .next_multiple_of(4)
        .max(spp)
        .min(pick(u32::MAX, 16));
    let final_start = Instant::now();
    let r = reference::render(&scene, &settings(&[Term::Ao], need), false);
    let final_seconds = final_start.elapsed().as_secs_f64();
    let total = start.elapsed().as_secs_f64();
    let (got, _) = worst(&r);
    println!(
        "  pilot {spp} spp: worst relative standard error {:.4} ({dark} pixels darker than {DARK} not held to it)",
        w
    );
    println!(
        "  final {need} spp: {final_seconds:.2} s ({:.2} M samples/s), worst {got:.4} (target {TARGET}: {})",
        pixels * need as f64 / final_seconds / 1e6,
        if got <= TARGET { "met" } else { "NOT met" }
    );
    println!(
        "  pilot + final {total:.2} s = {:.2}x the {GOAL_SECONDS} s goal ({})",
        total / GOAL_SECONDS,
        if total < GOAL_SECONDS { "met" } else { "NOT met" }
    );
    paths();
}
