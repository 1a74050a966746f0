//! Stage `integrate` of the reference renderer: one Monte Carlo estimate per term at the
//! surface a camera ray found. Each term is the exact quantity a raster effect approximates
//! (see `Term` for the definitions).

use super::emitters::{Emitters, LightSample};
use super::sample::{cosine_hemisphere, power_lobe, Rng};
use super::shading::{shininess, Brdf, Lobes, PunctualLight};
use super::world::{Faces, Hit, World};
use glam::Vec3A;

/// Bounces after which Russian roulette may end a `full` path, and the hard cap.
pub(crate) const ROULETTE_FROM: u32 = 3;
pub(crate) const MAX_BOUNCES: u32 = 256;

pub struct Context<'a> {
    pub world: &'a World,
    pub lights: Vec<PunctualLight>,
    /// The emissive triangles, sampled as lights at every vertex.
    pub emitters: Emitters,
    pub brdf: Brdf,
    /// Distance rays start off a surface (a fraction of the scene's size): no self-hits.
    pub eps: f32,
    pub ao_radius: f32,
    pub ao_falloff: bool,
    /// Next-event estimation of the emitters (with MIS); off, only BRDF sampling finds them
    /// (what the reference did before: a check that both estimate the same).
    pub sample_emitters: bool,
}

/// Power-heuristic weight of a strategy of density `p` against one of density `other`.
fn power_heuristic(p: f32, other: f32) -> f32 {
    let r = other / p;
    if r.is_finite() {
        1.0 / (1.0 + r * r)
    } else {
        0.0
    }
}

/// What every sample of a pixel shares at the surface its camera ray found: the surface, its
/// BRDF and (when a term uses it) the light arriving there from the scene's lights —
/// deterministic, so worked out once per pixel instead of once per sample (the same numbers
/// either way).
pub struct Primary {
    pub hit: Hit,
    pub(crate) lobes: Lobes,
    lights: Option<Vec3A>,
}

impl Context<'_> {
    /// The shared part of the pixel whose camera ray found `h` (seen from `v`); the lights'
    /// light (a shadow ray per light) only `with_lights`, for the terms that add it.
    pub fn primary(&self, h: &Hit, v: Vec3A, with_lights: bool, coin: u32) -> Primary {
        let lobes = self.brdf.at(h);
        Primary {
            hit: *h,
            lobes,
            lights: with_lights.then(|| self.lights(h, &lobes, v, coin)),
        }
    }

    /// The lights' light at a pixel's surface, seen from `v`: kept, or worked out now.
    pub(crate) fn primary_lights(&self, p: &Primary, v: Vec3A) -> Vec3A {
        p.lights.unwrap_or_else(|| self.lights(&p.hit, &p.lobes, v, 0))
    }

    fn origin(&self, h: &Hit) -> Vec3A {
        h.position + h.ng * self.eps
    }

    /// The nearest surface along `dir` from just off `h`, no farther than `tmax`. Rays leaving
    /// a surface (here and in the shadow rays) pass what lies nearer than the offset: at a
    /// corner the offset origin can round onto or just behind the other surface, which
    /// shadows nothing of the corner itself.
    pub(crate) fn trace_from(&self, h: &Hit, dir: Vec3A, tmax: f32, faces: Faces) -> Option<Hit> {
        self.world.trace(self.origin(h), dir, (self.eps, tmax), faces)
    }

    /// Whether `term`'s estimate has no noise, so one sample per pixel is enough: `direct`
    /// with point lights only (with emitters, it samples them) and nothing blended (its
    /// coins differ between samples).
    pub fn exact(&self, term: super::Term) -> bool {
        term == super::Term::Direct && self.emitters.is_empty() && !self.world.has_blended()
    }

    /// Whether the emitters are sampled as lights (else BRDF sampling alone finds them).
    fn emits(&self) -> bool {
        self.sample_emitters && !self.emitters.is_empty()
    }

    /// Light from the scene's lights reflected at `h` towards `v`, with exact visibility
    /// (hard shadows): what the raster light passes compute with shadow maps. Blended
    /// surfaces in the way pass the light by `coin` (see `World::trace_with_coin`).
    pub fn lights(&self, h: &Hit, b: &Lobes, v: Vec3A, coin: u32) -> Vec3A {
        let origin = self.origin(h);
        let mut sum = Vec3A::ZERO;
        for light in &self.lights {
            let (radiance, l, dist) = light.at(h.position);
            if radiance.max_element() <= 0.0 {
                continue;
            }
            let f = b.eval(h, l, v);
            if f.max_element() <= 0.0 {
                continue;
            }
            // A light closer than the offset (on the surface) is not shadowed.
            let tmax = dist - self.eps;
            if tmax <= 0.0 || !self.world.occluded_with_coin(origin, l, (self.eps, tmax), coin) {
                sum += f * radiance;
            }
        }
        sum
    }

    /// Light from one point drawn on an emitter, reflected at `h` towards `v` (next-event
    /// estimation), weighed against BRDF sampling by the power heuristic when `mis`. Draws
    /// no random numbers when nothing emits (point-lit images stay as they were).
    pub fn emitted_light(&self, h: &Hit, b: &Lobes, v: Vec3A, rng: &mut Rng, mis: bool) -> Vec3A {
        match self.emitter_point(h, rng) {
            Some(s) => self.emitter_light(h, &s, b.eval_pdf(h, s.l, v), mis),
            None => Vec3A::ZERO,
        }
    }

    /// `emitted_light`'s point on an emitter, drawn for `h`: none where nothing emits, or
    /// where the point lies below the geometric surface (BRDF sampling never goes there) or
    /// sends no light.
    pub(crate) fn emitter_point(&self, h: &Hit, rng: &mut Rng) -> Option<LightSample> {
        if !self.emits() {
            return None;
        }
        let u = (rng.uniform(), rng.uniform(), rng.uniform());
        let s = self.emitters.sample(self.world, h.position, u)?;
        (h.ng.dot(s.l) > 0.0 && s.radiance.max_element() > 0.0).then_some(s)
    }

    /// `emitted_light` from point `s`, given the BRDF × cos and the BRDF's density towards it.
    pub(crate) fn emitter_light(&self, h: &Hit, s: &LightSample, (f, brdf_pdf): (Vec3A, f32), mis: bool) -> Vec3A {
        if f.max_element() <= 0.0 || !self.visible(h, h.position + s.l * s.dist) {
            return Vec3A::ZERO;
        }
        let w = if mis { power_heuristic(s.pdf, brdf_pdf) } else { 1.0 };
        f * s.radiance * (w / s.pdf)
    }

    /// Whether nothing lies between `h` and the point `p` on a surface: the shadow ray runs
    /// from the offset origin to `p` itself and stops short of it (towards `p` from the
    /// offset origin, not along the direction from `h`, which would meet `p`'s plane early
    /// where the two surfaces face each other).
    fn visible(&self, h: &Hit, p: Vec3A) -> bool {
        let origin = self.origin(h);
        let d = p - origin;
        let dist = d.length();
        let tmax = dist - self.eps;
        tmax <= 0.0 || !self.world.occluded(origin, d / dist, self.eps, tmax)
    }

    /// What a surface `y` that a BRDF-sampled ray (direction `l`, density `pdf`) met emits
    /// towards it, weighed against next-event estimation. Nothing where the ray passed the
    /// back of a single-sided surface first: light is shadowed by every surface.
    pub(crate) fn emission_found(&self, y: &Hit, l: Vec3A, pdf: f32) -> Vec3A {
        if y.emissive.max_element() <= 0.0 || y.shadowed {
            return Vec3A::ZERO;
        }
        if !self.emits() {
            return y.emissive;
        }
        y.emissive * power_heuristic(pdf, self.emitters.pdf(self.world, y.triangle, l, y.t))
    }

    /// The light arriving directly from every light and emitter, reflected at `h` towards
    /// `v` (emitters by next-event estimation alone).
    pub fn direct_light(&self, h: &Hit, v: Vec3A, rng: &mut Rng) -> Vec3A {
        let b = self.brdf.at(h);
        self.lights(h, &b, v, 0) + self.emitted_light(h, &b, v, rng, false)
    }

    /// `direct`: emission plus the lights' light with hard shadows, plus the emitters' by
    /// both strategies (a point drawn on one, and a direction drawn from the BRDF; the
    /// latter alone when emitters are not sampled).
    pub fn direct(&self, p: &Primary, v: Vec3A, rng: &mut Rng) -> Vec3A {
        let (h, b) = (&p.hit, p.lobes);
        let sum = h.emissive + self.primary_lights(p, v);
        if self.emitters.is_empty() {
            return sum;
        }
        let (u, choose) = (rng.pair(), rng.uniform());
        let (l, w, pdf) = b.sample(h, v, u, choose);
        let found = match w.max_element() > 0.0 {
            true => self.trace_from(h, l, f32::INFINITY, Faces::Seen),
            false => None,
        };
        let by_brdf = found.map_or(Vec3A::ZERO, |y| w * self.emission_found(&y, l, pdf));
        sum + self.emitted_light(h, &b, v, rng, true) + by_brdf
    }

    /// `ao`: 1 minus the cosine-weighted share of directions that meet a surface within the
    /// radius, each weighed 1/(1 + d²) with the falloff (as `occluder_weight()` does).
    pub fn ao(&self, h: &Hit, rng: &mut Rng) -> f32 {
        let d = cosine_hemisphere(h.n, rng.pair());
        if h.ng.dot(d) <= 0.0 {
            return 0.0;
        }
        match self.trace_from(h, d, self.ao_radius, Faces::Both) {
            Some(hit) if self.ao_falloff => 1.0 - 1.0 / (1.0 + hit.t * hit.t),
            Some(_) => 0.0,
            None => 1.0,
        }
    }

    /// `indirect_diffuse`: one bounce of the lights' light off the surfaces around, as a
    /// white Lambertian receiver reflects it: (1/π) ∫ L_direct(y → x) cos θ dω. Raster
    /// indirect diffuse (`gi.indirect`) holds this before the albedo is applied.
    pub fn indirect_diffuse(&self, h: &Hit, rng: &mut Rng) -> Vec3A {
        let d = cosine_hemisphere(h.n, rng.pair());
        if h.ng.dot(d) <= 0.0 {
            return Vec3A::ZERO;
        }
        match self.trace_from(h, d, f32::INFINITY, Faces::Seen) {
            Some(y) => self.direct_light(&y, -d, rng),
            None => Vec3A::ZERO,
        }
    }

    /// `indirect_specular`: the light seen in the reflection — emitted and directly lit
    /// surfaces along directions drawn from the specular lobe about the mirror direction
    /// (a mirror at low roughness), averaged; before the surface's reflectance is applied,
    /// as raster SSR (`ssr.color`) holds it.
    pub fn indirect_specular(&self, h: &Hit, v: Vec3A, rng: &mut Rng) -> Vec3A {
        let half = power_lobe(h.n, shininess(h.roughness).max(1.0), rng.pair());
        let l = (2.0 * v.dot(half) * half - v).normalize_or_zero();
        if h.ng.dot(l) <= 0.0 || h.n.dot(l) <= 0.0 {
            return Vec3A::ZERO;
        }
        match self.trace_from(h, l, f32::INFINITY, Faces::Seen) {
            Some(y) => y.emissive + self.direct_light(&y, -l, rng),
            None => Vec3A::ZERO,
        }
    }

    /// `full`: all light leaving the surface towards `v`, every bounce (path tracing with
    /// the lights and emitters sampled at every vertex, emitters also found by the BRDF's
    /// directions and the two weighed by MIS; Russian roulette after a few bounces).
    pub fn full(&self, p: &Primary, v: Vec3A, rng: &mut Rng) -> Vec3A {
        let (mut h, mut v, mut b, mut lit) = (p.hit, v, p.lobes, self.primary_lights(p, v));
        let mut sum = h.emissive;
        let mut throughput = Vec3A::ONE;
        for bounce in 1..=MAX_BOUNCES {
            sum += throughput * (lit + self.emitted_light(&h, &b, v, rng, true));
            let (u, choose) = (rng.pair(), rng.uniform());
            let (l, w, pdf) = b.sample(&h, v, u, choose);
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
            let Some(y) = self.trace_from(&h, l, f32::INFINITY, Faces::Seen) else {
                break;
            };
            sum += throughput * self.emission_found(&y, l, pdf);
            (h, v) = (y, -l);
            b = self.brdf.at(&h);
            lit = self.lights(&h, &b, v, 0);
        }
        sum
    }
}
