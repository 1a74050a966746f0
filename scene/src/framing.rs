//! A model rendered on its own (a glTF file as the scene): the camera that frames its bounds and
//! the default light rig, both derived from the bounds so that a model in millimetres and
//! one in kilometres come out alike.
//!
//! Framing rule: the camera looks at the centre of the bounding box from the front (+Z side,
//! looking down -Z) and 20° above, with a 40° vertical field of view, at the distance where
//! the bounding sphere (radius: half the box's diagonal), enlarged by 10%, fits the narrower
//! of the two fields of view. Near and far hug the sphere: near = (d - r) / 2, far = 2 (d + r).
//!
//! Default rig (used only when the model brings no KHR lights): a key light from the upper
//! left front (directional, intensity 3, casting shadows) and a fill from the right
//! (directional, intensity 1, no shadows). Directional lights have no position or range, so
//! the rig is the same at every scale; their shadow maps fit the scene bounds.

use super::{Camera, Light, Scene};
use glam::Vec3;

pub const FOV: f32 = 40.0;
pub const PITCH: f32 = -20.0;
/// How much larger than the bounding sphere the framed view is.
pub const MARGIN: f32 = 1.1;

/// The camera that frames the scene's meshes at its output size.
pub fn frame(scene: &Scene) -> Camera {
    let (lo, hi) = scene.bounds();
    let centre = (lo + hi) * 0.5;
    let r = ((hi - lo).length() * 0.5).max(1e-6) * MARGIN;
    let aspect = scene.size.0 as f32 / scene.size.1.max(1) as f32;
    let half_v = (FOV * 0.5).to_radians();
    let half_h = (half_v.tan() * aspect).atan();
    let d = r / half_v.min(half_h).sin();
    let mut camera = Camera {
        position: Vec3::ZERO,
        yaw: 0.0,
        pitch: PITCH,
        fov: FOV,
        near: (d - r) * 0.5,
        far: (d + r) * 2.0,
        animation: None,
    };
    camera.position = centre - camera.forward() * d;
    camera
}

/// Key and fill lights for a model that has none.
pub fn default_rig() -> Vec<Light> {
    let key = Light::directional(Vec3::new(0.5, -1.0, -0.6), Vec3::new(1.0, 0.97, 0.92), 3.0);
    let mut fill = Light::directional(Vec3::new(-0.8, -0.3, -0.4), Vec3::new(0.9, 0.95, 1.0), 1.0);
    fill.shadows = false;
    vec![key, fill]
}
