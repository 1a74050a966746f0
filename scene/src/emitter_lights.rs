//! Emissive meshes as `Area` lights of the light array: what passes that list the kind (an
//! RSM of the light each emitter sends out) see of the scene's emitters. Direct light from
//! emitters is the area-light passes' and the reference's, from the triangles themselves.

use super::{Light, Scene};
use glam::Vec3;
use lightbench_compiler::ir::LightKind;

/// At most this many emissive meshes become `Area` lights (the most powerful): each costs
/// every pass that runs per `Area` light a repetition (an RSM and a gather each).
pub const MAX_EMITTER_LIGHTS: usize = 4;

/// Half the field of view an emitter's RSM sees about its normal, in degrees: a perspective
/// view cannot hold the whole hemisphere; a Lambertian emitter sends cos²(75°) = 6.7% of its
/// light beyond it (towards surfaces it grazes), which the RSM does not hold.
pub const EMITTER_HALF_ANGLE: f32 = 75.0;

/// Whether mesh `m` of `scene` emits: its material's emissive factor is not black (the rule
/// the area lights use; planning applies it to a model's JSON alike).
pub fn emits(scene: &Scene, m: &super::Mesh) -> bool {
    scene
        .materials
        .get(m.material)
        .is_some_and(|mat| mat.emissive.iter().any(|c| *c > 0.0))
}

impl Scene {
    /// The emissive meshes as `Area` lights, the most powerful first, at most
    /// `MAX_EMITTER_LIGHTS`: each at its drawn triangles' area-weighted centre, facing their
    /// area-weighted normal (the fronts' side), its `color` the mean emitted radiance and its
    /// `intensity` the area A — so colour × intensity = L·A, its intensity along the normal,
    /// which falls as cos θ (a flat Lambertian emitter seen from afar: exact for a flat lamp
    /// far from what it lights). Emissive maps are not looked up here (the factor counts);
    /// a double-sided emitter's back is not a light of its own.
    pub fn emitter_lights(&self) -> Vec<Light> {
        let (lo, hi) = self.bounds();
        let reach = 4.0 * (hi - lo).length().max(1e-6);
        let mut out: Vec<(f32, Light)> = self
            .meshes
            .iter()
            .filter(|m| emits(self, m))
            .map(|m| {
                let (area, centre, normal) = surface(m);
                let e = Vec3::from(self.materials[m.material].emissive);
                let mut l = Light::spot(centre, normal, EMITTER_HALF_ANGLE, EMITTER_HALF_ANGLE, e, area, reach);
                (l.kind, l.shadows) = (LightKind::Area, false);
                (area * (e.x + e.y + e.z), l)
            })
            .collect();
        out.sort_by(|a, b| b.0.total_cmp(&a.0));
        out.truncate(MAX_EMITTER_LIGHTS);
        out.into_iter().map(|(_, l)| l).collect()
    }

    /// The light array a frame binds: the lights that are on, in scene order, then the
    /// emitter lights. Plans name lights by their index in it.
    pub fn light_array(&self) -> Vec<Light> {
        let mut out: Vec<Light> = self.active_lights().into_iter().cloned().collect();
        out.extend(self.emitter_lights());
        out
    }
}

/// A mesh's drawn triangles in world space: total area, area-weighted centre and normal
/// (down where they have no area).
fn surface(m: &super::Mesh) -> (f32, Vec3, Vec3) {
    let drawn = &m.indices[..(m.drawn_indices() as usize).min(m.indices.len())];
    let (mut area, mut centre, mut normal) = (0.0f32, Vec3::ZERO, Vec3::ZERO);
    for t in drawn.chunks_exact(3) {
        let corner = |i: u32| {
            m.vertices
                .get(i as usize)
                .map(|v| m.transform.transform_point3(Vec3::from(v.position)))
        };
        let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) else {
            continue;
        };
        let n = (b - a).cross(c - a) * 0.5;
        let da = n.length();
        if !da.is_finite() || da <= 0.0 {
            continue;
        }
        area += da;
        centre += (a + b + c) / 3.0 * da;
        normal += n;
    }
    if area <= 0.0 {
        return (0.0, m.transform.transform_point3(Vec3::ZERO), Vec3::NEG_Y);
    }
    (area, centre / area, normal.try_normalize().unwrap_or(Vec3::NEG_Y))
}
