//! The reference path tracer with emissive surfaces as lights: next-event estimation against
//! Lambert's closed-form irradiance of a polygon, one-sided and double-sided emission, the
//! same image as BRDF sampling alone (within noise) at a fraction of its noise for the time,
//! and a noise-targeted render that reaches its target.

use crate::gpu_common;

use glam::{Mat4, Vec3, Vec3A};
use gpu_common::mesh;
use lightbench::reference::{
    self, emitters::Emitters, integrate::Context, sample::Rng, world::Faces, world::World, Brdf, Budget, Settings, Term,
};
use lightbench::scene::geometry::quad;
use lightbench::scene::{builtin, Material, Mesh, Scene};

const LE: f32 = 10.0;
const ALBEDO: f32 = 0.5;
/// The lamp: centred 1 above the floor, half extents 0.2 × 0.15.
const LAMP_C: Vec3 = Vec3::new(0.0, 1.0, 0.0);
const LAMP_U: Vec3 = Vec3::new(0.2, 0.0, 0.0);
const LAMP_W: Vec3 = Vec3::new(0.0, 0.0, 0.15);

/// A large grey floor (y = 0) and a small emissive quad above it, facing down (`down`) or
/// up, single- or double-sided.
fn lamp_over_floor(down: bool, double_sided: bool) -> Scene {
    let w = if down { LAMP_W } else { -LAMP_W };
    gpu_common::lamp_over_floor(
        (
            Material::color("grey", [ALBEDO; 3], 1.0),
            gpu_common::lamp_material([LE; 3], double_sided),
        ),
        (LAMP_C, LAMP_U, w),
        gpu_common::looking_down(Vec3::new(0.0, 3.0, 3.0), -45.0, (0.01, 100.0)),
        (8, 8),
    )
}

/// Irradiance at `x` (normal `n`) from a polygon of uniform radiance `le` (Lambert 1760:
/// E = L/2 · Σ Θ_i (γ_i · n), Θ_i the angle edge i subtends, γ_i its plane's normal).
fn polygon_irradiance(x: Vec3, n: Vec3, corners: &[Vec3], le: f32) -> f64 {
    let mut sum = 0.0f64;
    for i in 0..corners.len() {
        let a = (corners[i] - x).normalize();
        let b = (corners[(i + 1) % corners.len()] - x).normalize();
        let theta = (a.dot(b) as f64).clamp(-1.0, 1.0).acos();
        sum += theta * a.cross(b).normalize().dot(n) as f64;
    }
    le as f64 / 2.0 * sum.abs()
}

fn context(world: &World) -> Context<'_> {
    Context {
        world,
        lights: vec![],
        emitters: Emitters::new(world),
        brdf: Brdf::Lambert,
        eps: 1e-5,
        ao_radius: 0.5,
        ao_falloff: false,
        sample_emitters: true,
    }
}

/// The `direct` term at floor points on an 8 × 8 grid, 64 samples each: per point the mean
/// and its standard error, and the closed form.
fn direct_on_floor(s: &Scene) -> Vec<(f64, f64, f64)> {
    let world = World::new(s);
    let ctx = context(&world);
    let corners = [
        LAMP_C - LAMP_U - LAMP_W,
        LAMP_C + LAMP_U - LAMP_W,
        LAMP_C + LAMP_U + LAMP_W,
        LAMP_C - LAMP_U + LAMP_W,
    ];
    let mut out = vec![];
    for k in 0..64u64 {
        let x = Vec3::new((k % 8) as f32 * 0.25 - 0.9, 0.0, (k / 8) as f32 * 0.2 - 0.7);
        let hit = world
            .trace(Vec3A::from(x + Vec3::Y * 0.5), Vec3A::NEG_Y, (0.0, 1.0), Faces::Seen)
            .expect("the floor");
        let primary = ctx.primary(&hit, Vec3A::Y, true, 0);
        let samples: Vec<f64> = (0..64)
            .map(|i| ctx.direct(&primary, Vec3A::Y, &mut Rng::new(1, k, i, 0)).x as f64)
            .collect();
        let mean = samples.iter().sum::<f64>() / 64.0;
        let var = samples.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 63.0 / 64.0;
        let expected = ALBEDO as f64 / std::f64::consts::PI * polygon_irradiance(x, Vec3::Y, &corners, LE);
        out.push((mean, var.sqrt(), expected));
    }
    out
}

fn assert_matches_lambert(points: &[(f64, f64, f64)], what: &str) {
    let (got, want): (f64, f64) = points.iter().fold((0.0, 0.0), |(g, w), p| (g + p.0, w + p.2));
    assert!((got / want - 1.0).abs() < 0.005, "{what}: mean {got} vs closed form {want}");
    for (mean, se, expected) in points {
        assert!(
            (mean - expected).abs() < 4.0 * se.max(1e-4 * expected),
            "{what}: {mean} ± {se} vs {expected}"
        );
    }
}

#[test]
fn a_lamp_lights_the_floor_as_lamberts_polygon_formula_says() {
    assert_matches_lambert(&direct_on_floor(&lamp_over_floor(true, false)), "facing down");
}

#[test]
fn a_single_sided_lamp_lights_nothing_behind_it_and_a_double_sided_one_does() {
    let behind = direct_on_floor(&lamp_over_floor(false, false));
    assert!(behind.iter().all(|p| p.0 == 0.0), "light from the back of a single-sided emitter");
    assert_matches_lambert(&direct_on_floor(&lamp_over_floor(false, true)), "double-sided, facing up");
}

fn full(s: &Scene, spp: u32, sample_emitters: bool) -> reference::Reference {
    let settings = Settings {
        budget: Budget::Spp(spp),
        terms: vec![Term::Full],
        sample_emitters,
        ..Settings::default()
    };
    reference::render(s, &settings, false)
}

/// Median over lit pixels of the relative standard error of the mean.
fn median_relative_error(r: &reference::Reference) -> f64 {
    let e = r.term(Term::Full).unwrap().relative_errors();
    e[e.len() / 2]
}

/// The emitter-lit Cornell box, `full`: sampling the lamp as a light (with MIS) estimates
/// the same image as finding it by BRDF sampling alone — per-pixel z-scores as noise
/// predicts — and is far less noisy for the time it takes.
#[test]
fn sampling_emitters_estimates_the_same_image_with_far_less_noise_for_the_time() {
    let mut s = builtin::cornell_lamp();
    s.size = (16, 16);
    let nee = full(&s, 64, true);
    let brdf = full(&s, 1024, false);
    let (a, b) = (nee.term(Term::Full).unwrap(), brdf.term(Term::Full).unwrap());
    let mut z = vec![];
    for i in 0..a.mean.rgba.len() {
        if i % 4 == 3 {
            continue;
        }
        let var = (a.variance.rgba[i] + b.variance.rgba[i]) as f64;
        if var > 0.0 {
            z.push((a.mean.rgba[i] - b.mean.rgba[i]) as f64 / var.sqrt());
        }
    }
    let mean_z = z.iter().sum::<f64>() / z.len() as f64;
    let rms_z = (z.iter().map(|z| z * z).sum::<f64>() / z.len() as f64).sqrt();
    let far = z.iter().filter(|z| z.abs() > 4.0).count();
    assert!(
        mean_z.abs() < 0.2 && rms_z < 1.3 && far <= z.len() / 100,
        "z mean {mean_z}, rms {rms_z}, {far} beyond 4σ"
    );
    // Time to a given error: ∝ relative error² × seconds, whatever the sample count. (The
    // error itself at equal time is lower by the square root of this.)
    // The renders are milliseconds long: each side's time is its fastest of three more
    // renders, interleaved (the images are the same each time), so that a busy machine
    // slowing one of them does not decide the ratio.
    let (mut nee_s, mut brdf_s) = (nee.seconds, brdf.seconds);
    for _ in 0..3 {
        nee_s = nee_s.min(full(&s, 64, true).seconds);
        brdf_s = brdf_s.min(full(&s, 1024, false).seconds);
    }
    let gain = (median_relative_error(&brdf).powi(2) * brdf_s) / (median_relative_error(&nee).powi(2) * nee_s);
    eprintln!("time to the same error: {gain:.1}x sooner sampling emitters");
    assert!(gain > 30.0, "the median pixel reaches an error only {gain:.1}x sooner");
}

/// `--target-error`: the pilot's prediction taken, checked, and the samples those of a plain
/// count (the same image as asking for that many).
#[test]
fn a_target_error_is_reached_and_reported() {
    let mut s = builtin::cornell_lamp();
    s.size = (8, 8);
    let settings = Settings {
        budget: Budget::Error {
            target: 0.03,
            percentile: 50.0,
            max_spp: 4096,
        },
        terms: vec![Term::Full],
        ..Settings::default()
    };
    let r = reference::render(&s, &settings, false);
    let reached = r.reached.expect("an error budget reports what it reached");
    assert!(reached.error <= 0.03, "{reached:?}");
    assert!(median_relative_error(&r) <= 0.03 + 1e-9);
    assert!(r.spp > 64 && r.spp.is_multiple_of(4), "{} spp", r.spp);
    // The same samples as a count would take: bit-identical to asking for that many.
    let same = full(&s, r.spp, true);
    assert_eq!(same.term(Term::Full).unwrap().mean.rgba, r.term(Term::Full).unwrap().mean.rgba);
}

/// An emissive texture (KHR strength as the scene loader folds it into the factor): a 4 × 4
/// lamp whose map is white on one half and black on the other, sRGB. Sampling it as a light
/// (chosen by its texture's mean, evaluated texel by texel) estimates what BRDF sampling
/// alone finds, at 16 floor points (z-scores within noise), and it lights the floor under its
/// white half more than under its black one.
#[test]
fn an_emissive_texture_is_sampled_as_it_is_seen() {
    use lightbench::scene::ImageData;
    let mut s = lamp_over_floor(true, false);
    let (mut lv, mut li) = (vec![], vec![]);
    quad(LAMP_C, Vec3::X * 2.0, Vec3::Z * 2.0, &mut lv, &mut li);
    s.meshes[1] = Mesh {
        material: 1,
        ..mesh("lamp", (lv, li), Mat4::IDENTITY)
    };
    s.materials[1].emissive = [2.0, 1.5, 1.0];
    s.materials[1].emissive_texture = Some(0);
    s.textures = vec![ImageData {
        width: 8,
        height: 1,
        rgba: (0..8u8)
            .flat_map(|i| if i < 4 { [255, 255, 255, 255] } else { [0, 0, 0, 255] })
            .collect(),
        srgb: true,
    }];
    let world = World::new(&s);
    let nee = context(&world);
    let brdf = Context {
        sample_emitters: false,
        ..context(&world)
    };
    let (mut z2, mut count, mut under) = (0.0f64, 0, [0.0f64; 2]);
    for k in 0..16u64 {
        let x = Vec3::new((k % 4) as f32 * 0.8 - 1.2, 0.0, (k / 4) as f32 * 0.8 - 1.2);
        let hit = world
            .trace(Vec3A::from(x + Vec3::Y * 0.5), Vec3A::NEG_Y, (0.0, 1.0), Faces::Seen)
            .unwrap();
        let stats = |ctx: &Context| {
            let primary = ctx.primary(&hit, Vec3A::Y, true, 0);
            let v: Vec<f64> = (0..4096)
                .map(|i| ctx.direct(&primary, Vec3A::Y, &mut Rng::new(5, k, i, 0)).x as f64)
                .collect();
            let m = v.iter().sum::<f64>() / v.len() as f64;
            (
                m,
                v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() as f64 - 1.0) / v.len() as f64,
            )
        };
        let ((a, va), (b, vb)) = (stats(&nee), stats(&brdf));
        z2 += (a - b).powi(2) / (va + vb);
        count += 1;
        under[(x.x > 0.0) as usize] += a;
    }
    let rms_z = (z2 / count as f64).sqrt();
    assert!(rms_z < 1.6, "z RMS {rms_z}");
    assert!(
        under[0] > 1.5 * under[1],
        "lit under the white half {} vs the black {}",
        under[0],
        under[1]
    );
}
