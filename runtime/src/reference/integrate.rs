//! Stage `integrate` of the reference renderer: one Monte Carlo estimate per term at the
//! surface a camera ray found. Each term is the exact quantity a raster effect approximates
//! (see `Term` for the definitions).

use super::sample::{cosine_hemisphere, power_lobe, Rng};
use super::shading::{shininess, Brdf, PunctualLight};
use super::world::{Faces, Hit, World};
use glam::Vec3;

/// Bounces after which Russian roulette may end a `full` path, and the hard cap.
const ROULETTE_FROM: u32 = 3;
const MAX_BOUNCES: u32 = 256;

pub struct Context<'a> {
    pub world: &'a World,
    pub lights: Vec<PunctualLight>,
    pub brdf: Brdf,
    /// Distance rays start off a surface (a fraction of the scene's size): no self-hits.
    pub eps: f32,
    pub ao_radius: f32,
    pub ao_falloff: bool,
}

impl Context<'_> {
    fn origin(&self, h: &Hit) -> Vec3 {
        h.position + h.ng * self.eps
    }

    /// Light from the scene's lights reflected at `h` towards `v`, with exact visibility
    /// (hard shadows): what the raster light passes compute with shadow maps.
    pub fn direct_light(&self, h: &Hit, v: Vec3) -> Vec3 {
        let origin = self.origin(h);
        let mut sum = Vec3::ZERO;
        for light in &self.lights {
            let (radiance, l, dist) = light.at(h.position);
            if radiance.max_element() <= 0.0 {
                continue;
            }
            let f = self.brdf.eval(h, l, v);
            if f.max_element() <= 0.0 {
                continue;
            }
            // A light closer than the offset (on the surface) is not shadowed.
            let tmax = dist - self.eps;
            if tmax <= 0.0 || !self.world.occluded(origin, l, 0.0, tmax) {
                sum += f * radiance;
            }
        }
        sum
    }

    /// `direct`: emission plus the lights' light with hard shadows.
    pub fn direct(&self, h: &Hit, v: Vec3) -> Vec3 {
        h.emissive + self.direct_light(h, v)
    }

    /// `ao`: 1 minus the cosine-weighted share of directions that meet a surface within the
    /// radius, each weighed 1/(1 + d²) with the falloff (as `occluder_weight()` does).
    pub fn ao(&self, h: &Hit, rng: &mut Rng) -> f32 {
        let d = cosine_hemisphere(h.n, rng.pair());
        if h.ng.dot(d) <= 0.0 {
            return 0.0;
        }
        match self.world.trace(self.origin(h), d, (0.0, self.ao_radius), Faces::Both) {
            Some(hit) if self.ao_falloff => 1.0 - 1.0 / (1.0 + hit.t * hit.t),
            Some(_) => 0.0,
            None => 1.0,
        }
    }

    /// `indirect_diffuse`: one bounce of the lights' light off the surfaces around, as a
    /// white Lambertian receiver reflects it: (1/π) ∫ L_direct(y → x) cos θ dω. Raster
    /// indirect diffuse (`gi.indirect`) holds this before the albedo is applied.
    pub fn indirect_diffuse(&self, h: &Hit, rng: &mut Rng) -> Vec3 {
        let d = cosine_hemisphere(h.n, rng.pair());
        if h.ng.dot(d) <= 0.0 {
            return Vec3::ZERO;
        }
        match self.world.trace(self.origin(h), d, (0.0, f32::INFINITY), Faces::Seen) {
            Some(y) => self.direct_light(&y, -d),
            None => Vec3::ZERO,
        }
    }

    /// `indirect_specular`: the light seen in the reflection — emitted and directly lit
    /// surfaces along directions drawn from the specular lobe about the mirror direction
    /// (a mirror at low roughness), averaged; before the surface's reflectance is applied,
    /// as raster SSR (`ssr.color`) holds it.
    pub fn indirect_specular(&self, h: &Hit, v: Vec3, rng: &mut Rng) -> Vec3 {
        let half = power_lobe(h.n, shininess(h.roughness).max(1.0), rng.pair());
        let l = (2.0 * v.dot(half) * half - v).normalize_or_zero();
        if h.ng.dot(l) <= 0.0 || h.n.dot(l) <= 0.0 {
            return Vec3::ZERO;
        }
        match self.world.trace(self.origin(h), l, (0.0, f32::INFINITY), Faces::Seen) {
            Some(y) => self.direct(&y, -l),
            None => Vec3::ZERO,
        }
    }

    /// `full`: all light leaving the surface towards `v`, every bounce (path tracing with
    /// the lights sampled at every vertex, Russian roulette after a few bounces).
    pub fn full(&self, h: &Hit, v: Vec3, rng: &mut Rng) -> Vec3 {
        let (mut h, mut v) = (*h, v);
        let mut sum = self.direct(&h, v);
        let mut throughput = Vec3::ONE;
        for bounce in 1..=MAX_BOUNCES {
            let (u, choose) = (rng.pair(), rng.uniform());
            let (l, w) = self.brdf.sample(&h, v, u, choose);
            throughput *= w;
            if throughput.max_element() <= 0.0 {
                break;
            }
            if bounce > ROULETTE_FROM {
                let survive = throughput.max_element().min(0.95);
                if rng.uniform() >= survive {
                    break;
                }
                throughput /= survive;
            }
            let Some(y) = self.world.trace(self.origin(&h), l, (0.0, f32::INFINITY), Faces::Seen) else {
                break;
            };
            sum += throughput * self.direct(&y, -l);
            (h, v) = (y, -l);
        }
        sum
    }
}
