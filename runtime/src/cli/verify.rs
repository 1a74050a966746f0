//! `lightbench verify`: numerical stability of pipelines over scenes (see `crate::verify`).

use super::{usage_error, Format, EXIT_ERRORS, EXIT_OK};
use crate::error::{Error, Result};
use crate::gpu::{DeviceOptions, Gpu};
use crate::verify::{self, Options, Problem, Report, VariantMode};
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Pipeline files or directories (every .ron/.lbp below them). Default: `pipelines/`.
    pub paths: Vec<PathBuf>,
    /// Scene files, directories of scene files, built-in names or glTF models. Default: the
    /// hard-case suite `scenes/hard/`.
    #[arg(long, num_args = 1..)]
    pub scenes: Vec<String>,
    #[command(flatten)]
    pub effects: super::EffectArgs,
    /// `each`: the defaults and every variant option once; `all`: every combination.
    #[arg(long, value_enum, default_value = "each")]
    pub variants: VariantMode,
    /// Only these variants change, comma-separated (the others stay at their default): keeps
    /// `--variants all` to the combinations that matter.
    #[arg(long, value_delimiter = ',', value_name = "VARIANT,...")]
    pub vary: Vec<String>,
    /// Frames rendered per configuration (history resources need more than one).
    #[arg(long, default_value_t = 3)]
    pub frames: u32,
    /// The largest size rendered, WxH (scenes keep a smaller size of their own).
    #[arg(long)]
    pub size: Option<String>,
    #[arg(long, value_enum, default_value = "human")]
    pub format: Format,
    /// Shader root (default: `shaders/` beside or above each pipeline file).
    #[arg(long)]
    pub shaders: Option<PathBuf>,
    /// Override a pipeline parameter in every configuration (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    #[arg(long, value_enum)]
    pub backend: Option<crate::gpu::device::BackendChoice>,
    #[arg(long)]
    pub adapter: Option<String>,
}

pub fn run(a: Args) -> i32 {
    if a.frames == 0 {
        return usage_error("--frames must be at least 1");
    }
    let max_size = match a.size.as_deref().map(super::plan::parse_size).transpose() {
        Ok(s) => s,
        Err(e) => return usage_error(e),
    };
    let (pipelines, scenes) = match (pipelines(&a.paths), scene_specs(&a.scenes)) {
        (Ok(p), Ok(s)) => (p, s),
        (Err(e), _) | (_, Err(e)) => return usage_error(e),
    };
    let params = match super::parse_assignments("--param", "NAME=VALUE", &a.params) {
        Ok(p) => p,
        Err(e) => return usage_error(e),
    };
    if let Err(e) = check_vary(&pipelines, &a.vary) {
        return usage_error(e);
    }
    let opts = Options {
        frames: a.frames,
        max_size,
        variants: a.variants,
        vary: a.vary.clone(),
        shaders: a.shaders.clone(),
        params,
        workspace: lightbench_compiler::Workspace::disk(),
    };
    match execute(&a, &pipelines, &scenes, &opts) {
        Ok(reports) => summarize(&reports, a.format),
        Err(e) => {
            eprintln!("error: {e}");
            EXIT_ERRORS
        }
    }
}

/// Every `--vary` name is a variant of some pipeline checked (a typo would vary nothing).
fn check_vary(pipelines: &[PathBuf], vary: &[String]) -> std::result::Result<(), String> {
    let names: Vec<String> = pipelines
        .iter()
        .filter_map(|p| lightbench_compiler::Session::new().load_pipeline(p))
        .flat_map(|p| p.variants.into_iter().map(|v| v.name.value))
        .collect();
    match vary.iter().find(|v| !names.contains(v)) {
        Some(v) => {
            let hint = lightbench_compiler::diag::did_you_mean(v, names.iter().map(String::as_str))
                .map(|m| format!(" (did you mean `{m}`?)"))
                .unwrap_or_default();
            Err(format!("--vary `{v}`: no checked pipeline has this variant{hint}"))
        }
        None => Ok(()),
    }
}

fn execute(a: &Args, pipelines: &[PathBuf], scenes: &[String], opts: &Options) -> Result<Vec<Report>> {
    let gpu = Gpu::new(&DeviceOptions {
        backend: a.backend,
        adapter: a.adapter.clone(),
    })?;
    eprintln!("{}", gpu.describe());
    let bar = indicatif::ProgressBar::new((pipelines.len() * scenes.len()) as u64);
    if a.format == Format::Json {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let mut reports = vec![];
    // JSON lines as each configuration ends, failed ones included.
    let add = |found: Vec<Report>, reports: &mut Vec<Report>| -> Result<()> {
        if a.format == Format::Json {
            for r in &found {
                println!("{}", serde_json::to_string(r).map_err(|e| Error::resource(e.to_string()))?);
            }
        }
        reports.extend(found);
        Ok(())
    };
    for spec in scenes {
        let scene = match crate::scene::load(spec) {
            Ok(mut s) => {
                s.effects.extend(a.effects.effects.iter().copied());
                verify::capped(s, opts.max_size)
            }
            Err(e) => {
                bar.inc(pipelines.len() as u64);
                add(pipelines.iter().map(|p| failed(p, spec, e.to_string())).collect(), &mut reports)?;
                continue;
            }
        };
        for p in pipelines {
            bar.set_message(format!("{} × {spec}", p.display()));
            add(verify::pipeline_on_scene(&gpu, p, (spec, &scene), opts), &mut reports)?;
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    Ok(reports)
}

fn failed(pipeline: &Path, scene: &str, why: String) -> Report {
    Report {
        pipeline: pipeline.display().to_string(),
        scene: scene.to_string(),
        variants: vec![],
        problem: Some(Problem::Failed(why)),
    }
}

/// Findings as text (JSON lines were printed as they came), then the totals; exit 1 on any.
fn summarize(reports: &[Report], format: Format) -> i32 {
    let bad: Vec<&Report> = reports.iter().filter(|r| r.problem.is_some()).collect();
    if format == Format::Human {
        for r in &bad {
            print!("{}", describe(r));
        }
    }
    let line = format!("verified {} configuration(s): {} with problems", reports.len(), bad.len());
    if format == Format::Json {
        println!(
            "{}",
            serde_json::json!({"summary": {"configurations": reports.len(), "problems": bad.len()}})
        );
    } else {
        println!("{line}");
    }
    if bad.is_empty() {
        EXIT_OK
    } else {
        EXIT_ERRORS
    }
}

fn describe(r: &Report) -> String {
    let mut s = format!("{} [{}] × {}\n", r.pipeline, r.variants.join(", "), r.scene);
    match &r.problem {
        Some(Problem::Failed(why)) => s += &format!("  failed: {}\n", why.trim_end().replace('\n', "\n    ")),
        Some(Problem::NonFinite { found, first }) => {
            for b in found {
                s += &format!(
                    "  {} `{}`{}: {} at {} ({} value(s))\n",
                    kind(&b.kind),
                    b.resource,
                    place(&b.place),
                    b.value,
                    at(&b.at),
                    b.count
                );
            }
            match first {
                Some(o) => {
                    s += &format!(
                        "  first produced by pass `{}` in frame {}: `{}`{} = {} at {}\n",
                        o.pass,
                        o.frame,
                        o.output.resource,
                        place(&o.output.place),
                        o.output.value,
                        at(&o.output.at)
                    );
                    for (name, v) in &o.inputs {
                        s += &format!("    it read `{name}` = {v}\n");
                    }
                }
                None => s += "  no pass's output was non-finite when rendered pass by pass\n",
            }
        }
        None => {}
    }
    s
}

fn kind(k: &verify::scan::Kind) -> String {
    match k {
        verify::scan::Kind::NonFinite => "non-finite".into(),
        verify::scan::Kind::OutOfRange { min, max } => format!("out of range {min}..{max}"),
    }
}

fn place(p: &str) -> String {
    if p.is_empty() {
        String::new()
    } else {
        format!(" ({p})")
    }
}

fn at(a: &verify::scan::At) -> String {
    match a {
        verify::scan::At::Pixel { x, y, channel } => format!("pixel ({x}, {y}) channel {channel}"),
        verify::scan::At::Word(i) => format!("word {i}"),
    }
}

/// Pipeline files from paths (default `pipelines/`).
fn pipelines(paths: &[PathBuf]) -> std::result::Result<Vec<PathBuf>, String> {
    let paths = if paths.is_empty() {
        vec![PathBuf::from("pipelines")]
    } else {
        paths.to_vec()
    };
    let mut out = vec![];
    for p in &paths {
        let found = lightbench_compiler::pipeline_files(p).map_err(|e| format!("{}: {e}", p.display()))?;
        if found.is_empty() {
            return Err(format!("{}: no pipeline files (.ron or .lbp)", p.display()));
        }
        out.extend(found);
    }
    Ok(out)
}

/// Scene specs: directories expand to their scene files (`.ron`), sorted.
fn scene_specs(specs: &[String]) -> std::result::Result<Vec<String>, String> {
    let default = if Path::new("scenes/hard").is_dir() {
        "scenes/hard"
    } else {
        "cornell"
    };
    let specs = if specs.is_empty() {
        vec![default.to_string()]
    } else {
        specs.to_vec()
    };
    let mut out = vec![];
    for s in specs {
        let p = Path::new(&s);
        if !p.is_dir() {
            out.push(s);
            continue;
        }
        let mut files: Vec<String> = std::fs::read_dir(p)
            .map_err(|e| format!("{s}: {e}"))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|f| f.extension().is_some_and(|x| x == "ron"))
            .map(|f| f.display().to_string())
            .collect();
        if files.is_empty() {
            return Err(format!("{s}: no scene files (.ron)"));
        }
        files.sort();
        out.extend(files);
    }
    Ok(out)
}
