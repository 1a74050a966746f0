//! Built-in scenes, made in code so tests and the default render need no downloads.

use super::geometry::{cuboid, cylinder, quad, sphere};
use super::{Camera, Light, Material, Mesh, Scene};
use glam::{Mat4, Quat, Vec3};
use lightbench_compiler::ir::Effect;

pub const NAMES: [&str; 3] = ["cornell", "colonnade", "many_lights"];

pub fn by_name(name: &str) -> Option<Scene> {
    match name {
        "cornell" => Some(cornell()),
        "colonnade" => Some(colonnade()),
        "many_lights" => Some(many_lights(100)),
        _ => None,
    }
}

fn mesh(name: &str, (vertices, indices): (Vec<crate::blocks::Vertex>, Vec<u32>), material: usize, transform: Mat4) -> Mesh {
    Mesh {
        name: name.into(),
        vertices,
        indices,
        material,
        transform,
        triangle_fraction: 1.0,
        reflective: false,
    }
}

/// A Cornell box 2 units wide, deep and tall (floor at y = 0, open towards +Z) with a tall
/// and a short box, and a point light under the ceiling.
pub fn cornell() -> Scene {
    let materials = vec![
        Material::color("white", [0.73, 0.73, 0.73], 0.7),
        Material::color("red", [0.65, 0.05, 0.05], 0.7),
        Material::color("green", [0.12, 0.45, 0.15], 0.7),
    ];
    let mut meshes = vec![];
    let wall = |name: &str, c: Vec3, u: Vec3, w: Vec3, m: usize| {
        let (mut vs, mut is) = (vec![], vec![]);
        quad(c, u, w, &mut vs, &mut is);
        mesh(name, (vs, is), m, Mat4::IDENTITY)
    };
    meshes.push(wall("floor", Vec3::ZERO, Vec3::X, Vec3::NEG_Z, 0));
    meshes.push(wall("ceiling", Vec3::Y * 2.0, Vec3::X, Vec3::Z, 0));
    meshes.push(wall("back", Vec3::new(0.0, 1.0, -1.0), Vec3::X, Vec3::Y, 0));
    meshes.push(wall("left", Vec3::new(-1.0, 1.0, 0.0), Vec3::NEG_Z, Vec3::Y, 1));
    meshes.push(wall("right", Vec3::new(1.0, 1.0, 0.0), Vec3::Z, Vec3::Y, 2));
    meshes.push(mesh(
        "tall_box",
        cuboid(Vec3::new(0.3, 0.6, 0.3)),
        0,
        Mat4::from_rotation_translation(Quat::from_rotation_y(20f32.to_radians()), Vec3::new(-0.35, 0.6, -0.35)),
    ));
    meshes.push(mesh(
        "short_box",
        cuboid(Vec3::splat(0.3)),
        0,
        Mat4::from_rotation_translation(Quat::from_rotation_y(-17f32.to_radians()), Vec3::new(0.35, 0.3, 0.3)),
    ));
    Scene {
        name: "cornell".into(),
        size: (128, 128),
        camera: Camera {
            position: Vec3::new(0.0, 1.0, 3.6),
            yaw: 0.0,
            pitch: 0.0,
            fov: 40.0,
            near: 0.05,
            far: 20.0,
        },
        meshes,
        materials,
        textures: vec![],
        lights: vec![Light::point(Vec3::new(0.0, 1.8, 0.1), Vec3::new(1.0, 0.95, 0.85), 4.0, 6.0)],
        effects: [Effect::Shadows].into_iter().collect(),
    }
}

/// A colonnade: two rows of columns under beams on a long floor, lit by a low sun and a
/// spot light; many draws for shadow and draw-count tests (a Sponza stand-in).
pub fn colonnade() -> Scene {
    let materials = vec![
        Material::color("stone", [0.75, 0.7, 0.62], 0.8),
        Material::color("floor", [0.5, 0.5, 0.52], 0.6),
    ];
    let mut meshes = vec![mesh(
        "floor",
        cuboid(Vec3::new(14.0, 0.1, 5.0)),
        1,
        Mat4::from_translation(Vec3::new(0.0, -0.1, 0.0)),
    )];
    for row in [-2.5f32, 2.5] {
        for i in 0..12 {
            let x = -11.0 + i as f32 * 2.0;
            meshes.push(mesh(
                &format!("column_{row}_{i}"),
                cylinder(0.35, 4.0, 20),
                0,
                Mat4::from_translation(Vec3::new(x, 0.0, row)),
            ));
            meshes.push(mesh(
                &format!("base_{row}_{i}"),
                cuboid(Vec3::new(0.5, 0.15, 0.5)),
                0,
                Mat4::from_translation(Vec3::new(x, 0.15, row)),
            ));
        }
        meshes.push(mesh(
            &format!("beam_{row}"),
            cuboid(Vec3::new(12.0, 0.3, 0.5)),
            0,
            Mat4::from_translation(Vec3::new(0.0, 4.3, row)),
        ));
    }
    Scene {
        name: "colonnade".into(),
        size: (256, 128),
        camera: Camera {
            position: Vec3::new(-13.0, 2.0, 0.0),
            yaw: 90.0 - 180.0,
            pitch: -5.0,
            fov: 60.0,
            near: 0.1,
            far: 100.0,
        },
        meshes,
        materials,
        textures: vec![],
        lights: vec![
            Light::directional(Vec3::new(0.4, -0.6, 0.5), Vec3::new(1.0, 0.92, 0.8), 2.5),
            Light::spot(
                Vec3::new(0.0, 6.0, 0.0),
                Vec3::NEG_Y,
                25.0,
                35.0,
                Vec3::new(0.8, 0.85, 1.0),
                30.0,
                12.0,
            ),
        ],
        effects: [Effect::Shadows].into_iter().collect(),
    }
}

/// A floor with a grid of spheres lit by `n` small point lights (up to 1000) without shadows.
pub fn many_lights(n: usize) -> Scene {
    let n = n.min(1000);
    let materials = vec![
        Material::color("floor", [0.6, 0.6, 0.6], 0.5),
        Material::color("sphere", [0.8, 0.8, 0.8], 0.3),
    ];
    let mut meshes = vec![mesh(
        "floor",
        cuboid(Vec3::new(10.0, 0.1, 10.0)),
        0,
        Mat4::from_translation(Vec3::new(0.0, -0.1, 0.0)),
    )];
    for i in 0..8 {
        for j in 0..8 {
            let p = Vec3::new(-7.0 + i as f32 * 2.0, 0.5, -7.0 + j as f32 * 2.0);
            meshes.push(mesh(&format!("sphere_{i}_{j}"), sphere(0.5, 12, 16), 1, Mat4::from_translation(p)));
        }
    }
    // Deterministic pseudo-random placement and colours (no RNG dependency, same every run).
    let mut lights = vec![];
    let mut s = 0x9E37_79B9u32;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s as f32 / u32::MAX as f32
    };
    for _ in 0..n {
        let p = Vec3::new(next() * 18.0 - 9.0, 0.3 + next() * 1.5, next() * 18.0 - 9.0);
        let c = Vec3::new(0.3 + next() * 0.7, 0.3 + next() * 0.7, 0.3 + next() * 0.7);
        let mut l = Light::point(p, c, 1.5, 2.5);
        l.shadows = false;
        lights.push(l);
    }
    Scene {
        name: format!("many_lights_{n}"),
        size: (128, 128),
        camera: Camera {
            position: Vec3::new(0.0, 9.0, 12.0),
            yaw: 0.0,
            pitch: -35.0,
            fov: 55.0,
            near: 0.1,
            far: 100.0,
        },
        meshes,
        materials,
        textures: vec![],
        lights,
        effects: Default::default(),
    }
}
