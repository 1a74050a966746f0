//! The `full` term's two integrators: paths in SIMD lanes (the default) against one path at a
//! time (`Integrator::Scalar`, the oracle) — the same image within noise, judged as the GPU
//! path tracer is (`agreement`), on scenes that take every part of the lanes' arithmetic.

use super::agreement::{agreement, judge, load, settings};
use lightbench::reference::{self, Integrator, Reference, Settings, Term};
use lightbench::scene::Scene;

/// Point-lit, sun-lit, spot-lit and emitter-lit boxes, a mirror floor (the sharpest lobes:
/// the largest powers), and a scene a millimetre across (the offsets' and lights' ranges
/// scaled down) — each at 64², 128 samples. The lanes' side takes another seed, so that the
/// two estimates are independent and their z-scores mean what they say (from one seed they
/// follow nearly the same paths: z RMS ≈ 0, which would hide nothing but a gross error).
#[test]
fn the_lanes_integrator_equals_the_scalar_one_within_noise() {
    let mut bad = vec![];
    for spec in [
        "cornell",
        "scenes/cornell_sun.ron",
        "scenes/cornell_spot.ron",
        "cornell_lamp",
        "scenes/hard/mirror_floor.ron",
        "scenes/hard/tiny_scale.ron",
    ] {
        let scene = load(spec, (64, 64));
        let scene = &scene;
        let with = |integrator, seed: u64| {
            move |s: &Settings| {
                let s = Settings {
                    integrator,
                    seed: s.seed + seed,
                    ..s.clone()
                };
                reference::render(scene, &s, false)
            }
        };
        bad.extend(judge(
            scene,
            &settings(&[Term::Full], 128),
            with(Integrator::Scalar, 0),
            with(Integrator::Lanes, 1000),
        ));
    }
    assert!(bad.is_empty(), "the lanes' integrator differs from the scalar one: {bad:?}");
}

/// `scene` rendered with `s` (the default integrator) and with the scalar one.
fn both(scene: &Scene, s: Settings) -> (Reference, Reference) {
    let scalar = Settings {
        integrator: Integrator::Scalar,
        ..s.clone()
    };
    (reference::render(scene, &s, false), reference::render(scene, &scalar, false))
}

/// The default is the lanes' integrator, and it is what `render` runs: its image is not the
/// scalar one's bit for bit (their draws round differently), while the other terms are.
#[test]
fn the_default_integrator_is_the_lanes_one_and_only_full_uses_it() {
    assert_eq!(Settings::default().integrator, Integrator::Lanes);
    let (lanes, scalar) = both(&load("cornell", (16, 16)), settings(&[Term::Ao, Term::Full], 8));
    let mean = |r: &Reference, t| r.term(t).unwrap().mean.rgba.clone();
    assert_eq!(mean(&lanes, Term::Ao), mean(&scalar, Term::Ao));
    assert_ne!(mean(&lanes, Term::Full), mean(&scalar, Term::Full));
}

/// From one seed the two integrators follow the same paths but for rounding (the lanes' `pow`
/// and sine are not libm's, bit for bit), so their images differ far less than their noise:
/// a slip in the lanes' arithmetic that biases each path a little — too little for the
/// independent comparison above at 128 samples — shows here as a mean z-score off 0.
#[test]
fn from_one_seed_the_two_integrators_differ_by_rounding_alone() {
    for spec in ["cornell", "cornell_lamp", "scenes/cornell_spot.ron"] {
        let scene = load(spec, (32, 32));
        let (lanes, scalar) = both(&scene, settings(&[Term::Full], 64));
        let (a, b) = (scalar.term(Term::Full).unwrap(), lanes.term(Term::Full).unwrap());
        let z = agreement(a, b, &reference::edge_pixels(&scene));
        eprintln!("{spec}: from one seed z mean {:+.4}, RMS {:.4}", z.mean, z.rms);
        assert!(z.mean.abs() < 0.005 && z.rms < 0.03, "{spec}: z mean {}, RMS {}", z.mean, z.rms);
    }
}
