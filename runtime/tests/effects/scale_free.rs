//! Ambient occlusion and screen-space reflections at default settings look the same at any
//! scale: their lengths are fractions of the scene's bounding radius (`frame.scene_radius`).
//! The same scene at scale 0.001 and 1 (geometry, camera and lights scaled) gives the same
//! `ao.full` and `ssr.color`; with `lengths.world` (the seeds' world units) it does not.

use crate::gpu_common;

use glam::{Mat4, Vec3};
use gpu_common::*;
use lightbench::io::Image;
use lightbench::scene::Scene;
use lightbench_compiler::ir::{LightKind, ParamValue};

/// `s` scaled by `k` about the origin: geometry, camera, light positions and ranges, and
/// the intensities of lights that fall off with distance (by k², so that they light alike).
pub(crate) fn scaled(mut s: Scene, k: f32) -> Scene {
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

/// `resource` of `file` at scale 0.001 and at scale 1: within `tolerance` (RMSE) by default,
/// and at least `world_differs` apart in world units (`what` says why).
fn assert_scale_free(file: &str, resource: &str, (tolerance, world_differs): (f64, f64), what: &str) {
    let s = lightbench::scene::load(root().join(file).to_str().unwrap()).unwrap();
    let across = |world: bool| {
        let (small, one) = (render(&scaled(s.clone(), 0.001), resource, world), render(&s, resource, world));
        assert_eq!(small.non_finite() + one.non_finite(), 0, "{file}");
        lightbench::io::rmse(&small, &one).unwrap()
    };
    let (e, world) = (across(false), across(true));
    eprintln!("{resource} RMSE between scales 0.001 and 1: {e} (world units: {world})");
    assert!(e < tolerance, "{resource}: {e}");
    assert!(world > world_differs, "{what}: {world}");
}

#[test]
fn ssao_is_the_same_at_any_scale() {
    assert_scale_free(
        "scenes/cornell_spot.ron",
        "ao.full",
        (0.01, 0.02),
        "in world units the millimetre box is all occluded",
    );
}

#[test]
fn ssr_is_the_same_at_any_scale() {
    assert_scale_free(
        "scenes/mirror.ron",
        "ssr.color",
        (0.02, 0.05),
        "in world units the millimetre mirror reflects nothing",
    );
}
