//! Built-in scenes as descriptions: camera, size, lights and effects. Their meshes are made
//! by the runtime from `geometry` (the same name), so tests and the default render need no
//! downloads, and `check`/`plan` know a built-in scene's lights without a GPU.

use super::{CameraDesc, KeySpans, LightDesc, SceneDesc};
use crate::ir::Effect;

pub const NAMES: [&str; 5] = ["cornell", "cornell_lamp", "colonnade", "many_lights", "panes"];

/// Lights of `many_lights` (the built-in); `many_lights(n)` makes other counts for tests.
pub const MANY_LIGHTS: usize = 100;
/// The most lights `many_lights(n)` makes: past this a frame is all light loops.
pub const MAX_MANY_LIGHTS: usize = 1000;

pub fn by_name(name: &str) -> Option<SceneDesc> {
    match name {
        "cornell" => Some(cornell()),
        "cornell_lamp" => Some(cornell_lamp()),
        "colonnade" => Some(colonnade()),
        "many_lights" => Some(many_lights(MANY_LIGHTS)),
        "panes" => Some(panes()),
        _ => None,
    }
}

fn camera(position: [f32; 3], yaw: f32, pitch: f32, fov: f32, near: f32, far: f32) -> CameraDesc {
    CameraDesc {
        position,
        yaw,
        pitch,
        fov,
        near,
        far,
        animation: None,
        at: KeySpans::default(),
    }
}

fn scene(name: &str, size: (u32, u32), camera: CameraDesc, lights: Vec<LightDesc>, shadows: bool) -> SceneDesc {
    SceneDesc {
        geometry: Some(name.into()),
        size,
        camera,
        lights,
        effects: shadows.then_some(Effect::Shadows).into_iter().collect(),
        ..SceneDesc::empty(name)
    }
}

/// A Cornell box 2 units wide, deep and tall (floor at y = 0, open towards +Z) with a
/// point light under the ceiling.
pub fn cornell() -> SceneDesc {
    let cam = camera([0.0, 1.0, 3.6], 0.0, 0.0, 40.0, 0.05, 20.0);
    let light = LightDesc::point([0.0, 1.8, 0.1], [1.0, 0.95, 0.85], 4.0, 6.0);
    scene("cornell", (128, 128), cam, vec![light], true)
}

/// The Cornell box lit as the classic one is, by an emissive panel alone (0.47 × 0.38 under
/// the ceiling, single-sided, facing down): no light of the light array. The raster pipelines
/// light it with `area_lights = ltc`; the reference samples the panel.
pub fn cornell_lamp() -> SceneDesc {
    let cam = camera([0.0, 1.0, 3.6], 0.0, 0.0, 40.0, 0.05, 20.0);
    scene("cornell_lamp", (128, 128), cam, vec![], false)
}

/// A colonnade lit by a low sun and a spot light.
pub fn colonnade() -> SceneDesc {
    let cam = camera([-13.0, 2.0, 0.0], 90.0 - 180.0, -5.0, 60.0, 0.1, 100.0);
    let lights = vec![
        LightDesc::directional([0.4, -0.6, 0.5], [1.0, 0.92, 0.8], 2.5),
        LightDesc::spot([0.0, 6.0, 0.0], [0.0, -1.0, 0.0], (25.0, 35.0), [0.8, 0.85, 1.0], 30.0, 12.0),
    ];
    scene("colonnade", (256, 128), cam, lights, true)
}

/// Three coloured glass panes that pass through each other, before a wall, lit from the
/// front: no order of whole objects blends them right (transparency options).
pub fn panes() -> SceneDesc {
    let cam = camera([0.0, 1.0, 3.0], 0.0, 0.0, 45.0, 0.05, 20.0);
    let light = LightDesc::point([1.2, 2.2, 2.0], [1.0, 0.97, 0.92], 6.0, 8.0);
    scene("panes", (128, 128), cam, vec![light], false)
}

/// A grid of spheres lit by `n` small point lights (at most [`MAX_MANY_LIGHTS`]) without shadows.
pub fn many_lights(n: usize) -> SceneDesc {
    let n = n.min(MAX_MANY_LIGHTS);
    // Deterministic pseudo-random placement and colours (no RNG dependency, same every run).
    let mut s = 0x9E37_79B9u32;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s as f32 / u32::MAX as f32
    };
    let mut lights = vec![];
    for _ in 0..n {
        let p = [next() * 18.0 - 9.0, 0.3 + next() * 1.5, next() * 18.0 - 9.0];
        let c = [0.3 + next() * 0.7, 0.3 + next() * 0.7, 0.3 + next() * 0.7];
        let mut l = LightDesc::point(p, c, 1.5, 2.5);
        l.shadows = false;
        lights.push(l);
    }
    let cam = camera([0.0, 9.0, 12.0], 0.0, -35.0, 55.0, 0.1, 100.0);
    let mut desc = scene("many_lights", (128, 128), cam, lights, false);
    desc.name = format!("many_lights_{n}");
    desc
}
