//! Lights and their shadow-map matrices. Built with a safe up vector, so a spot light
//! pointing straight down (up parallel to the view direction) stays well defined.

use glam::{Mat4, Vec3};
use lightbench_compiler::abi::{LightBlock, LIGHT_AREA, LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SPOT};
use lightbench_compiler::ir::LightKind;

#[derive(Clone, Debug, PartialEq)]
pub enum Animation {
    /// Circle around `center` (in the XZ plane) at `radius`, `speed` degrees per second.
    Orbit { center: Vec3, radius: f32, speed: f32 },
    /// Turn the direction about the Y axis, `speed` degrees per second.
    Rotate { speed: f32 },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    pub on: bool,
    /// Linear RGB.
    pub color: Vec3,
    pub intensity: f32,
    pub position: Vec3,
    /// Where the light points (directional, spot); normalised on use.
    pub direction: Vec3,
    /// Spot cone half-angles in degrees: full intensity inside `inner`, none outside `outer`.
    pub inner_angle: f32,
    pub outer_angle: f32,
    /// Attenuation range (seed 003 eq. 3.5): contribution reaches 0 here.
    pub range: f32,
    pub shadows: bool,
    pub animation: Option<Animation>,
}

impl Light {
    pub fn point(position: Vec3, color: Vec3, intensity: f32, range: f32) -> Self {
        Light {
            kind: LightKind::Point,
            on: true,
            color,
            intensity,
            position,
            direction: Vec3::NEG_Y,
            inner_angle: 30.0,
            outer_angle: 45.0,
            range,
            shadows: true,
            animation: None,
        }
    }
    pub fn spot(position: Vec3, direction: Vec3, inner: f32, outer: f32, color: Vec3, intensity: f32, range: f32) -> Self {
        Light {
            kind: LightKind::Spot,
            direction,
            inner_angle: inner,
            outer_angle: outer,
            ..Self::point(position, color, intensity, range)
        }
    }
    pub fn directional(direction: Vec3, color: Vec3, intensity: f32) -> Self {
        Light {
            kind: LightKind::Directional,
            direction,
            range: 1e6,
            ..Self::point(Vec3::ZERO, color, intensity, 1e6)
        }
    }

    /// The light at time `t` seconds.
    pub fn at(&self, t: f32) -> Light {
        let mut l = self.clone();
        match &self.animation {
            Some(Animation::Orbit { center, radius, speed }) => {
                let a = (speed * t).to_radians();
                l.position = *center + Vec3::new(a.cos() * radius, 0.0, a.sin() * radius);
            }
            Some(Animation::Rotate { speed }) => {
                l.direction = glam::Quat::from_rotation_y((speed * t).to_radians()) * self.direction;
            }
            None => {}
        }
        l
    }

    fn dir(&self) -> Vec3 {
        let d = self.direction.normalize_or_zero();
        if d == Vec3::ZERO {
            Vec3::NEG_Y
        } else {
            d
        }
    }

    /// Shadow near/far planes of spot and point lights: the range and a fixed fraction of it,
    /// so that depth precision and the depth bias (in depth-buffer units) are the same at
    /// every scene scale.
    pub fn shadow_planes(&self) -> (f32, f32) {
        (self.range / SHADOW_NEAR_DIVISOR, self.range)
    }

    /// World -> shadow clip space: orthographic over the scene for directional lights,
    /// perspective over the outer cone for spot lights (and emitter lights, whose cone is
    /// their RSM's field of view).
    pub fn view_proj(&self, bounds: (Vec3, Vec3)) -> Mat4 {
        let d = self.dir();
        match self.kind {
            LightKind::Directional => {
                let center = (bounds.0 + bounds.1) * 0.5;
                // Fitted to the scene's bounding sphere, near plane included, at any scale.
                let radius = ((bounds.1 - bounds.0).length() * 0.5).max(1e-30);
                let eye = center - d * radius * 2.0;
                let view = super::math::look_to(eye, d, safe_up(d));
                super::math::orthographic(-radius, radius, -radius, radius, radius * 0.01, radius * 4.0) * view
            }
            _ => {
                let (n, f) = self.shadow_planes();
                let fov = (2.0 * self.outer_angle.clamp(1.0, 89.0)).to_radians();
                super::math::perspective(fov, 1.0, n, f) * super::math::look_to(self.position, d, safe_up(d))
            }
        }
    }

    /// World -> clip space of the 6 cube faces (+X, -X, +Y, -Y, +Z, -Z), set up so that a
    /// depth texel rendered on face i is where cube sampling with the same direction reads.
    /// wgpu's framebuffer rows grow downwards while cube-map t grows with -y on the side
    /// faces, so the projection mirrors y (which flips triangle winding: cull none or front).
    pub fn cube_view_proj(&self) -> [Mat4; 6] {
        let (n, f) = self.shadow_planes();
        let proj = Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0)) * super::math::perspective(std::f32::consts::FRAC_PI_2, 1.0, n, f);
        let faces = [
            (Vec3::X, Vec3::NEG_Y),
            (Vec3::NEG_X, Vec3::NEG_Y),
            (Vec3::Y, Vec3::Z),
            (Vec3::NEG_Y, Vec3::NEG_Z),
            (Vec3::Z, Vec3::NEG_Y),
            (Vec3::NEG_Z, Vec3::NEG_Y),
        ];
        faces.map(|(dir, up)| proj * super::math::look_to(self.position, dir, up))
    }

    pub fn block(&self, bounds: (Vec3, Vec3)) -> LightBlock {
        let (n, f) = self.shadow_planes();
        let faces = if self.kind == LightKind::Point {
            self.cube_view_proj().map(|m| m.to_cols_array_2d())
        } else {
            [Mat4::IDENTITY.to_cols_array_2d(); 6]
        };
        let c = self.color * self.intensity;
        LightBlock {
            color: [c.x, c.y, c.z, 0.0],
            position: [self.position.x, self.position.y, self.position.z, self.range],
            direction: {
                let d = self.dir();
                // An emitter light's area (its intensity: `Scene::emitter_lights`).
                let area = if self.kind == LightKind::Area { self.intensity } else { 0.0 };
                [d.x, d.y, d.z, area]
            },
            cone: [self.inner_angle.to_radians().cos(), self.outer_angle.to_radians().cos(), n, f],
            kind: match self.kind {
                LightKind::Directional => LIGHT_DIRECTIONAL,
                LightKind::Spot => LIGHT_SPOT,
                LightKind::Point => LIGHT_POINT,
                LightKind::Area => LIGHT_AREA,
            },
            casts_shadows: self.shadows as u32,
            _pad0: 0,
            _pad1: 0,
            view_proj: if self.kind == LightKind::Point {
                Mat4::IDENTITY.to_cols_array_2d()
            } else {
                self.view_proj(bounds).to_cols_array_2d()
            },
            face_view_proj: faces,
        }
    }
}

/// Spot and point shadow maps start at range / this (0.05 for the Cornell light's range 6).
pub const SHADOW_NEAR_DIVISOR: f32 = 120.0;

/// An up vector not parallel to `dir` (the lookAt hazard of a light pointing straight down).
pub fn safe_up(dir: Vec3) -> Vec3 {
    if dir.normalize_or_zero().dot(Vec3::Y).abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_down_spot_has_finite_matrix() {
        let l = Light::spot(Vec3::new(0.0, 2.0, 0.0), Vec3::NEG_Y, 20.0, 30.0, Vec3::ONE, 1.0, 5.0);
        let m = l.view_proj((Vec3::splat(-1.0), Vec3::splat(1.0)));
        assert!(m.to_cols_array().iter().all(|x| x.is_finite()));
        // The point under the light projects to the centre of the shadow map.
        let c = m.project_point3(Vec3::new(0.0, 0.0, 0.0));
        assert!(c.x.abs() < 1e-4 && c.y.abs() < 1e-4, "{c}");
    }

    /// Cube sampling (Vulkan/WebGPU face selection) and our face matrices agree on texels.
    #[test]
    fn cube_faces_match_cube_sampling() {
        let l = Light::point(Vec3::new(0.3, 1.0, -0.2), Vec3::ONE, 1.0, 10.0);
        let faces = l.cube_view_proj();
        for dir in [
            Vec3::new(1.0, 0.3, -0.2),
            Vec3::new(-1.0, -0.4, 0.5),
            Vec3::new(0.2, 1.0, 0.6),
            Vec3::new(-0.3, -1.0, 0.1),
            Vec3::new(0.4, -0.2, 1.0),
            Vec3::new(-0.6, 0.3, -1.0),
        ] {
            let a = dir.abs();
            // Face and (s, t) per the cube-map selection table.
            let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
                if dir.x > 0.0 {
                    (0, -dir.z, -dir.y, a.x)
                } else {
                    (1, dir.z, -dir.y, a.x)
                }
            } else if a.y >= a.z {
                if dir.y > 0.0 {
                    (2, dir.x, dir.z, a.y)
                } else {
                    (3, dir.x, -dir.z, a.y)
                }
            } else if dir.z > 0.0 {
                (4, dir.x, -dir.y, a.z)
            } else {
                (5, -dir.x, -dir.y, a.z)
            };
            let (u, v) = ((sc / ma + 1.0) * 0.5, (tc / ma + 1.0) * 0.5);
            let ndc = faces[face].project_point3(l.position + dir);
            let (fu, fv) = ((ndc.x + 1.0) * 0.5, (1.0 - ndc.y) * 0.5);
            assert!(
                (fu - u).abs() < 1e-4 && (fv - v).abs() < 1e-4,
                "dir {dir}: face {face} ({fu}, {fv}) vs ({u}, {v})"
            );
        }
    }
}
