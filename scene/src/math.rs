//! Camera and light transforms in wgpu's conventions: right-handed view space, NDC y up,
//! depth 0..1 (glam's "directx" projections).

use glam::{Mat4, Vec3};

pub fn look_to(eye: Vec3, dir: Vec3, up: Vec3) -> Mat4 {
    glam::camera::rh::view::look_to_mat4(eye, dir, up)
}

pub fn perspective(fov_y: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    glam::camera::rh::proj::directx::perspective(fov_y, aspect, near, far)
}

pub fn orthographic(l: f32, r: f32, b: f32, t: f32, near: f32, far: f32) -> Mat4 {
    glam::camera::rh::proj::directx::orthographic(l, r, b, t, near, far)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depth_range_is_zero_to_one() {
        let p = perspective(1.0, 1.0, 0.5, 10.0);
        assert!((p.project_point3(Vec3::new(0.0, 0.0, -0.5)).z - 0.0).abs() < 1e-5);
        assert!((p.project_point3(Vec3::new(0.0, 0.0, -10.0)).z - 1.0).abs() < 1e-5);
        let v = look_to(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y);
        assert_eq!(v, Mat4::IDENTITY);
    }
}
