//! Shadow acne at default settings: a box on a floor lit at grazing angles by each light kind,
//! under every shadow option, against the reference's direct term. Where the reference is
//! lit all around (away from shadow edges), no raster pixel may be darker than it by more
//! than a tolerance: acne is self-shadowing, which darkens lit surfaces in stripes and moiré.

use crate::gpu_common;

use glam::{Mat4, Quat, Vec3};
use gpu_common::*;
use lightbench::io::Image;
use lightbench::scene::geometry::{cuboid, quad};
use lightbench::scene::{Camera, Light, Material, Scene};

/// A floor and a box turned 30° about the vertical, lit by `light` alone.
fn grazing(light: Light) -> Scene {
    let (mut vs, mut is) = (vec![], vec![]);
    quad(Vec3::ZERO, Vec3::X * 4.0, Vec3::NEG_Z * 4.0, &mut vs, &mut is);
    let floor = mesh("floor", (vs, is), Mat4::IDENTITY);
    let mut boxed = mesh(
        "box",
        cuboid(Vec3::new(0.4, 0.6, 0.4)),
        Mat4::from_rotation_translation(Quat::from_rotation_y(30f32.to_radians()), Vec3::new(0.0, 0.6, 0.0)),
    );
    boxed.material = 1;
    let mut s = Scene {
        name: "grazing".into(),
        size: (96, 96),
        camera: Camera {
            position: Vec3::new(0.0, 2.2, 4.0),
            yaw: 0.0,
            pitch: -25.0,
            fov: 55.0,
            near: 0.05,
            far: 50.0,
            animation: None,
        },
        meshes: vec![floor, boxed],
        materials: vec![
            Material::color("floor", [0.8, 0.8, 0.8], 1.0),
            Material::color("box", [0.7, 0.6, 0.5], 1.0),
        ],
        textures: vec![],
        lights: vec![light],
        effects: Default::default(),
    };
    s.effects.insert(lightbench_compiler::ir::Effect::Shadows);
    s
}

/// Pixels lit in the reference with every neighbour within 2 pixels lit too (shadow edges
/// and the terminator excluded), where the raster is darker than the reference by more than
/// 20% (and 0.005): acne; and pixels dark in the reference all around where the raster is
/// lit: light leaking under an offset too large (peter-panning).
fn acne(raster: &Image, reference: &Image) -> (usize, usize) {
    let (w, h) = (reference.width as i64, reference.height as i64);
    let lum = |img: &Image, x: i64, y: i64| {
        let p = img.pixel(x as u32, y as u32);
        p[0] + p[1] + p[2]
    };
    let around = |x: i64, y: i64, f: &dyn Fn(f32) -> bool| (-2..=2).all(|dy| (-2..=2).all(|dx| f(lum(reference, x + dx, y + dy))));
    let (mut acne, mut leaks) = (0, 0);
    for y in 2..h - 2 {
        for x in 2..w - 2 {
            let (r, g) = (lum(reference, x, y), lum(raster, x, y));
            acne += (around(x, y, &|v| v > 0.03) && g < r - (0.2 * r).max(0.005)) as usize;
            leaks += (around(x, y, &|v| v < 0.003) && g > 0.03) as usize;
        }
    }
    (acne, leaks)
}

fn lights() -> Vec<(&'static str, Light)> {
    let low = 8f32.to_radians();
    vec![
        (
            "sun",
            Light::directional(Vec3::new(-low.cos() * 0.8, -low.sin(), -low.cos() * 0.6), Vec3::ONE, 3.0),
        ),
        (
            "spot",
            Light::spot(
                Vec3::new(2.6, 0.45, 2.2),
                Vec3::new(-2.6, -0.25, -2.2),
                30.0,
                40.0,
                Vec3::ONE,
                12.0,
                12.0,
            ),
        ),
        ("point", Light::point(Vec3::new(2.2, 0.3, 1.6), Vec3::ONE, 10.0, 12.0)),
        // Above the box: its sides are lit at grazing angles.
        ("point above", Light::point(Vec3::new(0.25, 2.6, 0.45), Vec3::ONE, 10.0, 12.0)),
        ("sun above", Light::directional(Vec3::new(0.1, -1.0, 0.12), Vec3::ONE, 3.0)),
    ]
}

#[test]
fn no_acne_at_grazing_angles_with_default_settings() {
    let params = [("ambient.color", "(0, 0, 0)")];
    let tolerance = 10;
    let mut found = vec![];
    for (name, light) in lights() {
        let s = grazing(light.clone());
        let options: &[&str] = if name.starts_with("point") {
            &["classic", "multiview", "instanced", "dual_paraboloid"]
        } else {
            &["default"]
        };
        for option in options {
            let variants: Vec<(&str, &str)> = if name.starts_with("point") {
                vec![("cube_shadow", *option)]
            } else {
                vec![]
            };
            // PCF widens the footprint a lookup compares against: with and without.
            for pcf in ["true", "false"] {
                let mut with = params.to_vec();
                with.push((if name.starts_with("point") { "cube.pcf" } else { "shadow.pcf" }, pcf));
                let (raster, reference) = raster_and_direct(&s, &deferred(), &variants, &with);
                let (n, leaks) = acne(&raster, &reference);
                eprintln!("{name} ({option}, pcf {pcf}): {n} acne pixels, {leaks} leaked");
                found.push((name, *option, pcf, n.max(leaks)));
            }
        }
    }
    let bad: Vec<_> = found.iter().filter(|(.., n)| *n > tolerance).collect();
    assert!(bad.is_empty(), "acne or leaks above {tolerance} pixels: {bad:?}");
}
