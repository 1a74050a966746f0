//! The sidedness rule, raster against the reference: every surface blocks light from either
//! side, in every shadow technique (a single-sided occluder whose back faces the light casts
//! its shadow where the reference is black); the camera sees the front of a single-sided
//! surface only, and either side of a double-sided one (its back lit as its own side); a
//! mirroring transform swaps the sides.

use crate::gpu_common;

use glam::{Mat4, Vec3};
use gpu_common::*;
use lightbench::io::Image;
use lightbench::scene::geometry::quad;
use lightbench::scene::{Camera, Light, Material, Mesh, Scene};

fn quad_mesh(name: &str, (c, u, w): (Vec3, Vec3, Vec3), material: usize) -> Mesh {
    let (mut vs, mut is) = (vec![], vec![]);
    quad(c, u, w, &mut vs, &mut is);
    let mut m = mesh(name, (vs, is), Mat4::IDENTITY);
    m.material = material;
    m
}

fn scene(meshes: Vec<Mesh>, materials: Vec<Material>, camera: Camera, light: Light) -> Scene {
    let mut s = Scene {
        name: "sidedness".into(),
        size: (64, 64),
        camera,
        meshes,
        materials,
        textures: vec![],
        lights: vec![light],
        effects: Default::default(),
    };
    s.effects.insert(lightbench_compiler::ir::Effect::Shadows);
    s
}

/// A floor (facing up) under a single-sided square occluder at height 1 whose normal faces
/// the light above (`faces_light`) or the floor; the camera looks down from the front, so it
/// sees the occluder's top: its front, or its back (not drawn).
fn occluded_floor(light: Light, faces_light: bool) -> Scene {
    let up = if faces_light { Vec3::NEG_Z } else { Vec3::Z };
    scene(
        vec![
            quad_mesh("floor", (Vec3::ZERO, Vec3::X * 2.5, Vec3::NEG_Z * 2.5), 0),
            quad_mesh("occluder", (Vec3::Y, Vec3::X * 0.5, up * 0.5), 1),
        ],
        vec![
            Material::color("floor", [0.8, 0.8, 0.8], 1.0),
            Material::color("occluder", [0.5, 0.5, 0.6], 1.0),
        ],
        camera(Vec3::new(0.0, 3.2, 3.2), -45.0),
        light,
    )
}

/// Pixels where one image is black (every channel below 0.004) and the other lit (some channel
/// above 0.05): (lit in the raster where the reference is black, the other way round).
fn disagreements(raster: &Image, reference: &Image) -> (usize, usize) {
    let black = |p: &[f32]| p[..3].iter().all(|&v| v < 0.004);
    let lit = |p: &[f32]| p[..3].iter().any(|&v| v > 0.05);
    let (mut leaks, mut lost) = (0, 0);
    for (g, f) in raster.rgba.chunks_exact(4).zip(reference.rgba.chunks_exact(4)) {
        leaks += (black(f) && lit(g)) as usize;
        lost += (black(g) && lit(f)) as usize;
    }
    (leaks, lost)
}

/// The raster `hdr` (no ambient, unfiltered shadows) agrees with the reference's `direct`:
/// at most `edge` pixels differ in being black (shadow-map texels along the outline), and
/// nearly every value is within 3% (95%: paraboloid depth is interpolated across texels).
fn assert_agrees(s: &Scene, pipeline: &std::path::Path, variants: &[(&str, &str)], what: &str) {
    let params = [("ambient.color", "(0, 0, 0)"), ("shadow.pcf", "false")];
    let (raster, reference) = raster_and_direct(s, pipeline, variants, &params);
    let (leaks, lost) = disagreements(&raster, &reference);
    let (share, _) = agreement(&raster, &reference, 0.03);
    eprintln!("{what}: {leaks} leaked, {lost} lost pixels, {:.2}% within 3%", share * 100.0);
    let edge = 24;
    assert!(leaks <= edge, "{what}: {leaks} pixels lit where the reference is black");
    assert!(lost <= edge, "{what}: {lost} pixels black where the reference is lit");
    assert!(share > 0.95, "{what}: {:.2}% of values within 3%", share * 100.0);
}

#[test]
fn a_single_sided_occluder_shadows_the_floor_from_either_side_for_every_light_and_shadow_option() {
    let sun = Light::directional(Vec3::new(0.3, -1.0, 0.2), Vec3::ONE, 2.0);
    let spot = Light::spot(Vec3::new(0.2, 3.0, 0.1), Vec3::NEG_Y, 35.0, 45.0, Vec3::ONE, 12.0, 10.0);
    let point = Light::point(Vec3::new(0.1, 2.4, 0.15), Vec3::ONE, 8.0, 10.0);
    for faces_light in [false, true] {
        let side = if faces_light { "facing the light" } else { "facing away" };
        for (light, name) in [(sun.clone(), "sun"), (spot.clone(), "spot")] {
            let s = occluded_floor(light, faces_light);
            assert_agrees(&s, &deferred(), &[], &format!("{name}, occluder {side}"));
            let gi = root().join("pipelines/deferred_gi.ron");
            assert_agrees(&s, &gi, &[], &format!("{name}, occluder {side}, deferred_gi"));
        }
        let s = occluded_floor(point.clone(), faces_light);
        for option in ["classic", "multiview", "instanced", "dual_paraboloid"] {
            let what = format!("point ({option}), occluder {side}");
            assert_agrees(&s, &deferred(), &[("cube_shadow", option)], &what);
        }
    }
}

/// A green wall facing the camera behind a red square pane at the origin; a sun from the
/// camera's side casts the pane's shadow on the wall off to the side, so the image centre
/// shows the pane where it is drawn, else the lit wall.
fn pane_before_wall(pane: Mesh, double_sided: bool) -> Scene {
    let mut red = Material::color("pane", [0.8, 0.1, 0.1], 1.0);
    red.double_sided = double_sided;
    let mut pane = pane;
    pane.material = 1;
    scene(
        vec![
            quad_mesh("wall", (Vec3::new(0.0, 0.0, -1.5), Vec3::X * 3.0, Vec3::Y * 3.0), 0),
            pane,
        ],
        vec![Material::color("wall", [0.1, 0.8, 0.1], 1.0), red],
        camera(Vec3::new(0.0, 0.0, 3.0), 0.0),
        Light::directional(Vec3::new(0.6, -0.4, -1.0), Vec3::ONE, 2.0),
    )
}

/// What the camera sees at the image centre: red (the pane) or green (the wall), and the
/// reference seeing the same.
fn centre(s: &Scene) -> &'static str {
    let params = [("ambient.color", "(0, 0, 0)"), ("shadow.pcf", "false")];
    let (raster, reference) = raster_and_direct(s, &deferred(), &[], &params);
    let (share, _) = agreement(&raster, &reference, 0.03);
    assert!(share > 0.97, "{:.2}% of values within 3% of the reference", share * 100.0);
    let p = raster.pixel(32, 32);
    let q = reference.pixel(32, 32);
    assert!(p[0].max(p[1]) > 0.05, "the centre is lit: {p:?}");
    let colour = |p: [f32; 4]| if p[0] > p[1] { "red" } else { "green" };
    eprintln!("centre: raster {p:?}, reference {q:?}");
    assert_eq!(colour(p), colour(q), "raster {p:?}, reference {q:?}");
    colour(p)
}

#[test]
fn the_camera_sees_single_sided_fronts_and_both_sides_of_double_sided_surfaces() {
    // The pane's normal points away from the camera: the camera sees its back.
    let back = quad_mesh("pane", (Vec3::ZERO, Vec3::NEG_X * 0.5, Vec3::Y * 0.5), 1);
    assert_eq!(
        centre(&pane_before_wall(back.clone(), false)),
        "green",
        "a single-sided back is not seen"
    );
    assert_eq!(centre(&pane_before_wall(back, true)), "red", "a double-sided back is seen, lit");
    // Facing the camera, mirrored in x: the mirror keeps the normal towards the camera and
    // reverses the winding, which glTF says keeps the same front.
    let mut mirrored = quad_mesh("pane", (Vec3::ZERO, Vec3::X * 0.5, Vec3::Y * 0.5), 1);
    mirrored.transform = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    assert_eq!(
        centre(&pane_before_wall(mirrored.clone(), false)),
        "red",
        "a mirrored front is seen"
    );
    mirrored.transform = Mat4::from_rotation_y(std::f32::consts::PI) * mirrored.transform;
    assert_eq!(centre(&pane_before_wall(mirrored, false)), "green", "a mirrored back is not seen");
}
/// The reference's rays meet a surface on the edge its two triangles share, from the front
/// and from behind (the image centre of `pane_before_wall` lies on the pane's diagonal).
#[test]
fn reference_rays_through_a_shared_edge_hit_from_either_side() {
    use lightbench::reference::world::{Faces, World};
    let back = quad_mesh("pane", (Vec3::ZERO, Vec3::NEG_X * 0.5, Vec3::Y * 0.5), 1);
    let s = pane_before_wall(back, true);
    let w = World::new(&s);
    for (origin, dir) in [(Vec3::Z * 3.0, Vec3::NEG_Z), (Vec3::NEG_Z, Vec3::Z)] {
        for d in [dir, (dir + Vec3::new(0.01, -0.01, 0.0)).normalize()] {
            let t = w.trace(origin.into(), d.into(), (0.0, 100.0), Faces::Both).map(|h| h.t);
            let expected = origin.z.abs() / d.z.abs();
            assert!(t.is_some_and(|t| (t - expected).abs() < 1e-4), "from {origin} along {d}: {t:?}");
        }
    }
}
