//! Command-line interface. Exit codes: 0 success, 1 errors in the input, 2 usage errors.

mod check;
mod convert;
mod diff;
pub mod plan;
pub mod progress;
mod reference;
mod render;
mod sweep;
mod verify;
mod view;

use crate::error::{Error, Result};
use clap::{Parser, Subcommand, ValueEnum};
use lightbench_compiler::profile::Profile;
use std::path::PathBuf;

pub const EXIT_OK: i32 = 0;
pub use crate::error::{EXIT_ERRORS, EXIT_USAGE};

#[derive(Parser, Debug)]
#[command(name = "lightbench", version, about = "Build, run and measure real-time lighting pipelines")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum DumpFormat {
    Exr,
    Png,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum Format {
    Human,
    Json,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Validate pipeline files and their shaders without a GPU (for CI).
    Check {
        /// Pipeline files or directories (every .ron/.lbp file below them).
        #[arg(required = true)]
        paths: Vec<PathBuf>,
        /// Diagnostic output: rustc-style text or one JSON object per line.
        #[arg(long, value_enum, default_value = "human")]
        format: Format,
        /// Offline capability profile to check against: webgpu, vulkan or gl.
        #[arg(long, default_value = "vulkan")]
        profile: String,
        /// Scene file or built-in scene whose lights and effects decide culling.
        #[arg(long)]
        scene: Option<String>,
        /// Shader root (default: `shaders/` beside or above the pipeline file).
        #[arg(long)]
        shaders: Option<PathBuf>,
        /// Check a parameter value against the pipelines that declare it (repeatable).
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
    },
    /// Print the Plan for one configuration: passes kept and culled, layouts, resources, memory.
    Plan(plan::Args),
    /// Render a pipeline on a scene with the GPU (headless) and save the output image.
    Render(render::Args),
    /// Render every configuration of pipelines on scenes and check every value of every
    /// resource is finite; names the first pass that produced a NaN or Inf.
    Verify(verify::Args),
    /// Compare two pipelines, or one in two configurations: Plan structure, the pixels of
    /// every shared resource, per-pass time; a report in markdown, HTML or JSON.
    Diff(diff::Args),
    /// Render reference images with a CPU path tracer (direct light with exact shadows, AO,
    /// one-bounce indirect diffuse, indirect specular, full global illumination) as EXR.
    Reference(reference::Args),
    /// What accuracy costs in time: render a pipeline over a grid of settings, time the
    /// effect's passes and measure its error against a reference; CSV, JSON, markdown and
    /// an SVG plot with the Pareto front. `sweep merge` joins shards.
    Sweep(sweep::Args),
    /// Open a window onto a running pipeline: any buffer, camera and light controls,
    /// parameters and variants, per-pass costs, screenshots.
    View(view::Args),
    /// Write the pipelines, shaders, scenes and sweep specs bundled in lightbench into a folder (a fresh
    /// one: nothing is overwritten) as the start of your own project.
    Init { dir: PathBuf },
    /// Scene utilities.
    #[command(subcommand)]
    Scene(SceneCommand),
    /// Convert a pipeline between RON and LBP without losing anything (comments are kept).
    Convert {
        input: PathBuf,
        /// Target format: ron or lbp.
        #[arg(long)]
        to: String,
        /// Output file (default: standard output).
        #[arg(short, long)]
        out: Option<PathBuf>,
    },
    /// Rewrite an .lbp pipeline in canonical layout (idempotent).
    Fmt {
        file: PathBuf,
        /// Do not write; exit 1 if the file is not formatted.
        #[arg(long)]
        check: bool,
    },
    /// Language server for pipeline, scene and shader files (LSP over stdin/stdout; an
    /// editor starts it).
    Lsp,
}

#[derive(Subcommand, Debug)]
pub enum SceneCommand {
    /// Write a built-in scene as glTF (NAME.gltf with NAME.bin beside it; .glb is not written).
    Export { name: String, out: PathBuf },
}

pub fn profile(name: &str) -> Result<Profile> {
    Profile::offline(name).map_err(Error::Usage)
}

pub fn run(cli: Cli) -> i32 {
    match cli.command {
        Command::Check {
            paths,
            format,
            profile,
            scene,
            shaders,
            params,
        } => check::run(&paths, format, &profile, scene.as_deref(), shaders.as_deref(), &params),
        Command::Plan(args) => plan::run(args),
        Command::Render(args) => render::run(args),
        Command::Verify(args) => verify::run(args),
        Command::Diff(args) => diff::run(args),
        Command::View(args) => view::run(args),
        Command::Reference(args) => reference::run(args),
        Command::Sweep(args) => sweep::run(args),
        Command::Init { dir } => match crate::bundled::init(&dir) {
            Ok(files) => {
                eprintln!(
                    "wrote {} files into {} (pipelines/, shaders/, scenes/, sweeps/); try: cd {} && lightbench render",
                    files.len(),
                    dir.display(),
                    dir.display()
                );
                EXIT_OK
            }
            Err(e) => failed(e),
        },
        Command::Convert { input, to, out } => convert::convert(&input, &to, out.as_deref()),
        Command::Fmt { file, check } => convert::fmt(&file, check),
        Command::Lsp => match crate::lsp::run() {
            Ok(()) => EXIT_OK,
            Err(e) => {
                eprintln!("error: lsp: {e}");
                EXIT_ERRORS
            }
        },
        Command::Scene(SceneCommand::Export { out, .. }) if out.extension().and_then(|e| e.to_str()) != Some("gltf") => {
            usage_error(format!(
                "{}: scene export writes .gltf (JSON, with its .bin beside it); name the file `.gltf`",
                out.display()
            ))
        }
        Command::Scene(SceneCommand::Export { name, out }) => match crate::scene::builtin::by_name(&name) {
            None => usage_error(format!(
                "unknown built-in scene `{name}` (expected one of {})",
                crate::scene::builtin::NAMES.join(", ")
            )),
            Some(scene) => match crate::scene::export::export(&scene, &out) {
                Ok(()) => {
                    eprintln!("wrote {}", out.display());
                    EXIT_OK
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    EXIT_ERRORS
                }
            },
        },
    }
}

/// `--variant NAME=OPTION` arguments; a name given twice is an error (which would win?).
pub fn parse_variants(args: &[String]) -> Result<Vec<(String, String)>> {
    parse_assignments("--variant", "NAME=OPTION", args)
}

/// `FLAG KEY=VALUE` arguments, each key once.
pub fn parse_assignments(flag: &str, form: &str, args: &[String]) -> Result<Vec<(String, String)>> {
    let mut out: Vec<(String, String)> = vec![];
    for v in args {
        let (k, val) = match v.split_once('=') {
            Some((k, val)) if !k.trim().is_empty() && !val.trim().is_empty() => (k.trim().to_string(), val.trim().to_string()),
            _ => return Err(Error::Usage(format!("invalid {flag} `{v}`: expected {form}"))),
        };
        if let Some((_, first)) = out.iter().find(|(name, _)| *name == k) {
            return Err(Error::Usage(format!("{flag} `{k}` is given twice (`{first}` and `{val}`)")));
        }
        out.push((k, val));
    }
    Ok(out)
}

/// Say a command's error and end with its category's exit code (`Error::exit_code`).
pub fn failed(e: Error) -> i32 {
    eprintln!("error: {e}");
    e.exit_code()
}

pub fn usage_error(msg: impl std::fmt::Display) -> i32 {
    eprintln!("error: {msg}");
    EXIT_USAGE
}

/// `--effect NAME` (render, view, verify, diff, sweep): effects added to those the scene
/// calls for, so that a model given on its own (which calls for shadows only) can run a
/// pipeline's effect passes.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct EffectArgs {
    /// Add an effect to the scene's (repeatable): Shadows, AmbientOcclusion, MultiViewAo, Ssr,
    /// IndirectDiffuse, IndirectSpecular, Bloom.
    #[arg(long = "effect", value_name = "NAME", value_parser = parse_effect)]
    pub effects: Vec<lightbench_compiler::ir::Effect>,
}

fn parse_effect(s: &str) -> std::result::Result<lightbench_compiler::ir::Effect, String> {
    use lightbench_compiler::ir::Effect;
    Effect::from_name(s.trim()).ok_or_else(|| {
        format!(
            "unknown effect `{s}`: {}",
            lightbench_compiler::diag::suggestion_note(s.trim(), &Effect::NAMES)
        )
    })
}
