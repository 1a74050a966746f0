//! `lightbench diff A B`: parse the sides and options, plan both (without a GPU for
//! `--no-render`), run `crate::diff`, write the report, and exit by `--fail-above`.

use super::plan::parse_size;
use super::{failed, EXIT_ERRORS, EXIT_OK};
use crate::diff::{self, report, spec, Metric, Options, Planned};
use crate::error::{Error, Result};
use crate::gpu::{DeviceOptions, Gpu};
use crate::scene::Scene;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::Workspace;
use std::path::PathBuf;

#[derive(Clone, Copy, Debug, clap::ValueEnum, PartialEq, Eq)]
pub enum ReportFormat {
    Md,
    Html,
    Json,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// First side: a pipeline file, optionally `@variant=option,param=value,...`.
    pub a: String,
    /// Second side, as the first (often the same file with other settings).
    pub b: String,
    /// Scene file (.ron), glTF model or built-in scene both sides render.
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    #[command(flatten)]
    pub effects: super::EffectArgs,
    /// Size to render at, overriding the scene's.
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Frames timed per side after a warm-up frame (interleaved A, B, A, B…).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub frames: u32,
    /// Resources to compare besides the output: `all` or NAME,NAME...
    #[arg(long, default_value = "all")]
    pub resources: String,
    /// Folder for the report and its images.
    #[arg(long, default_value = "lightbench-diff")]
    pub out: PathBuf,
    /// Report written to the folder (and printed, but for HTML).
    #[arg(long, value_enum, default_value = "md")]
    pub format: ReportFormat,
    /// Exit 1 when B crosses a limit: flip, rmse, max (of the output), time, memory (B/A).
    #[arg(long, value_name = "METRIC=VALUE,...")]
    pub fail_above: Option<String>,
    /// Compare structure only (no GPU adapter needed), against `--profile`.
    #[arg(long)]
    pub no_render: bool,
    /// Offline profile for `--no-render`: webgpu, vulkan or gl.
    #[arg(long, default_value = "vulkan")]
    pub profile: String,
    #[arg(long)]
    pub shaders: Option<PathBuf>,
    #[arg(long, value_enum)]
    pub backend: Option<crate::gpu::device::BackendChoice>,
    #[arg(long)]
    pub adapter: Option<String>,
}

fn parse_limits(text: Option<&str>, render: bool) -> Result<Vec<(Metric, f64)>> {
    let mut out = vec![];
    for part in text.into_iter().flat_map(|t| t.split(',')).filter(|p| !p.trim().is_empty()) {
        let bad = || {
            Error::Usage(format!(
                "--fail-above `{part}`: expected METRIC=NUMBER, METRIC one of {}",
                Metric::NAMES.join(", ")
            ))
        };
        let (m, v) = part.split_once('=').ok_or_else(bad)?;
        let metric = Metric::from_name(m.trim()).ok_or_else(bad)?;
        let limit: f64 = v.trim().parse().ok().filter(|x: &f64| x.is_finite()).ok_or_else(bad)?;
        if metric.rendered() && !render {
            return Err(Error::Usage(format!(
                "--fail-above {}: needs rendering (drop --no-render)",
                metric.name()
            )));
        }
        out.push((metric, limit));
    }
    Ok(out)
}

/// Plan one side in its configuration (see `render::plan_configured`), its diagnostics shown.
fn plan_side(ws: &Workspace, side: spec::Side, a: &Args, (profile, scene): (&Profile, &Scene)) -> Result<Planned> {
    if !side.pipeline.is_file() {
        return Err(Error::Usage(format!("no such pipeline file: {}", side.pipeline.display())));
    }
    match crate::render::plan_configured(ws, (&side.pipeline, a.shaders.as_deref()), (profile, scene), &side.settings).map_err(Error::from)
    {
        Ok(c) => {
            eprint!("{}", c.warnings);
            Ok(Planned {
                side,
                exe: c.exe,
                params: c.params,
            })
        }
        Err(Error::Executor(crate::gpu::Error::Compile(report))) => {
            eprint!("{report}");
            Err(Error::compile(String::new()))
        }
        Err(e) => Err(e),
    }
}

fn write_report(a: &Args, r: &diff::Report) -> Result<()> {
    std::fs::create_dir_all(&a.out).map_err(|e| Error::io(&a.out, e))?;
    let (name, text) = match a.format {
        ReportFormat::Md => ("report.md", report::markdown(r)),
        ReportFormat::Json => ("report.json", report::json(r)),
        ReportFormat::Html => ("report.html", report::html(r, &a.out)?),
    };
    let path = a.out.join(name);
    crate::io::write_atomic(&path, text.as_bytes())?;
    match a.format {
        ReportFormat::Html => eprintln!("wrote {}", path.display()),
        _ => print!("{text}"),
    }
    Ok(())
}

fn execute(a: &Args) -> Result<bool> {
    let (sa, sb) = (spec::parse(&a.a)?, spec::parse(&a.b)?);
    let limits = parse_limits(a.fail_above.as_deref(), !a.no_render)?;
    let resources = match a.resources.as_str() {
        "all" => None,
        list => Some(list.split(',').map(|s| s.trim().to_string()).filter(|s| !s.is_empty()).collect()),
    };
    let size = a.size.as_deref().map(parse_size).transpose()?;
    let scene = crate::scene::load::load_sized(&a.scene, size, &a.effects.effects)?;
    let ws = Workspace::disk();
    let report = if a.no_render {
        let profile = super::profile(&a.profile)?;
        let (pa, pb) = (
            plan_side(&ws, sa, a, (&profile, &scene))?,
            plan_side(&ws, sb, a, (&profile, &scene))?,
        );
        let mut r = diff::structure(&pa, &pb, &scene.name, scene.size);
        r.thresholds = diff::thresholds(&r, &limits);
        r
    } else {
        let gpu = Gpu::new(&DeviceOptions {
            backend: a.backend,
            adapter: a.adapter.clone(),
        })?;
        eprintln!("{}", gpu.describe());
        let (pa, pb) = (
            plan_side(&ws, sa, a, (&gpu.profile, &scene))?,
            plan_side(&ws, sb, a, (&gpu.profile, &scene))?,
        );
        let opts = Options {
            frames: a.frames,
            resources,
            out: a.out.clone(),
            fail_above: limits,
        };
        diff::run(&gpu, (&pa, &pb), &scene, &opts)?
    };
    write_report(a, &report)?;
    Ok(report.thresholds.iter().any(|t| t.crossed))
}

pub fn run(a: Args) -> i32 {
    match execute(&a) {
        Ok(false) => EXIT_OK,
        Ok(true) => {
            eprintln!("error: a --fail-above limit was crossed");
            EXIT_ERRORS
        }
        // Compile and scene diagnostics were printed as they came.
        Err(Error::Executor(crate::gpu::Error::Compile(_)) | Error::Scene(crate::scene::Error::Scene(_))) => EXIT_ERRORS,
        Err(e) => failed(e),
    }
}
