//! Stage `sample` of the reference renderer: random numbers that depend only on (seed,
//! pixel, sample, term) — never on threads or scheduling, so a seed gives bit-identical
//! images — and the direction distributions the estimators draw from.

use glam::Vec3A;
use std::f32::consts::PI;

/// SplitMix64: a counter-based stream, one per (seed, pixel, sample, term).
pub struct Rng(u64);

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl Rng {
    pub fn new(seed: u64, pixel: u64, sample: u64, stream: u64) -> Rng {
        let mut s = mix(seed ^ 0x9e37_79b9_7f4a_7c15);
        for k in [pixel, sample, stream] {
            s = mix(s ^ k.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        }
        Rng(s)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        (mix(self.0) >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    pub fn pair(&mut self) -> (f32, f32) {
        (self.uniform(), self.uniform())
    }
}

/// The coin that keeps blended surfaces where they are, as solid as opaque ones (their outline
/// is an edge, which `edge_pixels` looks for; their stochastic transparency is not).
pub const SOLID_BLEND: u32 = u32::MAX;

/// The coin of a pixel's sample (for blended surfaces its camera ray meets; `World::trace_with_coin`):
/// a stream of its own, so the terms' numbers stay as they are.
pub fn coin(seed: u64, pixel: u64, sample: u64) -> u32 {
    // Never `SOLID_BLEND`, which keeps blended surfaces solid.
    ((Rng::new(seed, pixel, sample, u64::MAX).0 >> 32) as u32).min(SOLID_BLEND - 1)
}

/// A number in [0, 1) from a few floats (stochastic transparency's coin).
pub fn unit_hash(values: &[f32]) -> f32 {
    let h = values.iter().fold(0x51_7cc1_b727_220au64, |h, v| mix(h ^ v.to_bits() as u64));
    (h >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

/// Two unit vectors completing `n` to an orthonormal frame (Duff et al. 2017, branchless).
pub fn frame(n: Vec3A) -> (Vec3A, Vec3A) {
    let s = 1f32.copysign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (
        Vec3A::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        Vec3A::new(b, s + n.y * n.y * a, -n.y),
    )
}

/// Cosine-weighted direction about `n` (Malley: a uniform disc point lifted to the
/// hemisphere); its density is cos θ / π.
pub fn cosine_hemisphere(n: Vec3A, (u1, u2): (f32, f32)) -> Vec3A {
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    let (t, b) = frame(n);
    unit(t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u1).max(0.0).sqrt())
}

/// A half vector about `n` with density (e + 1) / 2π · cos^e θ (a Phong-power lobe;
/// `Brdf::eval_pdf` states the density of the direction it reflects to).
pub fn power_lobe(n: Vec3A, e: f32, (u1, u2): (f32, f32)) -> Vec3A {
    let cos_t = u1.powf(1.0 / (e + 1.0));
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    let (t, b) = frame(n);
    unit(t * (sin_t * phi.cos()) + b * (sin_t * phi.sin()) + n * cos_t)
}

/// `v` at unit length, as a multiple of its reciprocal length (`Vec3A::normalize` divides,
/// which rounds otherwise: a seed's images stay what they were with `Vec3`).
fn unit(v: Vec3A) -> Vec3A {
    v * v.length_recip()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_deterministic_and_uniform() {
        let (mut a, mut b) = (Rng::new(7, 3, 1, 0), Rng::new(7, 3, 1, 0));
        let xs: Vec<f32> = (0..10_000).map(|_| a.uniform()).collect();
        assert!(xs.iter().all(|&x| x == b.uniform() && (0.0..1.0).contains(&x)));
        let mean = xs.iter().sum::<f32>() / xs.len() as f32;
        assert!((mean - 0.5).abs() < 0.01, "{mean}");
        assert_ne!(Rng::new(7, 3, 1, 0).uniform(), Rng::new(7, 3, 2, 0).uniform());
    }

    /// Cosine sampling: E[cos θ] = 2/3 and every direction above the surface.
    #[test]
    fn cosine_hemisphere_has_the_cosine_density() {
        let n = Vec3A::new(0.3, -0.8, 0.5).normalize();
        let mut rng = Rng::new(1, 0, 0, 0);
        let cos: Vec<f32> = (0..50_000).map(|_| cosine_hemisphere(n, rng.pair()).dot(n)).collect();
        assert!(cos.iter().all(|&c| c >= -1e-6));
        let mean = cos.iter().sum::<f32>() / cos.len() as f32;
        assert!((mean - 2.0 / 3.0).abs() < 0.01, "{mean}");
        let (t, b) = frame(n);
        assert!(t.dot(n).abs() < 1e-6 && b.dot(n).abs() < 1e-6 && t.dot(b).abs() < 1e-6);
    }
}
