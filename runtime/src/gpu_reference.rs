//! The reference on the GPU: `pipelines/pathtrace.lbp` (the CPU reference's integrator as a
//! pipeline) run frame after frame until the budget is spent, its accumulation read back as
//! the reference's term images — the same `Reference` the CPU path tracer makes, stored the
//! same way (`reference --device gpu`, sweeps and diffs).

use crate::error::{Error, Result};
use crate::gpu::{Executor, Gpu};
use crate::reference::{self, Brdf, Budget, Reached, Reference, Settings, Term, TermImage};
use crate::scene::Scene;
use lightbench_compiler::ir::ParamValue;
use lightbench_compiler::Workspace;
use std::path::Path;
use std::time::Instant;

/// The terms the path-tracing pipeline has (its variant `term`).
pub const TERMS: [Term; 3] = [Term::Direct, Term::Ao, Term::Full];

/// Where the path tracer comes from: a workspace and the pipeline's path in it.
pub struct Tracer<'a> {
    pub ws: &'a Workspace,
    pub pipeline: &'a Path,
}

/// The bundled path tracer's path relative to a project.
pub const PIPELINE: &str = "pipelines/pathtrace.lbp";

/// The path tracer to run: the file named, else `pipelines/pathtrace.lbp` where it is on
/// disk, else the copy bundled in the binary.
pub fn source(named: Option<&Path>) -> Result<(std::path::PathBuf, Workspace)> {
    match named {
        Some(p) if !p.is_file() => Err(Error::Usage(format!("no such pipeline file: {}", p.display()))),
        Some(p) => Ok((p.to_path_buf(), Workspace::disk())),
        None if Path::new(PIPELINE).is_file() => Ok((PIPELINE.into(), Workspace::disk())),
        None => Ok((Path::new(crate::bundled::ROOT).join(PIPELINE), crate::bundled::workspace())),
    }
}

/// Refuse what the GPU path tracer does not compute, by name, before anything renders.
pub fn check(scene: &Scene, s: &Settings) -> Result<()> {
    if let Some(t) = s.terms.iter().find(|t| !TERMS.contains(t)) {
        let names: Vec<&str> = TERMS.iter().map(|t| t.name()).collect();
        return Err(Error::Usage(format!(
            "--device gpu renders the terms {}; `{}` is the CPU reference's only (--device cpu)",
            names.join(", "),
            t.name()
        )));
    }
    if s.brdf != Brdf::BlinnPhong {
        return Err(Error::Usage(
            "--device gpu shades with the Blinn-Phong BRDF only; --brdf lambert is the CPU reference's (--device cpu)".into(),
        ));
    }
    if scene.meshes.iter().all(|m| m.drawn_indices() < 3) {
        return Err(Error::scene(format!(
            "scene `{}` has no triangles for the GPU path tracer to trace (its reference is black, and AO 1 everywhere); the CPU reference renders it",
            scene.name
        )));
    }
    Ok(())
}

/// The triangles that emit with some power (the area lights' count, emissive maps' means
/// included, before any is left out for the raster's budget).
fn emitters(scene: &Scene) -> usize {
    let (kept, dropped) = crate::gpu::scene_gpu::area_lights(scene);
    kept.len() + dropped
}

/// Paths per pixel in one frame: about 4 million a frame at most, so that a frame stays
/// short on any device (a display driver resets a GPU busy for seconds).
fn per_frame((w, h): (u32, u32)) -> u32 {
    ((4u64 << 20) / (w as u64 * h as u64).max(1)).clamp(1, 64) as u32
}

/// Render every term of `s` with the path-tracing pipeline on `gpu`; `progress` draws a bar
/// of the paths traced on a terminal.
pub fn render(gpu: &Gpu, tracer: &Tracer, scene: &Scene, s: &Settings, progress: bool) -> Result<Reference> {
    check(scene, s)?;
    if !gpu.device.features().contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY) {
        return Err(Error::adapter(format!(
            "adapter `{}` ({:?}) has no ray queries (wgpu feature EXPERIMENTAL_RAY_QUERY), which the GPU path tracer needs; use --device cpu, or a Vulkan adapter that has them",
            gpu.info.name, gpu.info.backend
        )));
    }
    let start = Instant::now();
    let mut terms = s.terms.clone();
    terms.sort();
    terms.dedup();
    let (emitters, blended) = (emitters(scene), scene.features().transparent);
    // `direct` has no noise (one sample is all of it, as the CPU reference decides) with no
    // emitter and nothing blended (its coins differ by sample).
    let exact = |t: Term| t == Term::Direct && emitters == 0 && !blended;
    let noisy = terms.iter().filter(|t| !exact(**t)).count().max(1);
    let (mut images, mut reached) = (vec![], None);
    let mut spp = match s.budget {
        Budget::Spp(n) => n,
        _ => 0,
    };
    let bar = progress_bar(s, terms.len(), progress);
    for &t in &terms {
        let mut run = Run::new(gpu, tracer, scene, s, t)?;
        run.bar = bar.clone();
        let budget = match s.budget {
            _ if exact(t) => Budget::Spp(1),
            // The time is shared out between the noisy terms.
            Budget::Seconds(secs) => Budget::Seconds(secs / noisy as f64),
            b => b,
        };
        reached = run.until(gpu, budget, Instant::now())?.or(reached);
        let image = run.image(gpu, t)?;
        if !exact(t) {
            spp = spp.max(image.samples);
        }
        images.push(image);
    }
    bar.finish_and_clear();
    Ok(Reference {
        spp: spp.max(1),
        terms: images,
        seconds: start.elapsed().as_secs_f64(),
        triangles: scene.meshes.iter().map(|m| m.drawn_indices() as usize / 3).sum(),
        emitters,
        reached,
    })
}

/// A bar of paths per pixel over every term (with a count to reach; else of elapsed frames).
fn progress_bar(s: &Settings, terms: usize, visible: bool) -> indicatif::ProgressBar {
    if !visible {
        return indicatif::ProgressBar::hidden();
    }
    let len = match s.budget {
        Budget::Spp(n) => n as u64 * terms as u64,
        _ => 0,
    };
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(st) = indicatif::ProgressStyle::with_template("reference (GPU) {bar:40} {pos}/{len} paths per pixel, ETA {eta}") {
        bar.set_style(st);
    }
    bar
}

/// One term's accumulation on the GPU.
struct Run {
    ex: Executor,
    done: u32,
    chunk: u32,
    pixels: (u32, u32),
    bar: indicatif::ProgressBar,
}

impl Run {
    fn new(gpu: &Gpu, tracer: &Tracer, scene: &Scene, s: &Settings, term: Term) -> Result<Run> {
        let variants = [("term".to_string(), term.name().to_string())];
        let (exe, _) = crate::render::compile_in(tracer.ws, gpu, tracer.pipeline, None, scene, &variants)?;
        let mut ex = Executor::new(gpu, &exe, scene)?;
        let seed = (s.seed % (1 << 31)) as i64;
        for (name, value) in [
            ("pt.seed", ParamValue::Int(seed)),
            ("pt.ao_radius", ParamValue::Float(s.ao_radius as f64)),
            ("pt.ao_falloff", ParamValue::Bool(s.ao_falloff)),
            ("pt.emitter_sampling", ParamValue::Bool(s.sample_emitters)),
        ] {
            ex.set_param(name, value)?;
        }
        Ok(Run {
            ex,
            done: 0,
            chunk: per_frame(scene.size),
            pixels: scene.size,
            bar: indicatif::ProgressBar::hidden(),
        })
    }

    /// `n` more paths per pixel, over as many frames as they take.
    fn take(&mut self, gpu: &Gpu, n: u32) -> Result<()> {
        let goal = self.done + n;
        while self.done < goal {
            let k = self.chunk.min(goal - self.done);
            self.ex.set_param("pt.samples", ParamValue::Int(k as i64))?;
            self.ex.set_param("pt.max_samples", ParamValue::Int(goal as i64))?;
            // Lights and camera at time 0, as the CPU reference takes them.
            let inputs = self.ex.inputs(0.0);
            self.ex.render_frame(gpu, &inputs)?;
            self.done += k;
            self.bar.inc(k as u64);
        }
        Ok(self.ex.wait_idle(gpu)?)
    }

    /// Render until the budget is spent; with an error target, what was reached.
    fn until(&mut self, gpu: &Gpu, budget: Budget, start: Instant) -> Result<Option<Reached>> {
        match budget {
            Budget::Spp(n) => self.take(gpu, n).map(|_| None),
            Budget::Seconds(t) => {
                while self.done == 0 || start.elapsed().as_secs_f64() < t {
                    self.take(gpu, self.chunk.clamp(1, 4))?;
                }
                Ok(None)
            }
            Budget::Error {
                target,
                percentile,
                max_spp,
            } => {
                let mut goal = reference::PILOT_SPP.min(max_spp);
                loop {
                    self.take(gpu, goal - self.done)?;
                    let error = self.percentile_error(gpu, percentile)?;
                    if error <= target || self.done >= max_spp {
                        return Ok(Some(Reached { target, percentile, error }));
                    }
                    goal = reference::predict(self.done, error / target).min(max_spp);
                }
            }
        }
    }

    /// The relative standard error at `percentile` of the lit pixels.
    fn percentile_error(&self, gpu: &Gpu, percentile: f64) -> Result<f64> {
        let image = self.image(gpu, Term::Full)?;
        Ok(reference::percentile_of(&image.relative_errors(), percentile))
    }

    /// The accumulation as a term image: the mean and the variance of the mean (m2 / (n − 1)
    /// / n, as the CPU reference's), every pixel's count checked.
    fn image(&self, gpu: &Gpu, term: Term) -> Result<TermImage> {
        let mut mean = self.ex.read_texture(gpu, "pt.mean", 0, 0)?;
        let mut variance = self.ex.read_texture(gpu, "pt.m2", 0, 0)?;
        let n = self.done as f64;
        for (m, v) in mean.rgba.chunks_exact_mut(4).zip(variance.rgba.chunks_exact_mut(4)) {
            if m[3] as f64 != n {
                return Err(Error::resource(format!(
                    "the path tracer's accumulation holds {} paths in a pixel, not the {n} rendered",
                    m[3]
                )));
            }
            for c in &mut v[..3] {
                *c = if n > 1.0 {
                    (*c as f64 / (n - 1.0) / n).max(0.0) as f32
                } else {
                    0.0
                };
            }
            (m[3], v[3]) = (1.0, 1.0);
        }
        debug_assert_eq!((mean.width, mean.height), self.pixels);
        Ok(TermImage {
            term,
            samples: self.done,
            mean,
            variance,
        })
    }
}
