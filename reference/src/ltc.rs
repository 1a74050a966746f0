//! LTC fit: linearly transformed cosines (Heitz et al. 2016) fitted to the specular lobe of the
//! project's normalised Blinn-Phong (`blinn_phong()` in `shaders/lib/lighting.wgsl`, `Brdf` here),
//! so that a raster pass can integrate that lobe over a polygon light in closed form. The
//! diffuse lobe is a clamped cosine already (the identity transform): only the specular one is
//! fitted.
//!
//! A table cell holds, for a roughness and a view angle (view in the x-z plane, normal +z):
//! the inverse transform M⁻¹ with its four free entries (`[a, 0, b; 0, c, 0; d, 0, 1]`, scaled
//! so its last entry is 1: a transform's scale does not change the distribution), and the
//! magnitude that makes the lobe integrate, over the upper hemisphere, to the specular albedo
//! (for a specular colour of 1; the shader multiplies by its own). `examples/ltc_fit.rs` writes
//! the table for the pipelines; this module is what it runs and what the tests check.

use glam::{Mat3, Vec3};
use std::f32::consts::PI;

/// Cells per side: roughness down the rows, view angle across.
pub const SIZE: usize = 32;
/// Floats per cell: M⁻¹'s `a, b, c, d`, then the magnitude, the fit's error and two zeros.
pub const STRIDE: usize = 8;
/// Below this roughness the BRDF's exponent is clamped (roughness⁴ ≥ 1e-4): rougher only.
pub const MIN_ROUGHNESS: f32 = 0.1;

/// Samples per side of each stratified estimate (their square per estimate).
const STRATA: usize = 48;

/// Row `i`'s roughness: evenly from `MIN_ROUGHNESS` to 1.
pub fn roughness_at(i: usize) -> f32 {
    MIN_ROUGHNESS + (1.0 - MIN_ROUGHNESS) * i as f32 / (SIZE - 1) as f32
}

/// Column `j`'s cos θ_v: evenly in √(1 − cos θ_v) (finer towards grazing), kept above the
/// horizon.
pub fn cos_at(j: usize) -> f32 {
    let t = j as f32 / (SIZE - 1) as f32;
    (1.0 - t * t).max(0.02)
}

/// The view direction of column `j`, in the x-z plane.
pub fn view_at(j: usize) -> Vec3 {
    let c = cos_at(j);
    Vec3::new((1.0 - c * c).max(0.0).sqrt(), 0.0, c)
}

/// The specular lobe × cos θ_l for a specular colour of 1, as `blinn_phong()` computes it:
/// (s + 8)/8π · (n·h)^max(s, 1) · n·l.
pub fn lobe(v: Vec3, l: Vec3, s: f32) -> f32 {
    if l.z <= 0.0 {
        return 0.0;
    }
    let h = (v + l).normalize_or(Vec3::Z);
    (s + 8.0) / (8.0 * PI) * h.z.max(0.0).powf(s.max(1.0)) * l.z
}

/// The Phong exponent of a roughness (`shading::shininess`).
pub fn shininess(roughness: f32) -> f32 {
    crate::shading::shininess(roughness)
}

/// A direction drawn from the lobe's half-vector distribution, and its density.
fn sample_lobe(v: Vec3, s: f32, (u1, u2): (f32, f32)) -> (Vec3, f32) {
    let e = s.max(1.0);
    let cos_h = u1.powf(1.0 / (e + 1.0));
    let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    let h = Vec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
    let vh = v.dot(h);
    let l = 2.0 * vh * h - v;
    let pdf_h = (e + 1.0) / (2.0 * PI) * cos_h.powf(e);
    (l, if vh > 0.0 { pdf_h / (4.0 * vh) } else { 0.0 })
}

/// Density of `sample_lobe` drawing `l`.
fn lobe_pdf(v: Vec3, l: Vec3, s: f32) -> f32 {
    let h = (v + l).normalize_or(Vec3::Z);
    let (e, vh) = (s.max(1.0), v.dot(h));
    if h.z <= 0.0 || vh <= 0.0 {
        return 0.0;
    }
    (e + 1.0) / (2.0 * PI) * h.z.powf(e) / (4.0 * vh)
}

/// `n × n` stratified points in the unit square, each at its stratum's centre jittered by a
/// fixed hash (`seed`): the same points every run.
fn strata(n: usize, seed: u32) -> impl Iterator<Item = (f32, f32)> {
    (0..n * n).map(move |k| {
        let (x, y) = ((k % n) as f32, (k / n) as f32);
        let jitter = |m: u32| crate::sample::unit_hash(&[k as f32, seed as f32, m as f32]);
        ((x + jitter(0)) / n as f32, (y + jitter(1)) / n as f32)
    })
}

/// The specular albedo ∫ lobe dω at view `v`, estimated by sampling the lobe with `n²` points.
pub fn albedo(v: Vec3, s: f32, n: usize, seed: u32) -> f32 {
    let sum: f32 = strata(n, seed)
        .map(|u| {
            let (l, pdf) = sample_lobe(v, s, u);
            if pdf > 0.0 {
                lobe(v, l, s) / pdf
            } else {
                0.0
            }
        })
        .sum();
    sum / (n * n) as f32
}

/// A linearly transformed cosine: the clamped cosine D₀ carried by `m`.
#[derive(Clone, Copy, Debug)]
pub struct Ltc {
    pub m: Mat3,
    pub inv: Mat3,
}

impl Ltc {
    pub fn new(m: Mat3) -> Ltc {
        Ltc { m, inv: m.inverse() }
    }

    /// D(ω) = D₀(M⁻¹ω/|M⁻¹ω|) · |det M⁻¹| / |M⁻¹ω|³.
    pub fn eval(&self, w: Vec3) -> f32 {
        let o = self.inv * w;
        let len = o.length();
        let d0 = (o.z / len).max(0.0) / PI;
        d0 * self.inv.determinant().abs() / (len * len * len)
    }

    /// A direction drawn from D (a cosine-distributed one carried by M).
    pub fn sample(&self, u: (f32, f32)) -> Vec3 {
        (self.m * Vec3::from(crate::sample::cosine_hemisphere(glam::Vec3A::Z, u))).normalize()
    }

    /// The share of D above the horizon, estimated with `n²` samples drawn from it.
    pub fn upper_share(&self, n: usize, seed: u32) -> f32 {
        strata(n, seed).filter(|u| self.sample(*u).z > 0.0).count() as f32 / (n * n) as f32
    }

    /// M⁻¹'s four free entries, scaled so that its last entry is 1: `[a, b, c, d]` of
    /// `[a, 0, b; 0, c, 0; d, 0, 1]` (row-major).
    pub fn inverse_entries(&self) -> [f32; 4] {
        let i = self.inv.transpose(); // rows as columns: i.col(r) is row r
        let k = i.col(2).z;
        [i.col(0).x / k, i.col(0).z / k, i.col(1).y / k, i.col(2).x / k]
    }
}

/// The target the fit matches: the lobe normalised to integrate to 1.
struct Target {
    v: Vec3,
    s: f32,
    albedo: f32,
}

impl Target {
    fn f(&self, l: Vec3) -> f32 {
        lobe(self.v, l, self.s) / self.albedo
    }

    /// The lobe's mean direction, the frame the transform is fitted in.
    fn mean_direction(&self) -> Vec3 {
        let sum: Vec3 = strata(STRATA, 7)
            .map(|u| {
                let (l, pdf) = sample_lobe(self.v, self.s, u);
                if pdf > 0.0 {
                    l * (self.f(l) / pdf)
                } else {
                    Vec3::ZERO
                }
            })
            .sum();
        let d = Vec3::new(sum.x, 0.0, sum.z.max(1e-4)).normalize();
        if d.is_finite() {
            d
        } else {
            Vec3::Z
        }
    }

    /// ∫ |D − f| over the sphere, with samples drawn from both and combined by the balance
    /// heuristic: what the fit minimises (Heitz's fit weighs |D − f|³, which favours the peak;
    /// the L1 distance matched the path tracer's images slightly better here) and reports.
    fn error(&self, ltc: &Ltc) -> f32 {
        let mut l1 = 0.0;
        for u in strata(STRATA / 2, 11) {
            for l in [ltc.sample(u), sample_lobe(self.v, self.s, u).0] {
                let (d, f) = (ltc.eval(l), self.f(l));
                let pdf = d + lobe_pdf(self.v, l, self.s);
                if pdf > 0.0 && l.is_finite() {
                    l1 += (d - f).abs() / pdf;
                }
            }
        }
        l1 / ((STRATA / 2) * (STRATA / 2)) as f32
    }
}

/// One fitted cell.
#[derive(Clone, Copy, Debug)]
pub struct Fit {
    pub ltc: Ltc,
    /// Scales D so that its part above the horizon integrates to the specular albedo.
    pub magnitude: f32,
    /// ∫ |D − f| over the sphere, f the lobe normalised: 0 is a perfect fit, 2 none.
    pub error: f32,
}

/// The transform of parameters `(a, b, c)` in the frame of `mean`: M = [X Y Z]·[a 0 b; 0 c 0; 0 0 1].
fn transform(mean: Vec3, p: [f32; 3]) -> Mat3 {
    let frame = Mat3::from_cols(Vec3::Y.cross(mean).normalize(), Vec3::Y, mean);
    frame
        * Mat3::from_cols(
            Vec3::new(p[0].abs().max(1e-4), 0.0, 0.0),
            Vec3::new(0.0, p[2].abs().max(1e-4), 0.0),
            Vec3::new(p[1], 0.0, 1.0),
        )
}

/// Fit the cell of roughness `roughness` and view `v`, starting the search from `start`
/// (a neighbour's parameters); returns the fit and its parameters.
pub fn fit_cell(roughness: f32, v: Vec3, start: [f32; 3]) -> (Fit, [f32; 3]) {
    let (p, fit) = fit_cell_with(roughness, v, start, 300);
    (fit, p)
}

/// `fit_cell` with at most `iterations` steps of the search (0: `start` as it is).
pub fn fit_cell_with(roughness: f32, v: Vec3, start: [f32; 3], iterations: usize) -> ([f32; 3], Fit) {
    let s = shininess(roughness);
    let target = Target {
        v,
        s,
        albedo: albedo(v, s, STRATA, 3).max(1e-8),
    };
    let mean = target.mean_direction();
    let cost = |p: &[f32; 3]| target.error(&Ltc::new(transform(mean, *p)));
    let p = if iterations == 0 {
        start
    } else {
        nelder_mead(cost, start, iterations)
    };
    let ltc = Ltc::new(transform(mean, p));
    let magnitude = target.albedo / ltc.upper_share(STRATA, 5).max(1e-6);
    let error = target.error(&ltc);
    (p, Fit { ltc, magnitude, error })
}

/// The whole table, rows (roughness) in parallel, each row's cells from normal incidence
/// towards grazing, each fit starting from the one before. Row-major: `SIZE × SIZE × STRIDE`.
pub fn fit_table() -> Vec<Fit> {
    use rayon::prelude::*;
    let rows: Vec<Vec<Fit>> = (0..SIZE)
        .into_par_iter()
        .map(|i| {
            let r = roughness_at(i);
            // At normal incidence an isotropic lobe: a = c, b = 0.
            let mut p = [r * r, 0.0, r * r];
            (0..SIZE)
                .map(|j| {
                    let (fit, next) = fit_cell(r, view_at(j), p);
                    p = next;
                    fit
                })
                .collect()
        })
        .collect();
    rows.into_iter().flatten().collect()
}

/// The table as the pipelines read it: per cell `a, b, c, d, magnitude, error, 0, 0`.
pub fn table_floats(fits: &[Fit]) -> Vec<f32> {
    fits.iter()
        .flat_map(|f| {
            let [a, b, c, d] = f.ltc.inverse_entries();
            [a, b, c, d, f.magnitude, f.error, 0.0, 0.0]
        })
        .collect()
}

/// Nelder-Mead simplex search for a minimum of `f` from `start` (first steps 30% of the
/// lobe's scale), at most `iterations` steps; deterministic.
fn nelder_mead(f: impl Fn(&[f32; 3]) -> f32, start: [f32; 3], iterations: usize) -> [f32; 3] {
    let scale = start[0].abs().max(start[2].abs()).max(1e-3);
    let mut simplex: Vec<([f32; 3], f32)> = (0..4)
        .map(|k| {
            let mut p = start;
            if k > 0 {
                p[k - 1] += 0.3 * scale;
            }
            (p, f(&p))
        })
        .collect();
    let lerp = |a: &[f32; 3], b: &[f32; 3], t: f32| -> [f32; 3] { std::array::from_fn(|i| a[i] + (b[i] - a[i]) * t) };
    for _ in 0..iterations {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        if (simplex[3].1 - simplex[0].1).abs() <= 1e-7 * simplex[0].1.abs().max(1e-12) {
            break;
        }
        let centre: [f32; 3] = std::array::from_fn(|i| simplex[..3].iter().map(|(p, _)| p[i]).sum::<f32>() / 3.0);
        let worst = simplex[3].0;
        let reflected = lerp(&centre, &worst, -1.0);
        let fr = f(&reflected);
        if fr < simplex[0].1 {
            let expanded = lerp(&centre, &worst, -2.0);
            let fe = f(&expanded);
            simplex[3] = if fe < fr { (expanded, fe) } else { (reflected, fr) };
        } else if fr < simplex[2].1 {
            simplex[3] = (reflected, fr);
        } else {
            let contracted = lerp(&centre, &worst, 0.5);
            let fc = f(&contracted);
            if fc < simplex[3].1 {
                simplex[3] = (contracted, fc);
            } else {
                let best = simplex[0].0;
                for s in simplex.iter_mut().skip(1) {
                    s.0 = lerp(&best, &s.0, 0.5);
                    s.1 = f(&s.0);
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    simplex[0].0
}
