//! `lightbench reference`: parse the options, load the scene, render (or find in `--out`)
//! the reference terms and report where they are.

use super::plan::parse_size;
use super::{failed, EXIT_ERRORS, EXIT_OK};
use crate::error::{Error, Result};
use crate::reference::{store, Brdf, Budget, Integrator, Settings, Term};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (.ron), glTF model (.gltf, .glb) or built-in scene.
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Size to render at, overriding the scene's.
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Samples per pixel.
    #[arg(long, conflicts_with_all = ["seconds", "target_error"], value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub spp: Option<u32>,
    /// Render for about this long instead (whole passes of 4 samples per pixel).
    #[arg(long, conflicts_with = "target_error")]
    pub seconds: Option<f64>,
    /// Render until the pixels' relative standard error at `--percentile` reaches this (0.02:
    /// 2%); a 64-spp pilot predicts the samples needed, checked when they are taken.
    #[arg(long, value_name = "E")]
    pub target_error: Option<f64>,
    /// The percentile of pixels held to `--target-error` (100: the worst lit pixel).
    #[arg(long, default_value_t = 100.0, requires = "target_error")]
    pub percentile: f64,
    /// The most samples per pixel `--target-error` may take.
    #[arg(long, default_value_t = 65_536, requires = "target_error", value_parser = clap::value_parser!(u32).range(64..=1_000_000))]
    pub max_spp: u32,
    /// Find emitters by BRDF sampling only, not also by sampling them as lights: the slower
    /// estimator of the same image, to check the fast one against.
    #[arg(long)]
    pub no_emitter_sampling: bool,
    /// Terms: direct, ao, indirect_diffuse, indirect_specular, full (comma-separated).
    #[arg(long, default_value = "direct,ao")]
    pub terms: String,
    /// AO radius (world units).
    #[arg(long, default_value_t = 0.5)]
    pub ao_radius: f32,
    /// Weigh AO blockers by 1/(1 + d²), as SSAO's `ao.falloff`.
    #[arg(long)]
    pub ao_falloff: bool,
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Reflectance model: the shaders' Blinn-Phong, or Lambert for transport checks.
    #[arg(long, value_enum, default_value = "blinn-phong")]
    pub brdf: Brdf,
    /// The CPU reference's integrator for `full`: a pixel's paths 8 at a time in SIMD lanes
    /// (the default), or one at a time (the scalar oracle: the same image within noise).
    #[arg(long, value_enum)]
    pub integrator: Option<Integrator>,
    /// Folder for TERM.exr, TERM.variance.exr and reference.json.
    #[arg(long)]
    pub out: PathBuf,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Which renderer: the CPU path tracer, or the same integrator on the GPU
    /// (`pipelines/pathtrace.lbp`, ray queries; terms direct, ao, full).
    #[arg(long, value_enum, default_value = "cpu")]
    pub device: Device,
    /// With `--device gpu`: the path-tracing pipeline (default: `pipelines/pathtrace.lbp`,
    /// else the bundled copy).
    #[arg(long)]
    pub pipeline: Option<PathBuf>,
    /// With `--device gpu`: pick the adapter whose name contains this text.
    #[arg(long)]
    pub adapter: Option<String>,
    #[arg(long, value_enum)]
    pub backend: Option<crate::gpu::device::BackendChoice>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Device {
    Cpu,
    Gpu,
}

/// `a,b,c` as terms (each once).
pub fn parse_terms(text: &str) -> Result<Vec<Term>> {
    let mut out = vec![];
    for name in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let t = Term::from_name(name).ok_or_else(|| {
            Error::Usage(format!(
                "unknown reference term `{name}` (expected one of {})",
                Term::NAMES.join(", ")
            ))
        })?;
        if !out.contains(&t) {
            out.push(t);
        }
    }
    if out.is_empty() {
        return Err(Error::Usage("--terms names no term".into()));
    }
    Ok(out)
}

fn settings(a: &Args) -> Result<Settings> {
    let budget = match (a.spp, a.seconds, a.target_error) {
        (_, Some(t), _) if !(t.is_finite() && t > 0.0) => return Err(Error::Usage(format!("--seconds {t}: expected a positive number"))),
        (_, Some(t), _) => Budget::Seconds(t),
        (_, _, Some(e)) if !(e.is_finite() && e > 0.0) => {
            return Err(Error::Usage(format!("--target-error {e}: expected a positive number")))
        }
        (_, _, Some(_)) if !(a.percentile > 0.0 && a.percentile <= 100.0) => {
            return Err(Error::Usage(format!(
                "--percentile {}: expected a number in (0, 100]",
                a.percentile
            )))
        }
        (_, _, Some(target)) => Budget::Error {
            target,
            percentile: a.percentile,
            max_spp: a.max_spp,
        },
        (n, None, None) => Budget::Spp(n.unwrap_or(64)),
    };
    if !(a.ao_radius.is_finite() && a.ao_radius > 0.0) {
        return Err(Error::Usage(format!("--ao-radius {}: expected a positive number", a.ao_radius)));
    }
    Ok(Settings {
        budget,
        terms: parse_terms(&a.terms)?,
        ao_radius: a.ao_radius,
        ao_falloff: a.ao_falloff,
        seed: a.seed,
        brdf: a.brdf,
        sample_emitters: !a.no_emitter_sampling,
        integrator: a.integrator.unwrap_or_default(),
    })
}

fn execute(a: &Args) -> Result<()> {
    let s = settings(a)?;
    let gpu_only = [
        ("--pipeline", a.pipeline.is_some()),
        ("--adapter", a.adapter.is_some()),
        ("--backend", a.backend.is_some()),
    ];
    if let (Device::Cpu, Some((flag, _))) = (a.device, gpu_only.iter().find(|(_, given)| *given)) {
        return Err(Error::Usage(format!(
            "{flag} chooses how the GPU reference renders: it needs --device gpu"
        )));
    }
    if a.device == Device::Gpu && a.integrator.is_some() {
        return Err(Error::Usage(
            "--integrator chooses how the CPU reference renders: the GPU path tracer has one integrator".into(),
        ));
    }
    let size = a.size.as_deref().map(parse_size).transpose()?;
    let scene = crate::scene::load::load_sized(&a.scene, size, &[])?;
    let (r, fresh) = match a.device {
        Device::Cpu => store::cached(&scene, &s, &a.out, !a.quiet)?,
        Device::Gpu => on_gpu(a, &scene, &s)?,
    };
    let what = if fresh {
        "rendered"
    } else {
        "up to date (same scene and settings)"
    };
    eprintln!(
        "reference {what}: {} at {}x{}, {} spp, {} triangles ({} emitting), {:.2} s",
        scene.name, scene.size.0, scene.size.1, r.spp, r.triangles, r.emitters, r.seconds
    );
    if let Some(e) = r.reached {
        let verdict = if e.error <= e.target {
            "reached"
        } else {
            "NOT reached: --max-spp stopped it"
        };
        eprintln!(
            "  relative standard error at the {}th percentile of lit pixels: {:.4} (target {}: {verdict})",
            e.percentile, e.error, e.target
        );
    }
    for t in &r.terms {
        let n = (t.mean.width * t.mean.height) as f64;
        let mean: f64 = t.mean.rgba.chunks_exact(4).map(|p| (p[0] + p[1] + p[2]) as f64 / 3.0).sum::<f64>() / n;
        eprintln!(
            "  {}: {}  (mean {mean:.4})",
            t.term.name(),
            a.out.join(format!("{}.exr", t.term.name())).display()
        );
    }
    Ok(())
}

/// The reference rendered by the path-tracing pipeline on the GPU (or found in `--out`).
fn on_gpu(a: &Args, scene: &crate::scene::Scene, s: &Settings) -> Result<(crate::reference::Reference, bool)> {
    use crate::gpu_reference as gpu_ref;
    gpu_ref::check(scene, s)?;
    let (pipeline, ws) = gpu_ref::source(a.pipeline.as_deref())?;
    let gpu = crate::gpu::Gpu::new(&crate::gpu::DeviceOptions {
        backend: a.backend,
        adapter: a.adapter.clone(),
    })?;
    let device = store::Device::Gpu(gpu.info.name.clone());
    let tracer = gpu_ref::Tracer {
        ws: &ws,
        pipeline: &pipeline,
    };
    store::cached_on(scene, (s, &device), &a.out, || gpu_ref::render(&gpu, &tracer, scene, s, !a.quiet))
}

pub fn run(a: Args) -> i32 {
    match execute(&a) {
        Ok(()) => EXIT_OK,
        // Compile diagnostics are rendered already, and so are a scene's that did not load.
        Err(Error::Executor(crate::gpu::Error::Compile(report))) => {
            eprint!("{report}");
            EXIT_ERRORS
        }
        Err(Error::Scene(crate::scene::Error::Scene(msg))) if msg.is_empty() => EXIT_ERRORS,
        Err(e) => failed(e),
    }
}
