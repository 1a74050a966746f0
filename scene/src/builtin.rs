//! Built-in scenes: their descriptions (camera, lights, effects) come from the compiler's
//! `scene::builtin`; their meshes and materials are made here, in code, so tests and the
//! default render need no downloads.

use super::geometry::{cuboid, cylinder, quad, sphere};
use super::{Material, Mesh, Scene};
use glam::{Mat4, Quat, Vec3};
use lightbench_compiler::scene::builtin as desc;

pub use desc::NAMES;

/// A built-in scene, complete with geometry.
pub fn by_name(name: &str) -> Option<Scene> {
    desc::by_name(name).map(|d| Scene::from_desc(&d))
}

pub fn cornell() -> Scene {
    Scene::from_desc(&desc::cornell())
}

/// The Cornell box lit by an emissive panel alone, as the classic box is: 0.47 × 0.38 under
/// the ceiling, single-sided, facing down, no point light (the built-in `cornell_lamp`).
pub fn cornell_lamp() -> Scene {
    Scene::from_desc(&desc::cornell_lamp())
}

fn cornell_lamp_geometry() -> (Vec<Mesh>, Vec<Material>) {
    let (mut meshes, mut materials) = cornell_geometry();
    let mut lamp = Material::color("lamp", [0.78; 3], 1.0);
    lamp.emissive = [17.0, 12.0, 4.0];
    let (mut vs, mut is) = (vec![], vec![]);
    quad(Vec3::new(0.0, 1.99, 0.0), Vec3::X * 0.235, Vec3::Z * 0.19, &mut vs, &mut is);
    meshes.push(mesh("lamp", (vs, is), materials.len(), Mat4::IDENTITY));
    materials.push(lamp);
    (meshes, materials)
}

pub fn colonnade() -> Scene {
    Scene::from_desc(&desc::colonnade())
}

/// `many_lights` with `n` lights.
pub fn many_lights(n: usize) -> Scene {
    Scene::from_desc(&desc::many_lights(n))
}

/// Meshes and materials of the built-in geometry `name`.
pub fn geometry(name: &str) -> Option<(Vec<Mesh>, Vec<Material>)> {
    match name {
        "cornell" => Some(cornell_geometry()),
        "cornell_lamp" => Some(cornell_lamp_geometry()),
        "colonnade" => Some(colonnade_geometry()),
        "many_lights" => Some(many_lights_geometry()),
        "panes" => Some(panes_geometry()),
        _ => None,
    }
}

fn mesh(name: &str, (vertices, indices): (Vec<lightbench_compiler::abi::Vertex>, Vec<u32>), material: usize, transform: Mat4) -> Mesh {
    Mesh::new(name, vertices, indices, material, transform)
}

/// A Cornell box 2 units wide, deep and tall (floor at y = 0, open towards +Z) with a tall
/// and a short box.
fn cornell_geometry() -> (Vec<Mesh>, Vec<Material>) {
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
    (meshes, materials)
}

/// The [`PANES`], a back wall and a floor.
fn panes_geometry() -> (Vec<Mesh>, Vec<Material>) {
    let mut materials = vec![Material::color("wall", [0.6, 0.6, 0.6], 0.8)];
    let mut meshes = vec![];
    let mut wall = |name: &str, c: Vec3, u: Vec3, w: Vec3| {
        let (mut vs, mut is) = (vec![], vec![]);
        quad(c, u, w, &mut vs, &mut is);
        meshes.push(mesh(name, (vs, is), 0, Mat4::IDENTITY));
    };
    wall("back", Vec3::new(0.0, 1.75, -1.5), Vec3::X * 2.5, Vec3::Y * 1.75);
    wall("floor", Vec3::new(0.0, 0.0, 0.0), Vec3::X * 2.5, Vec3::NEG_Z * 1.5);
    for (name, rgb, rotation) in PANES {
        let mut glass = Material::color(name, rgb, 0.3);
        glass.base_color[3] = 0.5;
        glass.emissive = rgb.map(|c| 0.25 * c);
        glass.alpha = super::AlphaMode::Blend;
        glass.double_sided = true;
        let (mut vs, mut is) = (vec![], vec![]);
        let (u, w) = panes_pane(rotation);
        quad(PANES_CENTRE, u, w, &mut vs, &mut is);
        meshes.push(mesh(name, (vs, is), materials.len(), Mat4::IDENTITY));
        materials.push(glass);
    }
    (meshes, materials)
}

/// The centre all panes pass through.
pub const PANES_CENTRE: Vec3 = Vec3::new(0.0, 1.0, 0.0);

/// The panes: name, colour (base and a quarter of it emitted; opacity 0.5) and orientation,
/// a rotation of a square facing the camera (+Z).
pub const PANES: [(&str, [f32; 3], Quat); 3] = [
    ("red", [0.9, 0.1, 0.1], Quat::from_xyzw(0.0, 0.300_705_8, 0.0, 0.953_717)), // 35° about Y
    ("green", [0.1, 0.9, 0.1], Quat::from_xyzw(0.0, -0.300_705_8, 0.0, 0.953_717)), // -35° about Y
    ("blue", [0.1, 0.2, 0.9], Quat::from_xyzw(0.300_705_8, 0.0, 0.0, 0.953_717)), // 35° about X
];

/// Half-axes of a pane turned by `rotation`: a square 1.2 wide.
pub fn panes_pane(rotation: Quat) -> (Vec3, Vec3) {
    (rotation * Vec3::X * 0.6, rotation * Vec3::Y * 0.6)
}

/// A colonnade: two rows of columns under beams on a long floor (a Sponza stand-in: many
/// draws for shadow and draw-count tests).
fn colonnade_geometry() -> (Vec<Mesh>, Vec<Material>) {
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
    (meshes, materials)
}

/// A floor with a grid of spheres (the lights are the description's).
fn many_lights_geometry() -> (Vec<Mesh>, Vec<Material>) {
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
    (meshes, materials)
}
