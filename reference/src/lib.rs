//! The reference renderer: a CPU path tracer over the same scene data the raster pipelines
//! draw (meshes, glTF materials and textures, every light kind with the shaders' attenuation
//! and cone), computing exactly the quantities the real-time effects approximate. Sub-stages:
//! `world` (triangles, BVH, surfaces), `shading` (the shaders' light and BRDF definitions),
//! `emitters` (emissive triangles as lights), `sample` (deterministic random numbers, directions), `integrate` (one estimator per term),
//! `store` (EXR files, manifest, cache); here: terms, settings and the pixel loop.

mod bvh;
pub mod emitters;
pub mod error;
pub use error::{Error, Result};
pub mod integrate;
pub mod lanes;
pub mod ltc;
pub mod sample;
pub mod shading;
pub mod store;
pub mod world;

use glam::{Vec3A, Vec4};
use lightbench_scene::io::Image;
use lightbench_scene::Scene;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
pub use shading::Brdf;
use std::time::Instant;

/// What the reference computes per pixel (each camera ray goes through the pixel's centre,
/// where the raster passes sample it, so that edges are not counted as error).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Term {
    /// Emission plus the light of every light and emitter once through the BRDF, with exact
    /// visibility (hard shadows).
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
}

/// How many samples: a count, as many as fit in a time budget (rounded to whole passes), or
/// as many as bring a percentile of the pixels' relative standard error down to a target.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Budget {
    Spp(u32),
    Seconds(f64),
    /// `target` relative standard error at the `percentile` (100: the worst pixel), found by
    /// a pilot of 64 spp and predicted from it (error ∝ 1/√n), checked and predicted again
    /// until reached or `max_spp`.
    Error {
        target: f64,
        percentile: f64,
        max_spp: u32,
    },
}

/// What a noise-targeted render reached: the relative standard error at the percentile.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Reached {
    pub target: f64,
    pub percentile: f64,
    pub error: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    pub budget: Budget,
    pub terms: Vec<Term>,
    pub ao_radius: f32,
    pub ao_falloff: bool,
    pub seed: u64,
    pub brdf: Brdf,
    /// Emitters sampled as lights (next-event estimation with MIS); off, only BRDF sampling
    /// finds them — slower to converge to the same image, kept to check that it is the same.
    #[serde(default = "yes")]
    pub sample_emitters: bool,
    /// How the `full` term's paths are computed: one at a time, or a pixel's 8 at once.
    #[serde(default)]
    pub integrator: Integrator,
}

/// The `full` term's integrator: `lanes` (a pixel's paths 8 side by side, their BRDF draws,
/// emitters' BRDF and lights' light in SIMD lanes; the same image within noise) or `scalar`
/// (one path at a time: the oracle). The other terms, and scenes with blended surfaces (whose
/// samples' camera rays differ), are computed one path at a time either way.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Integrator {
    Scalar,
    #[default]
    Lanes,
}

fn yes() -> bool {
    true
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
            sample_emitters: true,
            integrator: Integrator::default(),
        }
    }
}

/// One term's image: the per-pixel mean and the variance of that mean (sample variance / n:
/// the reference's own noise, which error measures subtract).
#[derive(Clone, Debug)]
pub struct TermImage {
    pub term: Term,
    /// Samples per pixel behind it (1 for a noise-free term).
    pub samples: u32,
    pub mean: Image,
    pub variance: Image,
}

impl TermImage {
    /// The relative standard error of every lit pixel (`relative_error`), sorted.
    pub fn relative_errors(&self) -> Vec<f64> {
        let rgb = |p: &[f32]| [p[0] as f64, p[1] as f64, p[2] as f64];
        let mut e: Vec<f64> = self
            .mean
            .rgba
            .chunks_exact(4)
            .zip(self.variance.rgba.chunks_exact(4))
            .filter_map(|(m, v)| relative_error(rgb(m), rgb(v)))
            .collect();
        e.sort_by(f64::total_cmp);
        e
    }
}

#[derive(Clone, Debug)]
pub struct Reference {
    pub terms: Vec<TermImage>,
    pub spp: u32,
    pub seconds: f64,
    pub triangles: usize,
    /// Emissive triangles sampled as lights.
    pub emitters: usize,
    /// With an error budget: what the render reached.
    pub reached: Option<Reached>,
}

impl Reference {
    pub fn term(&self, t: Term) -> Option<&TermImage> {
        self.terms.iter().find(|i| i.term == t)
    }
}

/// Samples per pixel in one pass over the image under a time budget, which stops between
/// passes. A count or an error target takes all the samples it asks for in one pass, so that
/// each pixel's camera ray and first vertex (`integrate::Primary`) are worked out once for
/// all of them rather than once per pass (the sums, and so the image, are the same).
const PASS_SPP: u32 = 4;

/// Camera rays through pixel centres, clipped to the near and far planes as rasterising is.
/// Made from the frustum itself (f64), not by inverting the projection: with near 1e-4 and
/// far 1e5 the f32 projection matrix puts the far plane at infinity.
struct Camera {
    to_world: glam::DMat4,
    /// tan of half the field of view, horizontally and vertically.
    tan: (f64, f64),
    near: f64,
    far: f64,
    size: (u32, u32),
}

impl Camera {
    fn new(scene: &Scene) -> Camera {
        let (w, h) = scene.size;
        let c = &scene.camera;
        let tan_y = (c.fov.to_radians() as f64 / 2.0).tan();
        Camera {
            to_world: c.view().as_dmat4().inverse(),
            tan: (tan_y * w as f64 / h.max(1) as f64, tan_y),
            near: c.near as f64,
            far: c.far as f64,
            size: (w, h),
        }
    }

    /// Origin (on the near plane), unit direction and length to the far plane of the ray
    /// through pixel (x, y)'s centre.
    fn ray(&self, x: u32, y: u32) -> (Vec3A, Vec3A, f32) {
        self.ray_at(x as f64 + 0.5, y as f64 + 0.5)
    }

    /// `ray` through any point of the image (in pixels from its top left corner).
    fn ray_at(&self, px: f64, py: f64) -> (Vec3A, Vec3A, f32) {
        let (w, h) = self.size;
        let nx = px / w as f64 * 2.0 - 1.0;
        let ny = 1.0 - py / h as f64 * 2.0;
        // The view-space point at depth 1 through the pixel: scaled to the near and far planes.
        let at_one = glam::DVec3::new(nx * self.tan.0, ny * self.tan.1, -1.0);
        let near = self.to_world.transform_point3(at_one * self.near);
        let far = self.to_world.transform_point3(at_one * self.far);
        let d = far - near;
        (near.as_vec3a(), d.normalize_or(glam::DVec3::NEG_Z).as_vec3a(), d.length() as f32)
    }
}

/// The pixels whose centre lies within a thousandth of a pixel of an edge between surfaces
/// that look different (another normal, or albedo, emission, metallic or roughness off by
/// more than 1%, or nothing; a masked surface's cut-out edge is one): there the surface a
/// camera ray meets is a tie that another renderer (the GPU path tracer, a rasteriser) may
/// break the other way, so comparisons of two renderers leave them out. Row by row.
pub fn edge_pixels(scene: &Scene) -> Vec<bool> {
    let view = CameraView::new(scene);
    let look = |px: f64, py: f64| view.seen(px, py).map(|h| (h.n, h.albedo, h.emissive, h.metallic, h.roughness));
    // Within 1% (a map's bilinear lookup moves a little within a thousandth of a pixel).
    let close = |a: Vec3A, b: Vec3A| (a - b).abs().max_element() <= 0.01 * a.abs().max(b.abs()).max_element().max(0.01);
    let same = |a: &Option<_>, b: &Option<_>| match (a, b) {
        (None, None) => true,
        (Some((n0, a0, e0, m0, r0)), Some((n1, a1, e1, m1, r1))) => {
            let n0: &Vec3A = n0;
            let scalars = Vec3A::new(*m0, *r0, 0.0);
            n0.dot(*n1) > 0.999 && close(*a0, *a1) && close(*e0, *e1) && close(scalars, Vec3A::new(*m1, *r1, 0.0))
        }
        _ => false,
    };
    per_pixel(scene.size, |cx, cy| {
        let centre = look(cx, cy);
        [(1e-3, 0.0), (-1e-3, 0.0), (0.0, 1e-3), (0.0, -1e-3)]
            .iter()
            .any(|(dx, dy)| !same(&centre, &look(cx + dx, cy + dy)))
    })
}

/// The mesh each pixel's centre sees (an index into `scene.meshes`; `None` over the
/// background), as a camera ray finds it: what per-surface comparisons group pixels by. Row by
/// row.
pub fn surfaces_seen(scene: &Scene) -> Vec<Option<usize>> {
    let view = CameraView::new(scene);
    // The first scene triangle of each mesh, as World::new lays them out.
    let starts: Vec<u32> = scene
        .meshes
        .iter()
        .scan(0u32, |next, m| {
            let start = *next;
            *next += (m.drawn_indices() as usize).min(m.indices.len()) as u32 / 3;
            Some(start)
        })
        .collect();
    per_pixel(scene.size, |cx, cy| {
        let t = view.world.scene_triangle(view.seen(cx, cy)?.triangle);
        Some(starts.partition_point(|&s| s <= t) - 1)
    })
}

/// What camera rays see of a scene, blended surfaces solid: what comparisons of renderers
/// look at before any sample is drawn.
struct CameraView {
    world: world::World,
    cam: Camera,
}

impl CameraView {
    fn new(scene: &Scene) -> CameraView {
        CameraView {
            world: world::World::new(scene),
            cam: Camera::new(scene),
        }
    }

    /// The surface the camera ray through (px, py) (in pixels from the top left) meets.
    fn seen(&self, px: f64, py: f64) -> Option<world::Hit> {
        let (origin, dir, len) = self.cam.ray_at(px, py);
        self.world
            .trace_with_coin(origin, dir, (0.0, len), world::Faces::Seen, sample::SOLID_BLEND)
    }
}

/// `f` at every pixel centre of an image of `size`, row by row (rows in parallel).
fn per_pixel<T: Send>((w, h): (u32, u32), f: impl Fn(f64, f64) -> T + Sync) -> Vec<T> {
    (0..h)
        .into_par_iter()
        .flat_map_iter(|y| {
            let f = &f;
            (0..w).map(move |x| f(x as f64 + 0.5, y as f64 + 0.5))
        })
        .collect()
}

/// Per-pixel running sums: for each term, Σx and Σx² per channel.
type Sums = Vec<f64>;
const SLOTS: usize = 6;

/// Bytes a render of `terms` terms at `size` holds: the f64 sums, then mean and variance
/// images per term.
pub fn memory_bytes((w, h): (u32, u32), terms: usize) -> u64 {
    w as u64 * h as u64 * terms as u64 * (SLOTS as u64 * 8 + 2 * 16)
}

/// Samples of a pilot for an error budget.
pub const PILOT_SPP: u32 = 64;

/// The estimators' context for `scene` as `s` asks.
fn context<'a>(scene: &Scene, world: &'a world::World, s: &Settings) -> integrate::Context<'a> {
    let (lo, hi) = scene.bounds();
    integrate::Context {
        world,
        lights: scene.active_lights().into_iter().map(shading::PunctualLight::new).collect(),
        emitters: emitters::Emitters::new(world),
        brdf: s.brdf,
        eps: (hi - lo).length().max(1e-6) * 1e-5,
        ao_radius: s.ao_radius,
        ao_falloff: s.ao_falloff,
        sample_emitters: s.sample_emitters,
    }
}

/// Render every term of `s` for `scene` at its size. `progress` draws a bar with ETA.
pub fn render(scene: &Scene, s: &Settings, progress: bool) -> Reference {
    let start = Instant::now();
    let world = world::World::new(scene);
    render_from(&world, scene, s, progress, start)
}

/// `render` in a `world` already built from `scene` (`World::new(scene)`; the scene's size may
/// differ since): the same image bit for bit, its `seconds` (and a `Budget::Seconds`) counted
/// from this call, the BVH's build left out — for timing the paths alone, or rendering one
/// scene many times over, without building its world each time.
pub fn render_in(world: &world::World, scene: &Scene, s: &Settings, progress: bool) -> Reference {
    render_from(world, scene, s, progress, Instant::now())
}

/// `render`'s passes over the image, timed from `start`.
fn render_from(world: &world::World, scene: &Scene, s: &Settings, progress: bool, start: Instant) -> Reference {
    let ctx = context(scene, world, s);
    let cam = Camera::new(scene);
    let (w, h) = scene.size;
    let mut terms = s.terms.clone();
    terms.sort();
    terms.dedup();
    let mut sums: Sums = vec![0.0; (w * h) as usize * terms.len() * SLOTS];
    let bar = progress_bar(s.budget, h, progress);
    let mut done = 0u32;
    let mut goal = match s.budget {
        Budget::Spp(n) => n,
        Budget::Seconds(_) => u32::MAX,
        Budget::Error { max_spp, .. } => PILOT_SPP.min(max_spp),
    };
    let mut reached = None;
    loop {
        if done >= goal {
            let Budget::Error {
                target,
                percentile,
                max_spp,
            } = s.budget
            else {
                break;
            };
            let error = percentile_error(&sums, &terms, &ctx, done, percentile);
            reached = Some(Reached { target, percentile, error });
            if error <= target || done >= max_spp {
                break;
            }
            goal = predict(done, error / target).min(max_spp);
            bar.inc_length(h as u64);
        }
        if let Budget::Seconds(t) = s.budget {
            if start.elapsed().as_secs_f64() >= t && done > 0 {
                break;
            }
        }
        let n = match s.budget {
            Budget::Seconds(_) => PASS_SPP.min(goal - done),
            Budget::Spp(_) | Budget::Error { .. } => goal - done,
        };
        sums.par_chunks_mut(w as usize * terms.len() * SLOTS)
            .enumerate()
            .for_each(|(y, row)| {
                pass_row(&ctx, &cam, (&terms, s.seed, s.integrator), (y as u32, done..done + n), row);
                if !matches!(s.budget, Budget::Seconds(_)) {
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
            .map(|(k, &t)| finish(&sums, (k, terms.len()), t, (w, h), if ctx.exact(t) { 1 } else { done }))
            .collect(),
        spp: done,
        seconds: start.elapsed().as_secs_f64(),
        triangles: world.triangles(),
        emitters: ctx.emitters.len(),
        reached,
    }
}

/// Samples per pixel that bring a relative error `ratio` times the target down to it
/// (error ∝ 1/√n, 5% spare for the estimate's own noise), a multiple of
/// `PASS_SPP`, at least that many more than `done`.
pub fn predict(done: u32, ratio: f64) -> u32 {
    let need = (done as f64 * ratio * ratio * 1.05).ceil().min(u32::MAX as f64 / 2.0) as u32;
    need.max(done + PASS_SPP).next_multiple_of(PASS_SPP)
}

/// A pixel's relative standard error: the channels' standard errors of the mean over their
/// means (summed, so a dim channel does not dominate); `None` for a black pixel.
pub fn relative_error(mean: [f64; 3], variance: [f64; 3]) -> Option<f64> {
    let m: f64 = mean.iter().sum();
    (m > 0.0).then(|| variance.iter().map(|v| v.max(0.0).sqrt()).sum::<f64>() / m)
}

/// The `percentile` (0..100) of the relative standard error over every pixel of every noisy
/// term, after `n` samples (0 if no pixel is lit).
fn percentile_error(sums: &[f64], terms: &[Term], ctx: &integrate::Context, n: u32, percentile: f64) -> f64 {
    let n = n as f64;
    let mut errors = vec![];
    for (k, &t) in terms.iter().enumerate() {
        if ctx.exact(t) {
            continue;
        }
        for p in sums.chunks_exact(SLOTS).skip(k).step_by(terms.len()) {
            let mean: [f64; 3] = std::array::from_fn(|c| p[c] / n);
            let var = std::array::from_fn(|c| (p[3 + c] - n * mean[c] * mean[c]) / (n - 1.0).max(1.0) / n);
            errors.extend(relative_error(mean, var));
        }
    }
    errors.sort_by(f64::total_cmp);
    percentile_of(&errors, percentile)
}

/// The `p`th percentile (0..100, nearest rank) of sorted values; 0 for none.
pub fn percentile_of(sorted: &[f64], p: f64) -> f64 {
    let rank = ((p / 100.0 * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len().max(1)) - 1;
    sorted.get(rank).copied().unwrap_or(0.0)
}

fn progress_bar(budget: Budget, rows: u32, visible: bool) -> indicatif::ProgressBar {
    if !visible {
        return indicatif::ProgressBar::hidden();
    }
    let (len, what) = match budget {
        Budget::Spp(_) => (rows as u64, "rows"),
        Budget::Seconds(_) => (1000, "‰ of the time"),
        Budget::Error { .. } => (rows as u64, "rows (so far)"),
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
    (terms, seed, integrator): (&[Term], u64, Integrator),
    (y, range): (u32, std::ops::Range<u32>),
    row: &mut [f64],
) {
    let (w, _) = cam.size;
    let with_lights = terms.iter().any(|t| matches!(t, Term::Direct | Term::Full));
    // With blended surfaces each sample traces the camera ray with a coin of its own (else
    // a pixel would meet them in all its samples or none); without, once per pixel.
    let blended = ctx.world.has_blended();
    for x in 0..w {
        let (origin, dir, len) = cam.ray(x, y);
        let first = |coin| {
            let hit = ctx.world.trace_with_coin(origin, dir, (0.0, len), world::Faces::Seen, coin);
            hit.map(|h| ctx.primary(&h, -dir, with_lights, coin))
        };
        let shared = (!blended).then(|| first(0));
        let pixel = (y * w + x) as u64;
        let in_lanes = match (&shared, integrator, terms.contains(&Term::Full)) {
            (Some(Some(p)), Integrator::Lanes, true) => full_in_lanes(ctx, p, -dir, (seed, pixel), range.clone()),
            _ => vec![],
        };
        for i in range.clone() {
            // Worked out once per sample for all the terms.
            let own = blended.then(|| first(sample::coin(seed, pixel, i as u64)));
            let primary = own.as_ref().or(shared.as_ref()).and_then(Option::as_ref);
            for (k, &term) in terms.iter().enumerate() {
                if ctx.exact(term) && i > 0 {
                    continue;
                }
                let slot = &mut row[(x as usize * terms.len() + k) * SLOTS..][..SLOTS];
                let v = match in_lanes.get((i - range.start) as usize) {
                    Some(&v) if term == Term::Full => v,
                    _ => estimate(ctx, term, primary, -dir, &mut sample::Rng::new(seed, pixel, i as u64, term as u64)),
                };
                debug_assert!(v.is_finite(), "{term:?} at ({x}, {y}) sample {i}: {v}");
                for c in 0..3 {
                    slot[c] += v[c] as f64;
                    slot[3 + c] += (v[c] as f64) * (v[c] as f64);
                }
            }
        }
    }
}

/// `full` for samples `range` of the pixel whose camera ray found `p`, their paths in lanes.
fn full_in_lanes(
    ctx: &integrate::Context,
    p: &integrate::Primary,
    v: Vec3A,
    (seed, pixel): (u64, u64),
    range: std::ops::Range<u32>,
) -> Vec<Vec3A> {
    let mut out = vec![Vec3A::ZERO; range.len()];
    let rng = |i: u32| sample::Rng::new(seed, pixel, i as u64, Term::Full as u64);
    ctx.full_lanes(p, v, range, rng, lanes::Draws::Simd, &mut out);
    out
}

fn estimate(ctx: &integrate::Context, term: Term, primary: Option<&integrate::Primary>, v: Vec3A, rng: &mut sample::Rng) -> Vec3A {
    let Some(p) = primary else {
        // The background: nothing drawn, nothing occluded.
        return if term == Term::Ao { Vec3A::ONE } else { Vec3A::ZERO };
    };
    let h = &p.hit;
    match term {
        Term::Direct => ctx.direct(p, v, rng),
        Term::Ao => Vec3A::splat(ctx.ao(h, rng)),
        Term::IndirectDiffuse => ctx.indirect_diffuse(h, rng),
        Term::IndirectSpecular => ctx.indirect_specular(h, v, rng),
        Term::Full => ctx.full(p, v, rng),
    }
}

/// Term `k` of `count`, after `spp` samples, as mean and variance-of-the-mean images.
fn finish(sums: &[f64], (k, count): (usize, usize), term: Term, (w, h): (u32, u32), spp: u32) -> TermImage {
    let n = spp.max(1) as f64;
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
        samples: spp,
        mean: image(mean),
        variance: image(var),
    }
}
