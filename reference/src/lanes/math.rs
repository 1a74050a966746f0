//! Stage `integrate` in lanes, its arithmetic: `powf` and the sine and cosine of a turn as
//! branch-free f32 code over 8 lanes (`simd::F8`), so that they compile to SIMD instructions
//! (libm's are calls, one value at a time). Close to libm over the ranges the BRDF draws from
//! (tested below), not bit-identical to it: images from the lanes
//! agree with the scalar integrator's within noise, which `tests/reference` checks by z-scores.

use super::simd::{F8, I8, M8};
use std::f32::consts::{LN_2, SQRT_2, TAU};

/// Adding this to |x| < 2²² rounds x to an integer held in its low mantissa bits.
const ROUND: f32 = 12_582_912.0; // 1.5 × 2²³

/// x rounded to the nearest integer (ties to even), and that integer as bits of an `i32`.
#[inline(always)]
fn round(x: F8) -> (F8, I8) {
    let r = x + F8::splat(ROUND);
    let mut n = r.to_bits().as_i8();
    for v in &mut n.0 {
        *v -= ROUND.to_bits() as i32;
    }
    (r - F8::splat(ROUND), n)
}

/// log₂ x for a positive, normal x: its exponent, plus log₂ of its mantissa (taken in
/// [√½, √2)) as 2/ln 2 · atanh((m − 1)/(m + 1)) by atanh's series (|s| ≤ 0.172: five terms
/// leave 3e-10).
#[inline(always)]
fn log2(x: F8) -> F8 {
    let bits = x.to_bits();
    let m = F8::from_bits((bits & M8::splat(0x007f_ffff)) | M8::splat(0x3f80_0000));
    let big = m.gt(F8::splat(SQRT_2));
    let m = big.select(m * F8::splat(0.5), m);
    let e = (bits.shifted_right(23) & M8::splat(0xff)).as_i8() + I8::splat(-127);
    let e = e.to_f8() + big.select(F8::splat(1.0), F8::splat(0.0));
    let one = F8::splat(1.0);
    let s = (m - one) / (m + one);
    let s2 = s * s;
    let c = |k: f32| F8::splat(1.0 / k);
    let atanh = s * (one + s2 * (c(3.0) + s2 * (c(5.0) + s2 * (c(7.0) + s2 * c(9.0)))));
    e + atanh * F8::splat(2.0 / LN_2)
}

/// 2^y: 2 to the nearest integer n (by its exponent bits) times 2^(y − n) by the Taylor
/// series of e^(f ln 2) on |f| ≤ ½ (to f⁷: 1.2e-7 relative). 0 below 2⁻¹²⁶.
#[inline(always)]
fn exp2(y: F8) -> F8 {
    let y = y.max(F8::splat(-127.0)).min(F8::splat(127.0));
    let (n, bits) = round(y);
    let f = (y - n) * F8::splat(LN_2);
    let c = |k: f32| F8::splat(1.0 / k);
    let p = F8::splat(1.0)
        + f * (F8::splat(1.0) + f * (c(2.0) + f * (c(6.0) + f * (c(24.0) + f * (c(120.0) + f * (c(720.0) + f * c(5040.0)))))));
    p * F8::from_bits((bits + I8::splat(127)).shifted_left(23))
}

/// x^e for x ≥ 0 and e > 0 (what the BRDF raises: n · h and a uniform number): 0 for x = 0
/// and for subnormal x, whose powers here are below f32's range anyway.
#[inline(always)]
pub fn pow(x: F8, e: F8) -> F8 {
    let normal = x.ge(F8::splat(f32::MIN_POSITIVE));
    let r = exp2(e * log2(normal.select(x, F8::splat(1.0))));
    normal.select(r, F8::splat(0.0))
}

/// Sine and cosine of `t` turns (2πt radians): t reduced to the nearest quarter turn k/4, the
/// rest (at most an eighth of a turn) by Taylor's series to the 9th and 10th powers (2e-9),
/// then turned by k quarters.
#[inline(always)]
pub fn sincos_turns(t: F8) -> (F8, F8) {
    let a = t - round(t).0;
    let (q, k) = round(a * F8::splat(4.0));
    let x = (a - q * F8::splat(0.25)) * F8::splat(TAU);
    let x2 = x * x;
    let one = F8::splat(1.0);
    let d = |k: f32| x2 * F8::splat(1.0 / k);
    let s = x * (one - d(6.0) * (one - d(20.0) * (one - d(42.0) * (one - d(72.0)))));
    let c = one - d(2.0) * (one - d(12.0) * (one - d(30.0) * (one - d(56.0) * (one - d(90.0)))));
    // Turned by k quarters: odd k swaps sine and cosine; k = 1, 2 negate the sine, 2, 3 the cosine.
    let lane = |bit: i32| {
        let mut m = M8::default();
        for i in 0..super::simd::LANES {
            m.0[i] = if k.0[i] & bit != 0 { !0 } else { 0 };
        }
        m
    };
    let (odd, half) = (lane(1), lane(2));
    let (sin, cos) = (odd.select(c, s), odd.select(s, c));
    let flip_sin = M8::splat(0x8000_0000) & half;
    let flip_cos = M8::splat(0x8000_0000) & (half ^ odd);
    (F8::from_bits(sin.to_bits() ^ flip_sin), F8::from_bits(cos.to_bits() ^ flip_cos))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `f` of 8 values at once, lane by lane.
    fn lanes(xs: &[f32], f: impl Fn(F8) -> F8) -> Vec<f32> {
        xs.chunks(8)
            .flat_map(|c| {
                let mut x = F8::splat(c[0]);
                x.0[..c.len()].copy_from_slice(c);
                f(x).0[..c.len()].to_vec()
            })
            .collect()
    }

    /// Relative difference, with an absolute floor for values near 0.
    fn close(a: f32, b: f32, rel: f32, floor: f32) -> bool {
        (a - b).abs() <= rel * b.abs().max(floor)
    }

    /// Over the exponents the BRDF uses (1 to 19 998, and their reciprocals plus one's
    /// reciprocal for the lobe's draw) and bases from 1e-9 to 1: within 1.5e-7 × (1 + |y|)
    /// relative, y = e log₂ x (rounding y to f32 alone costs up to 4e-8 × |y|; libm works
    /// in double precision).
    #[test]
    fn pow_agrees_with_libm() {
        let xs: Vec<f32> = (0..4000)
            .map(|i| (i as f32 / 4000.0).powi(3).max(1e-9) + 1e-9 * (i % 7) as f32)
            .collect();
        for e in [
            1.0f32,
            1.5,
            2.0,
            6.33,
            31.0,
            200.0,
            1999.0,
            19998.0,
            0.5,
            0.1,
            1.0 / 7.33,
            1.0 / 19999.0,
        ] {
            for (&x, got) in xs.iter().zip(lanes(&xs, |x| pow(x, F8::splat(e)))) {
                let want = x.powf(e);
                let y = (e as f64 * (x as f64).log2()).abs() as f32;
                // Results below 1e-30 only need to be tiny (they weigh nothing).
                assert!(close(got, want, 1.5e-7 * (1.0 + y), 1e-30), "pow({x}, {e}) = {got}, libm {want}");
            }
        }
        let edge = lanes(&[0.0, 1.0, 1e-40], |x| pow(x, F8([3.0, 19998.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0])));
        assert_eq!(edge, [0.0, 1.0, 0.0]);
    }

    #[test]
    fn sine_and_cosine_of_turns_agree_with_libm() {
        let ts: Vec<f32> = (0..=100_000).map(|i| i as f32 / 100_000.0).collect();
        let sines = lanes(&ts, |t| sincos_turns(t).0);
        let cosines = lanes(&ts, |t| sincos_turns(t).1);
        for ((&t, s), c) in ts.iter().zip(sines).zip(cosines) {
            let (ws, wc) = ((t as f64) * std::f64::consts::TAU).sin_cos();
            assert!(
                (s as f64 - ws).abs() < 3e-7 && (c as f64 - wc).abs() < 3e-7,
                "{t}: ({s}, {c}) against ({ws}, {wc})"
            );
        }
    }
}
