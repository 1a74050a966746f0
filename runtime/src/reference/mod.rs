//! The reference renderer: a CPU path tracer over the same scene data the raster pipelines
//! draw (meshes, glTF materials and textures, every light kind with the shaders' attenuation
//! and cone), computing exactly the quantities the real-time effects approximate. Sub-stages:
//! `world` (triangles, BVH, surfaces), `shading` (the shaders' light and BRDF definitions),
//! `sample` (deterministic random numbers, directions), `integrate` (one estimator per term),
//! `store` (EXR files, manifest, cache); here: terms, settings and the pixel loop.

pub mod integrate;
pub mod sample;
pub mod shading;
pub mod store;
pub mod world;

use crate::io::Image;
use crate::scene::Scene;
use glam::{Vec3, Vec4};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
pub use shading::Brdf;
use std::time::Instant;

/// What the reference computes per pixel (each camera ray goes through the pixel's centre,
/// where the raster passes sample it, so that edges are not counted as error).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Term {
    /// Emission plus the lights' light through the BRDF with exact visibility (hard shadows).
    Direct,
    /// Ambient occlusion: 1 − the cosine-weighted share of directions blocked within the AO
    /// radius (each blocker weighed 1/(1 + d²) with the falloff); 1 where nothing was hit.
    Ao,
    /// One bounce of the lights' light, as a white Lambertian receiver reflects it
    /// ((1/π) ∫ L_direct cos θ dω; raster `gi.indirect` before the albedo).
    IndirectDiffuse,
    /// The light seen in the reflection: emitted and directly lit surfaces along the
    /// specular lobe about the mirror direction, averaged (raster `ssr.color`).
    IndirectSpecular,
    /// All light towards the camera, every bounce (global illumination).
    Full,
}

impl Term {
    pub const ALL: [Term; 5] = [Term::Direct, Term::Ao, Term::IndirectDiffuse, Term::IndirectSpecular, Term::Full];
    pub const NAMES: [&'static str; 5] = ["direct", "ao", "indirect_diffuse", "indirect_specular", "full"];

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
    pub fn from_name(s: &str) -> Option<Term> {
        Self::NAMES.iter().position(|n| *n == s).map(|i| Self::ALL[i])
    }
    /// Noise-free with centre rays and point lights: evaluated once per pixel.
    fn exact(self) -> bool {
        self == Term::Direct
    }
}

/// How many samples: a count, or as many as fit in a time budget (rounded to whole passes).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Budget {
    Spp(u32),
    Seconds(f64),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    pub budget: Budget,
    pub terms: Vec<Term>,
    pub ao_radius: f32,
    pub ao_falloff: bool,
    pub seed: u64,
    pub brdf: Brdf,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            budget: Budget::Spp(64),
            terms: vec![Term::Direct],
            ao_radius: 0.5,
            ao_falloff: false,
            seed: 0,
            brdf: Brdf::BlinnPhong,
        }
    }
}

/// One term's image: the per-pixel mean and the variance of that mean (sample variance / n:
/// the reference's own noise, which error measures subtract).
#[derive(Clone, Debug)]
pub struct TermImage {
    pub term: Term,
    pub mean: Image,
    pub variance: Image,
}

#[derive(Clone, Debug)]
pub struct Reference {
    pub terms: Vec<TermImage>,
    pub spp: u32,
    pub seconds: f64,
    pub triangles: usize,
}

impl Reference {
    pub fn term(&self, t: Term) -> Option<&TermImage> {
        self.terms.iter().find(|i| i.term == t)
    }
}

/// Samples per pixel in one pass over the image (time budgets stop between passes).
const PASS_SPP: u32 = 4;

/// Camera rays through pixel centres, clipped to the near and far planes as rasterising is.
struct Camera {
    inverse: glam::Mat4,
    size: (u32, u32),
}

impl Camera {
    fn new(scene: &Scene) -> Camera {
        let (w, h) = scene.size;
        let vp = scene.camera.proj(w as f32 / h.max(1) as f32) * scene.camera.view();
        Camera {
            inverse: vp.inverse(),
            size: (w, h),
        }
    }

    /// Origin (on the near plane), unit direction and length to the far plane.
    fn ray(&self, x: u32, y: u32) -> (Vec3, Vec3, f32) {
        let (w, h) = self.size;
        let nx = (x as f32 + 0.5) / w as f32 * 2.0 - 1.0;
        let ny = 1.0 - (y as f32 + 0.5) / h as f32 * 2.0;
        let near = self.inverse.project_point3(Vec3::new(nx, ny, 0.0));
        let far = self.inverse.project_point3(Vec3::new(nx, ny, 1.0));
        let d = far - near;
        (near, d.normalize_or(Vec3::NEG_Z), d.length())
    }
}

/// Per-pixel running sums: for each term, Σx and Σx² per channel.
type Sums = Vec<f64>;
const SLOTS: usize = 6;

/// Bytes a render of `terms` terms at `size` holds: the f64 sums, then mean and variance
/// images per term.
pub fn memory_bytes((w, h): (u32, u32), terms: usize) -> u64 {
    w as u64 * h as u64 * terms as u64 * (SLOTS as u64 * 8 + 2 * 16)
}

/// Render every term of `s` for `scene` at its size. `progress` draws a bar with ETA.
pub fn render(scene: &Scene, s: &Settings, progress: bool) -> Reference {
    let start = Instant::now();
    let world = world::World::new(scene);
    let (lo, hi) = scene.bounds();
    let ctx = integrate::Context {
        world: &world,
        lights: scene.active_lights().into_iter().map(shading::PunctualLight::new).collect(),
        brdf: s.brdf,
        eps: (hi - lo).length().max(1e-6) * 1e-5,
        ao_radius: s.ao_radius,
        ao_falloff: s.ao_falloff,
    };
    let cam = Camera::new(scene);
    let (w, h) = scene.size;
    let mut terms = s.terms.clone();
    terms.sort();
    terms.dedup();
    let mut sums: Sums = vec![0.0; (w * h) as usize * terms.len() * SLOTS];
    let bar = progress_bar(s.budget, h, progress);
    let mut done = 0u32;
    loop {
        let n = match s.budget {
            Budget::Spp(total) => PASS_SPP.min(total.saturating_sub(done)),
            Budget::Seconds(t) if start.elapsed().as_secs_f64() >= t && done > 0 => 0,
            Budget::Seconds(_) => PASS_SPP,
        };
        if n == 0 {
            break;
        }
        sums.par_chunks_mut(w as usize * terms.len() * SLOTS)
            .enumerate()
            .for_each(|(y, row)| {
                pass_row(&ctx, &cam, (&terms, s.seed), (y as u32, done..done + n), row);
                if let Budget::Spp(_) = s.budget {
                    bar.inc(1);
                }
            });
        done += n;
        if let Budget::Seconds(t) = s.budget {
            bar.set_position((start.elapsed().as_secs_f64() / t * 1000.0).min(1000.0) as u64);
        }
    }
    bar.finish_and_clear();
    Reference {
        terms: terms
            .iter()
            .enumerate()
            .map(|(k, &t)| finish(&sums, (k, terms.len()), t, (w, h), done))
            .collect(),
        spp: done,
        seconds: start.elapsed().as_secs_f64(),
        triangles: world.triangles(),
    }
}

fn progress_bar(budget: Budget, rows: u32, visible: bool) -> indicatif::ProgressBar {
    if !visible {
        return indicatif::ProgressBar::hidden();
    }
    let (len, what) = match budget {
        Budget::Spp(n) => ((rows * n.div_ceil(PASS_SPP)) as u64, "rows"),
        Budget::Seconds(_) => (1000, "‰ of the time"),
    };
    let bar = indicatif::ProgressBar::new(len);
    let style = format!("reference {{bar:40}} {{pos}}/{{len}} {what}, ETA {{eta}}");
    if let Ok(st) = indicatif::ProgressStyle::with_template(&style) {
        bar.set_style(st);
    }
    bar
}

/// Samples `range` of every pixel of row `y`, added to the row's sums.
fn pass_row(
    ctx: &integrate::Context,
    cam: &Camera,
    (terms, seed): (&[Term], u64),
    (y, range): (u32, std::ops::Range<u32>),
    row: &mut [f64],
) {
    let (w, _) = cam.size;
    for x in 0..w {
        let (origin, dir, len) = cam.ray(x, y);
        let hit = ctx.world.trace(origin, dir, (0.0, len), world::Faces::Seen);
        let pixel = (y * w + x) as u64;
        for (k, &term) in terms.iter().enumerate() {
            let slot = &mut row[(x as usize * terms.len() + k) * SLOTS..][..SLOTS];
            for i in range.clone() {
                if term.exact() && i > 0 {
                    break;
                }
                let mut rng = sample::Rng::new(seed, pixel, i as u64, term as u64);
                let v = estimate(ctx, term, hit.as_ref(), -dir, &mut rng);
                for c in 0..3 {
                    slot[c] += v[c] as f64;
                    slot[3 + c] += (v[c] as f64) * (v[c] as f64);
                }
            }
        }
    }
}

fn estimate(ctx: &integrate::Context, term: Term, hit: Option<&world::Hit>, v: Vec3, rng: &mut sample::Rng) -> Vec3 {
    let Some(h) = hit else {
        // The background: nothing drawn, nothing occluded.
        return if term == Term::Ao { Vec3::ONE } else { Vec3::ZERO };
    };
    match term {
        Term::Direct => ctx.direct(h, v),
        Term::Ao => Vec3::splat(ctx.ao(h, rng)),
        Term::IndirectDiffuse => ctx.indirect_diffuse(h, rng),
        Term::IndirectSpecular => ctx.indirect_specular(h, v, rng),
        Term::Full => ctx.full(h, v, rng),
    }
}

/// Term `k` of `count` as mean and variance-of-the-mean images.
fn finish(sums: &[f64], (k, count): (usize, usize), term: Term, (w, h): (u32, u32), spp: u32) -> TermImage {
    let n = if term.exact() { 1.0 } else { spp.max(1) as f64 };
    let (mut mean, mut var) = (Vec::with_capacity((w * h * 4) as usize), Vec::with_capacity((w * h * 4) as usize));
    for p in 0..(w * h) as usize {
        let s = &sums[(p * count + k) * SLOTS..][..SLOTS];
        let m: [f64; 3] = std::array::from_fn(|c| s[c] / n);
        let v: [f64; 3] = std::array::from_fn(|c| {
            if n > 1.0 {
                ((s[3 + c] - n * m[c] * m[c]) / (n - 1.0)).max(0.0) / n
            } else {
                0.0
            }
        });
        mean.extend_from_slice(&Vec4::new(m[0] as f32, m[1] as f32, m[2] as f32, 1.0).to_array());
        var.extend_from_slice(&Vec4::new(v[0] as f32, v[1] as f32, v[2] as f32, 1.0).to_array());
    }
    let image = |rgba| Image {
        width: w,
        height: h,
        rgba,
        srgb: false,
    };
    TermImage {
        term,
        mean: image(mean),
        variance: image(var),
    }
}
