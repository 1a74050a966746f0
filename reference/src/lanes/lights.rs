//! Stage `integrate` in lanes, the lights: `PunctualLight::at` and `Lobes::eval` for the
//! vertices a lane group's paths have just reached, one light at a time over the 8 lanes (all
//! lanes take the same light, so its kind is one branch, not one per lane). The shadow rays
//! stay one per lane (`lanes::Context::lit`).

use super::brdf::{eval, Vertices};
use super::simd::{simd_dispatch, F8, M8, V8};
use crate::shading::{PunctualLight, ATTENUATION_SOFTNESS};
use glam::Vec3A;
use lightbench_compiler::ir::LightKind;

/// One light at every lane's vertex: the light it reflects towards the viewer if nothing is
/// in the way (BRDF × cos × radiance), the unit vector towards the light and its distance, and
/// which lanes it lights at all (a shadow ray decides the rest).
#[derive(Default)]
pub struct Lit {
    reflected: V8,
    l: V8,
    dist: F8,
    lights: M8,
}

impl Lit {
    /// Lane `i`: `(reflected, l, dist)` where the light reaches it before shadowing.
    pub fn at(&self, i: usize) -> Option<(Vec3A, Vec3A, f32)> {
        (self.lights.0[i] != 0).then(|| (self.reflected.at(i), self.l.at(i), self.dist.0[i]))
    }
}

simd_dispatch! {
    /// `light` at every lane of `d` (lanes without a vertex give what they hold; not read).
    pub fn light(light: &PunctualLight, d: &Vertices) -> Lit = light_lanes
}

#[inline(always)]
fn light_lanes(light: &PunctualLight, d: &Vertices) -> Lit {
    let zero = F8::splat(0.0);
    let (radiance, l, dist) = arriving(light, d.p);
    let (f, _, _) = eval(d.n, d.v, l, (d.diffuse, d.specular, d.exponent));
    let max = |a: V8| a.x.max(a.y).max(a.z);
    let lights = max(radiance).gt(zero) & max(f).gt(zero);
    let reflected = V8 {
        x: f.x * radiance.x,
        y: f.y * radiance.y,
        z: f.z * radiance.z,
    };
    Lit {
        reflected,
        l,
        dist,
        lights,
    }
}

/// `PunctualLight::at` at the points `p`: the light arriving before shadowing, the unit vector
/// towards the light and its distance.
#[inline(always)]
fn arriving(light: &PunctualLight, p: V8) -> (V8, V8, F8) {
    let splat = |v: Vec3A| V8 {
        x: F8::splat(v.x),
        y: F8::splat(v.y),
        z: F8::splat(v.z),
    };
    if light.kind == LightKind::Directional {
        return (splat(light.radiance), splat(-light.direction), F8::splat(f32::INFINITY));
    }
    let d = splat(light.position).plus(p.scale(F8::splat(-1.0)));
    let dist = d.dot(d).sqrt();
    let to_light = d.scale(F8::splat(1.0) / dist.max(F8::splat(1e-6)));
    let mut strength = attenuation(dist, light.range);
    if light.kind == LightKind::Spot {
        let axis = splat(light.direction);
        let c = d.scale(F8::splat(-1.0)).normalize_or(axis).dot(axis);
        let inner = light.cos_inner.max(light.cos_outer + 1e-4);
        strength = strength * smoothstep(light.cos_outer, inner, c);
    }
    (splat(light.radiance).scale(strength), to_light, dist)
}

/// `shading::attenuation`: (1 − (d/r)²⁰) / ((r/6)² + d²), 0 from the range on.
#[inline(always)]
fn attenuation(d: F8, range: f32) -> F8 {
    let r = range.max(1e-30);
    let x = (d / F8::splat(r)).max(F8::splat(0.0)).min(F8::splat(1.0));
    let x5 = x * x * x * x * x;
    let x20 = (x5 * x5) * (x5 * x5);
    let soft = r / ATTENUATION_SOFTNESS;
    (F8::splat(1.0) - x20) / (F8::splat(soft * soft) + d * d)
}

#[inline(always)]
fn smoothstep(e0: f32, e1: f32, x: F8) -> F8 {
    let t = ((x - F8::splat(e0)) / F8::splat(e1 - e0)).max(F8::splat(0.0)).min(F8::splat(1.0));
    t * t * (F8::splat(3.0) - F8::splat(2.0) * t)
}
