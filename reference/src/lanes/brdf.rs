//! Stage `integrate` in lanes, its BRDF draw: `Lobes::sample` for a lane group's 8 paths at
//! once, each lane the scalar draw's arithmetic written branch-free (both lobes' directions
//! worked out, one kept), with `math`'s `pow` and sine and cosine in place of libm's, so that
//! the loop over the lanes compiles to SIMD instructions — 8 lanes at once with AVX2 where the
//! processor has it (detected when the program runs), 4 with the SSE2 every x86-64 has.

use super::math::{pow, sincos_turns};
use super::simd::{simd_dispatch, F8, M8, V8};
use crate::shading::Lobes;
use crate::world::Hit;
use glam::Vec3A;
use std::f32::consts::PI;

/// The lanes' vertices (structure of arrays): where each path is — position, shading and
/// geometric normal, towards the viewer — its BRDF's constants, and the numbers of its draw.
/// What the draw reads, and what the lights are evaluated at (`lights`).
#[derive(Default)]
pub struct Vertices {
    pub(super) p: V8,
    pub(super) n: V8,
    ng: V8,
    pub(super) v: V8,
    pub(super) diffuse: V8,
    pub(super) specular: V8,
    pub(super) exponent: F8,
    density: F8,
    share: F8,
    u1: F8,
    u2: F8,
    choose: F8,
}

/// What it gives, lane by lane: direction, weight (BRDF × cos / pdf, 0 below the surface) and
/// density, as `Lobes::sample` returns them.
#[derive(Default)]
pub struct Drawn {
    l: V8,
    w: V8,
    pdf: F8,
}

impl Vertices {
    /// Lane `i`: the path at `h` (BRDF `b`) seen from `v`.
    pub fn set(&mut self, i: usize, h: &Hit, b: &Lobes, v: Vec3A) {
        self.p.set(i, h.position);
        self.n.set(i, h.n);
        self.ng.set(i, h.ng);
        self.v.set(i, v);
        self.diffuse.set(i, b.diffuse);
        self.specular.set(i, b.specular);
        (self.exponent.0[i], self.density.0[i], self.share.0[i]) = (b.exponent, b.density, b.specular_share);
    }

    /// Lane `i`'s random numbers for its draw.
    pub fn set_numbers(&mut self, i: usize, (u1, u2): (f32, f32), choose: f32) {
        (self.u1.0[i], self.u2.0[i], self.choose.0[i]) = (u1, u2, choose);
    }
}

impl Drawn {
    /// Lane `i`'s (direction, weight, density).
    pub fn at(&self, i: usize) -> (Vec3A, Vec3A, f32) {
        (self.l.at(i), self.w.at(i), self.pdf.0[i])
    }
}

simd_dispatch! {
    /// Every lane's draw (lanes holding no path draw from whatever they hold: their results are
    /// not read).
    pub fn sample(d: &Vertices) -> Drawn = sample_lanes
}

simd_dispatch! {
    /// `Lobes::eval_pdf` towards `l` in every lane of `d` (the points drawn on emitters):
    /// BRDF × cos and the BRDF draw's density.
    pub fn eval_pdf_towards(d: &Vertices, l: &V8) -> (V8, F8) = eval_pdf_at
}

#[inline(always)]
fn eval_pdf_at(d: &Vertices, l: &V8) -> (V8, F8) {
    eval_pdf(d, *l)
}

#[inline(always)]
fn sample_lanes(d: &Vertices) -> Drawn {
    let specular = d.choose.lt(d.share);
    let l = direction(d, specular);
    let (f, pdf) = eval_pdf(d, l);
    let zero = F8::splat(0.0);
    let keep = d.ng.dot(l).gt(zero) & pdf.gt(zero);
    let w = V8::select(keep, f.scale(F8::splat(1.0) / pdf), V8::default());
    Drawn { l, w, pdf }
}

/// The direction `Lobes::sample` draws: a half vector from the power lobe reflected about
/// (`specular` lanes), or a cosine-weighted direction — `sample::power_lobe` and
/// `sample::cosine_hemisphere` in one, about the frame of `sample::frame`.
#[inline(always)]
fn direction(d: &Vertices, specular: M8) -> V8 {
    let (one, zero) = (F8::splat(1.0), F8::splat(0.0));
    let (n, u1) = (d.n, d.u1);
    let lobe_cos = pow(u1, one / (d.exponent + one));
    let cos_t = specular.select(lobe_cos, (one - u1).max(zero).sqrt());
    let sin_t = specular.select((one - lobe_cos * lobe_cos).max(zero).sqrt(), u1.sqrt());
    let (sin_p, cos_p) = sincos_turns(d.u2);
    let s = n.z.signum_bits();
    let a = -(one / (s + n.z));
    let b = n.x * n.y * a;
    let t = V8 {
        x: one + s * n.x * n.x * a,
        y: s * b,
        z: -(s * n.x),
    };
    let bt = V8 {
        x: b,
        y: s + n.y * n.y * a,
        z: -n.y,
    };
    let dir = t.scale(sin_t * cos_p).plus(bt.scale(sin_t * sin_p)).plus(n.scale(cos_t));
    let dir = dir.scale(one / dir.dot(dir).sqrt());
    let reflected = dir.scale(F8::splat(2.0) * d.v.dot(dir)).plus(d.v.scale(-one));
    V8::select(specular, reflected.normalize_or(V8::default()), dir)
}

/// `Lobes::eval_pdf`: BRDF × cos for light from `l`, and the draw's density.
#[inline(always)]
fn eval_pdf(d: &Vertices, l: V8) -> (V8, F8) {
    let zero = F8::splat(0.0);
    let (n, v) = (d.n, d.v);
    let (f, lobe, half) = eval(n, v, l, (d.diffuse, d.specular, d.exponent));
    let cos = n.dot(l).max(zero) / F8::splat(PI);
    let spec = d.density * lobe / (F8::splat(4.0) * v.dot(half).abs().max(F8::splat(1e-6)));
    let mixed = (F8::splat(1.0) - d.share) * cos + d.share * spec;
    (f, d.share.eq(zero).select(cos, mixed))
}

/// `Lobes::eval`: BRDF × cos for light from `l` seen from `v` at a surface of normal `n`
/// (0 unless both lie above it), with the specular lobe's value and the half vector.
#[inline(always)]
pub fn eval(n: V8, v: V8, l: V8, (diffuse, specular, exponent): (V8, V8, F8)) -> (V8, F8, V8) {
    let zero = F8::splat(0.0);
    let ndl = n.dot(l);
    let half = l.plus(v).normalize_or(n);
    let lobe = pow(n.dot(half).max(zero), exponent);
    let reflects = ndl.gt(zero) & n.dot(v).gt(zero);
    let f = V8::select(reflects, diffuse.plus(specular.scale(lobe)).scale(ndl), V8::default());
    (f, lobe, half)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kernels compiled for AVX2 (what `sample` and `eval_pdf_towards` run on this
    /// processor, if it has AVX2) and for the target's baseline (SSE2: what a processor
    /// without it runs) give the same bits: the same operations in the same order, no fused
    /// multiply-add, so a machine's instruction set does not change an image.
    #[test]
    fn the_avx2_and_baseline_kernels_agree_bit_for_bit() {
        let mut rng = crate::sample::Rng::new(3, 1, 4, 1);
        let mut u = || rng.uniform();
        for _ in 0..200 {
            let mut d = Vertices::default();
            let mut towards = V8::default();
            for i in 0..super::super::LANES {
                let n = Vec3A::new(u() - 0.5, u() - 0.5, u() - 0.5).normalize();
                let v = (n + Vec3A::new(u() - 0.5, u() - 0.5, u() - 0.5)).normalize();
                towards.set(i, (n + Vec3A::new(u() - 0.5, u() - 0.5, u() - 0.5)).normalize());
                (d.exponent.0[i], d.density.0[i], d.share.0[i]) = (1.0 + 2000.0 * u() * u(), 1.0 + 300.0 * u(), u());
                d.n.set(i, n);
                d.ng.set(i, n);
                d.v.set(i, v);
                d.diffuse.set(i, Vec3A::splat(u() / 3.2));
                d.specular.set(i, Vec3A::splat(u()));
                (d.u1.0[i], d.u2.0[i], d.choose.0[i]) = (u(), u(), u());
            }
            let (a, b) = (sample(&d), sample_lanes(&d));
            let bits = |v: &V8| [v.x, v.y, v.z].map(|f| f.0.map(f32::to_bits));
            assert_eq!(
                (bits(&a.l), bits(&a.w), a.pdf.0.map(f32::to_bits)),
                (bits(&b.l), bits(&b.w), b.pdf.0.map(f32::to_bits))
            );
            let ((f, pdf), (g, qdf)) = (eval_pdf_towards(&d, &towards), eval_pdf_at(&d, &towards));
            assert_eq!((bits(&f), pdf.0.map(f32::to_bits)), (bits(&g), qdf.0.map(f32::to_bits)));
        }
    }
}
