//! Light volumes (seed 003 §3.2.1): the unit meshes the standard `light_volumes` binding
//! holds and the vertex range a `draw: LightVolume` repetition draws for its light.
//!
//! One non-indexed triangle list of `vec4` corners; `w` names the shape, which
//! `shaders/lib/light_volume.wgsl` places: 0 a sphere of radius ≥ 1 (scaled by the light's
//! range), 1 a cone with its apex at the origin along +z reaching z = 1 with radius ≥ 1 there
//! (scaled by range and the tangent of the outer angle), 2 one triangle already in clip space
//! covering the screen. Every triangle faces outwards (counter-clockwise seen from outside),
//! so a pass with `cull Front` draws each pixel a convex volume covers once, from its far
//! side, whether or not the camera is inside it. The screen triangle is wound clockwise so
//! that it survives `cull Front` too.

use lightbench_compiler::ir::LightKind;
use std::ops::Range;

use lightbench_scene::Light;

const SPHERE: f32 = 0.0;
const CONE: f32 = 1.0;
const SCREEN: f32 = 2.0;

/// Icosphere subdivisions: 320 triangles, "a few hundred vertices" (seed 003 §3.2.1).
const SPHERE_LEVELS: u32 = 2;
/// Sides of the cone's polygonal base.
const CONE_SIDES: u32 = 24;
/// Spot lights wider than this get the sphere: a cone's base grows as tan(outer angle).
const WIDEST_CONE_DEG: f32 = 75.0;

/// The corners of every volume and where each shape's vertices lie.
pub struct LightVolumes {
    pub corners: Vec<[f32; 4]>,
    sphere: Range<u32>,
    cone: Range<u32>,
    screen: Range<u32>,
}

impl Default for LightVolumes {
    fn default() -> Self {
        Self::new()
    }
}

impl LightVolumes {
    pub fn new() -> LightVolumes {
        fn push(tris: Vec<[glam::Vec3; 3]>, shape: f32, corners: &mut Vec<[f32; 4]>) -> Range<u32> {
            let start = corners.len() as u32;
            corners.extend(tris.iter().flatten().map(|v| v.extend(shape).to_array()));
            start..corners.len() as u32
        }
        let mut corners = vec![];
        let sphere = push(icosphere(SPHERE_LEVELS), SPHERE, &mut corners);
        let cone = push(cone(CONE_SIDES), CONE, &mut corners);
        let screen = push(
            vec![[glam::vec3(-1.0, -1.0, 0.0), glam::vec3(-1.0, 3.0, 0.0), glam::vec3(3.0, -1.0, 0.0)]],
            SCREEN,
            &mut corners,
        );
        LightVolumes {
            corners,
            sphere,
            cone,
            screen,
        }
    }

    /// The vertices a repetition for `light` draws.
    pub fn range_for(&self, light: &Light) -> Range<u32> {
        match light.kind {
            LightKind::Directional => self.screen.clone(),
            LightKind::Spot if light.outer_angle <= WIDEST_CONE_DEG => self.cone.clone(),
            LightKind::Spot | LightKind::Point | LightKind::Area => self.sphere.clone(),
        }
    }
}

/// An icosahedron subdivided `levels` times, scaled so that every face lies outside the unit
/// sphere (the mesh bounds the light's reach, it does not approximate it from inside).
fn icosphere(levels: u32) -> Vec<[glam::Vec3; 3]> {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let v: Vec<glam::Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| glam::vec3(x, y, z).normalize())
    .collect();
    let faces = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut tris: Vec<[glam::Vec3; 3]> = faces.iter().map(|f| [v[f[0]], v[f[1]], v[f[2]]]).collect();
    for _ in 0..levels {
        tris = tris
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = ((a + b).normalize(), (b + c).normalize(), (c + a).normalize());
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect();
    }
    // The nearest face plane to the centre sets the scale that puts it at distance 1.
    let inradius = tris
        .iter()
        .map(|[a, b, c]| (b - a).cross(c - a).normalize().dot(*a).abs())
        .fold(f32::INFINITY, f32::min);
    tris.iter().map(|t| t.map(|p| p / inradius)).collect()
}

/// A cone with its apex at the origin, opening along +z to a base at z = 1 whose polygon
/// encloses the unit circle, closed by the base.
fn cone(sides: u32) -> Vec<[glam::Vec3; 3]> {
    let r = 1.0 / (std::f32::consts::PI / sides as f32).cos();
    let rim = |i: u32| {
        let a = i as f32 / sides as f32 * std::f32::consts::TAU;
        glam::vec3(r * a.cos(), r * a.sin(), 1.0)
    };
    let (apex, centre) = (glam::Vec3::ZERO, glam::Vec3::Z);
    (0..sides)
        .flat_map(|i| [[apex, rim(i + 1), rim(i)], [centre, rim(i), rim(i + 1)]])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each triangle's outward normal (counter-clockwise winding) points away from `inside`.
    fn faces_out(tris: &[glam::Vec3], inside: glam::Vec3) -> bool {
        tris.chunks(3).all(|t| {
            let n = (t[1] - t[0]).cross(t[2] - t[0]);
            n.dot((t[0] + t[1] + t[2]) / 3.0 - inside) > 0.0
        })
    }

    fn shape(v: &LightVolumes, r: Range<u32>) -> Vec<glam::Vec3> {
        v.corners[r.start as usize..r.end as usize]
            .iter()
            .map(|c| glam::vec3(c[0], c[1], c[2]))
            .collect()
    }

    #[test]
    fn volumes_face_outwards_and_enclose_the_unit_shapes() {
        let v = LightVolumes::new();
        let sphere = shape(&v, v.sphere.clone());
        assert_eq!(sphere.len(), 960);
        assert!(faces_out(&sphere, glam::Vec3::ZERO));
        // Every face plane at least 1 from the centre: the unit sphere is inside.
        let nearest = sphere
            .chunks(3)
            .map(|t| (t[1] - t[0]).cross(t[2] - t[0]).normalize().dot(t[0]))
            .fold(f32::INFINITY, f32::min);
        assert!((nearest - 1.0).abs() < 1e-5, "{nearest}");
        let cone = shape(&v, v.cone.clone());
        assert!(faces_out(&cone, glam::vec3(0.0, 0.0, 0.5)));
        // The unit circle at z = 1 (and so the cone of radius z below it) lies inside every side.
        for k in 0..360 {
            let a = (k as f32).to_radians();
            let p = glam::vec3(a.cos(), a.sin(), 1.0) * 0.999;
            let inside = cone.chunks(3).all(|t| (t[1] - t[0]).cross(t[2] - t[0]).dot(p - t[0]) <= 1e-5);
            assert!(inside, "angle {k}");
        }
        // The screen triangle is clockwise in clip space (y up) and covers [-1, 1]².
        let s = shape(&v, v.screen.clone());
        assert!((s[1] - s[0]).cross(s[2] - s[0]).z < 0.0);
    }

    #[test]
    fn lights_get_their_shapes() {
        let v = LightVolumes::new();
        let mut l = Light::point(glam::Vec3::ZERO, glam::Vec3::ONE, 1.0, 2.0);
        assert_eq!(v.range_for(&l), v.sphere);
        l.kind = LightKind::Spot;
        assert_eq!(v.range_for(&l), v.cone);
        l.outer_angle = 89.0;
        assert_eq!(v.range_for(&l), v.sphere, "a wide spot gets the sphere");
        l.kind = LightKind::Directional;
        assert_eq!(v.range_for(&l), v.screen);
    }
}
