//! Ambient occlusion and screen-space reflections at default settings look the same at any
//! scale: their lengths are fractions of the scene's bounding radius (`frame.scene_radius`).
//! The same scene at scale 0.001 and 1 (geometry, camera and lights scaled) gives the same
//! `ao.full` and `ssr.color`; with `lengths.world` (the seeds' world units) it does not.

mod gpu_common;

use glam::{Mat4, Vec3};
use gpu_common::*;
use lightbench::io::Image;
use lightbench::scene::Scene;
use lightbench_compiler::ir::{LightKind, ParamValue};

/// `s` scaled by `k` about the origin: geometry, camera, light positions and ranges, and
/// the intensities of lights that fall off with distance (by k², so that they light alike).
fn scaled(mut s: Scene, k: f32) -> Scene {
    for m in &mut s.meshes {
        m.transform = Mat4::from_scale(Vec3::splat(k)) * m.transform;
    }
    s.camera.position *= k;
    s.camera.near *= k;
    s.camera.far *= k;
    for l in &mut s.lights {
        l.position *= k;
        if l.kind != LightKind::Directional {
            l.range *= k;
            l.intensity *= k * k;
        }
    }
    s
}

/// `resource` after one frame of `deferred_gi` on `s`, with `lengths.world` as given.
fn render(s: &Scene, resource: &str, world: bool) -> Image {
    let g = gpu();
    let p = root().join("pipelines/deferred_gi.ron");
    let (exe, _) = lightbench::render::compile(&g, &p, None, s, &[]).unwrap_or_else(|e| panic!("{e}"));
    let params = [("lengths.world".to_string(), ParamValue::Bool(world))];
    let ex = lightbench::render::render_with(&g, &exe, s, 1, &params).unwrap();
    ex.read_texture(&g, resource, 0, 0).unwrap()
}

/// RMSE between `resource` at scale 0.001 and at scale 1.
fn across_scales(file: &str, resource: &str, world: bool) -> f64 {
    let s = lightbench::scene::load(root().join(file).to_str().unwrap()).unwrap();
    let (small, one) = (render(&scaled(s.clone(), 0.001), resource, world), render(&s, resource, world));
    assert_eq!(small.non_finite() + one.non_finite(), 0, "{file}");
    lightbench::io::rmse(&small, &one).unwrap()
}

#[test]
fn ssao_is_the_same_at_any_scale() {
    let e = across_scales("scenes/cornell_spot.ron", "ao.full", false);
    let world = across_scales("scenes/cornell_spot.ron", "ao.full", true);
    eprintln!("ao.full RMSE between scales 0.001 and 1: {e} (world units: {world})");
    assert!(e < 0.01, "{e}");
    assert!(world > 0.02, "in world units the millimetre box is all occluded: {world}");
}

#[test]
fn ssr_is_the_same_at_any_scale() {
    let e = across_scales("scenes/mirror.ron", "ssr.color", false);
    let world = across_scales("scenes/mirror.ron", "ssr.color", true);
    eprintln!("ssr.color RMSE between scales 0.001 and 1: {e} (world units: {world})");
    assert!(e < 0.02, "{e}");
    assert!(world > 0.05, "in world units the millimetre mirror reflects nothing: {world}");
}
