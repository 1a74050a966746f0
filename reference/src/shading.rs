//! Stage `shading` of the reference renderer: lights and the BRDF, defined exactly as the
//! raster shaders define them in `shaders/lib/lighting.wgsl` (the one documented definition:
//! windowed attenuation, spot cone, normalised Blinn-Phong), so that the only difference
//! between a raster image and the reference is the algorithm. Change one, change both:
//! `tests/reference/reference.rs` renders the Cornell box both ways and compares.

use super::world::Hit;
use glam::Vec3A;
use lightbench_compiler::ir::LightKind;
use lightbench_scene::Light;
use std::f32::consts::PI;

/// `ATTENUATION_SOFTNESS` of `lib/lighting.wgsl`.
pub const ATTENUATION_SOFTNESS: f32 = 6.0;

/// `attenuation()`: (1 - (d/r)^20) / ((r/6)^2 + d^2), 0 from the range on.
pub fn attenuation(d: f32, range: f32) -> f32 {
    let r = range.max(1e-30);
    let x = (d / r).clamp(0.0, 1.0);
    let soft = r / ATTENUATION_SOFTNESS;
    (1.0 - x.powi(20)) / (soft * soft + d * d)
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// A light as the shaders see it: `color × intensity`, unit direction, cone cosines.
#[derive(Clone, Debug)]
pub struct PunctualLight {
    pub kind: LightKind,
    pub radiance: Vec3A,
    pub position: Vec3A,
    pub direction: Vec3A,
    pub range: f32,
    pub cos_inner: f32,
    pub cos_outer: f32,
}

impl PunctualLight {
    /// The light at time 0 (as `Light::block` fills the shaders' light array).
    pub fn new(l: &Light) -> PunctualLight {
        let l = l.at(0.0);
        PunctualLight {
            kind: l.kind,
            radiance: (l.color * l.intensity).into(),
            position: l.position.into(),
            direction: Vec3A::from(l.direction).try_normalize().unwrap_or(Vec3A::NEG_Y),
            range: l.range,
            cos_inner: l.inner_angle.to_radians().cos(),
            cos_outer: l.outer_angle.to_radians().cos(),
        }
    }

    /// `light_at()`: light arriving at `p` before shadowing, the unit vector towards the
    /// light, and its distance (infinite for directional lights).
    pub fn at(&self, p: Vec3A) -> (Vec3A, Vec3A, f32) {
        if self.kind == LightKind::Directional {
            return (self.radiance, -self.direction, f32::INFINITY);
        }
        let d = self.position - p;
        let dist = d.length();
        let to_light = d / dist.max(1e-6);
        let mut radiance = self.radiance * attenuation(dist, self.range);
        if self.kind == LightKind::Spot {
            // `spot_factor()`, with the same guard for a point at the light itself.
            let c = (-d).try_normalize().unwrap_or(self.direction).dot(self.direction);
            radiance *= smoothstep(self.cos_outer, self.cos_inner.max(self.cos_outer + 1e-4), c);
        }
        (radiance, to_light, dist)
    }
}

/// Which reflectance model surfaces have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Brdf {
    /// The shaders' normalised Blinn-Phong (`blinn_phong()`): what every comparison uses.
    BlinnPhong,
    /// Diffuse only, albedo × (1 - metallic) / π: for transport checks with an analytic
    /// answer (the white furnace), where a specular lobe's energy would not be constant.
    Lambert,
}

/// Phong exponent of a roughness (`blinn_phong()`).
pub fn shininess(roughness: f32) -> f32 {
    2.0 / (roughness.powi(4)).max(1e-4) - 2.0
}

impl Brdf {
    /// Diffuse reflectance and specular colour of a surface.
    pub fn colours(self, h: &Hit) -> (Vec3A, Vec3A) {
        let diffuse = h.albedo * (1.0 - h.metallic);
        match self {
            Brdf::BlinnPhong => (diffuse, Vec3A::splat(0.04).lerp(h.albedo, h.metallic)),
            Brdf::Lambert => (diffuse, Vec3A::ZERO),
        }
    }

    /// The BRDF at `h`, its constants worked out once for every evaluation at this vertex.
    pub fn at(self, h: &Hit) -> Lobes {
        let (diffuse, spec_color) = self.colours(h);
        let (d, sp) = (diffuse.max_element(), spec_color.max_element());
        let s = shininess(h.roughness);
        let e = s.max(1.0);
        Lobes {
            diffuse: diffuse / PI,
            specular: spec_color * ((s + 8.0) / 25.132741),
            exponent: e,
            density: (e + 1.0) / (2.0 * PI),
            // The specular lobe is drawn in proportion to its share of the reflectance.
            specular_share: if d + sp <= 0.0 { 0.0 } else { sp / (d + sp) },
        }
    }

    /// BRDF × cos θ_l for light arriving from `l` seen from `v` (`blinn_phong()`).
    pub fn eval(self, h: &Hit, l: Vec3A, v: Vec3A) -> Vec3A {
        self.at(h).eval(h, l, v)
    }

    /// Density of `Lobes::sample` drawing `l`.
    pub fn pdf(self, h: &Hit, l: Vec3A, v: Vec3A) -> f32 {
        self.at(h).eval_pdf(h, l, v).1
    }
}

/// A surface's BRDF at one vertex: diffuse/π, the specular colour × (s + 8)/8π, the lobe's
/// exponent and density constant, and the probability of sampling the specular lobe.
#[derive(Clone, Copy, Debug)]
pub struct Lobes {
    pub(crate) diffuse: Vec3A,
    pub(crate) specular: Vec3A,
    pub(crate) exponent: f32,
    pub(crate) density: f32,
    pub(crate) specular_share: f32,
}

/// Whether a surface reflects light from `l` towards `v` at all: both must lie above the
/// shading normal's hemisphere. The second half is the convention of the independent renderer
/// the reference is checked against (Mitsuba 3's BSDFs are zero for a cos θ ≤ 0 on either side,
/// in the shading frame): at a smooth-normal surface seen at a grazing angle the interpolated
/// normal can turn away from the viewer while the face does not, and without it such a point
/// still reflected the light it gets — 1.05% of a smooth sphere's and its floor's indirect light
/// (docs/reference.md, tested). `lib/lobes.wgsl` applies the same rule.
fn reflects(h: &Hit, l: Vec3A, v: Vec3A) -> bool {
    h.n.dot(l) > 0.0 && h.n.dot(v) > 0.0
}

impl Lobes {
    /// BRDF × cos θ_l for light arriving from `l` seen from `v`.
    pub fn eval(&self, h: &Hit, l: Vec3A, v: Vec3A) -> Vec3A {
        if !reflects(h, l, v) {
            return Vec3A::ZERO;
        }
        let ndl = h.n.dot(l);
        let half = (l + v).try_normalize().unwrap_or(h.n);
        let lobe = h.n.dot(half).max(0.0).powf(self.exponent);
        (self.diffuse + self.specular * lobe) * ndl
    }

    /// `eval` and the density of `sample` drawing `l` (the one-sample mixture of the cosine
    /// and specular lobes), sharing the lobe's power of n · h.
    pub fn eval_pdf(&self, h: &Hit, l: Vec3A, v: Vec3A) -> (Vec3A, f32) {
        let ndl = h.n.dot(l).max(0.0);
        let cos = ndl / PI;
        let ps = self.specular_share;
        if ps == 0.0 && ndl <= 0.0 {
            return (Vec3A::ZERO, cos);
        }
        let half = (l + v).try_normalize().unwrap_or(h.n);
        let lobe = h.n.dot(half).max(0.0).powf(self.exponent);
        let f = if !reflects(h, l, v) {
            Vec3A::ZERO
        } else {
            (self.diffuse + self.specular * lobe) * ndl
        };
        if ps == 0.0 {
            return (f, cos);
        }
        let spec = self.density * lobe / (4.0 * v.dot(half).abs().max(1e-6));
        (f, (1.0 - ps) * cos + ps * spec)
    }

    /// A direction to continue a path in, from the lobes in proportion to their reflectance,
    /// its weight BRDF × cos / pdf (zero when it points below the surface) and its density.
    pub fn sample(&self, h: &Hit, v: Vec3A, u: (f32, f32), choose: f32) -> (Vec3A, Vec3A, f32) {
        let l = if choose < self.specular_share {
            let half = super::sample::power_lobe(h.n, self.exponent, u);
            (2.0 * v.dot(half) * half - v).normalize_or_zero()
        } else {
            super::sample::cosine_hemisphere(h.n, u)
        };
        let (f, pdf) = self.eval_pdf(h, l, v);
        if h.ng.dot(l) <= 0.0 || pdf <= 0.0 {
            return (l, Vec3A::ZERO, pdf);
        }
        (l, f / pdf, pdf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shaders' definitions as this module restates them: a change to one of these lines
    /// of `shaders/lib/lighting.wgsl` must come with the same change here (and the Cornell
    /// comparison in `tests/reference/reference.rs` checks the whole of it).
    #[test]
    fn the_shader_definitions_are_the_ones_restated_here() {
        let wgsl = include_str!("../../shaders/lib/lighting.wgsl");
        for line in [
            format!("const ATTENUATION_SOFTNESS: f32 = {ATTENUATION_SOFTNESS:?};"),
            "return (1.0 - x20) / (soft * soft + d * d);".into(),
            "return smoothstep(l.cone.y, max(l.cone.x, l.cone.y + 1e-4), c);".into(),
            "let shininess = 2.0 / max(roughness * roughness * roughness * roughness, 1e-4) - 2.0;".into(),
            "let spec_color = mix(vec3<f32>(0.04), albedo, metallic);".into(),
            "let spec = pow(max(dot(n, h), 0.0), max(shininess, 1.0)) * (shininess + 8.0) / 25.132741;".into(),
            "return (diffuse / 3.14159265 + spec_color * spec) * ndl;".into(),
        ] {
            assert!(wgsl.contains(&line), "lib/lighting.wgsl no longer has `{line}`");
        }
        // Windowed: full strength near, 0 at the range; the range of 6 is the seed's 1/(1 + d²).
        assert!((attenuation(1.0, 6.0) - (1.0 - (1.0f32 / 6.0).powi(20)) / 2.0).abs() < 1e-6);
        assert_eq!(attenuation(6.0, 6.0), 0.0);
    }
}
