//! Command-line interface. Exit codes: 0 success, 1 errors in the input, 2 usage errors.

mod check;
mod plan;

use clap::{Parser, Subcommand, ValueEnum};
use lightbench_compiler::profile::Profile;
use std::path::PathBuf;

pub const EXIT_OK: i32 = 0;
pub const EXIT_ERRORS: i32 = 1;
pub const EXIT_USAGE: i32 = 2;

#[derive(Parser, Debug)]
#[command(name = "lightbench", version, about = "Build, run and measure real-time lighting pipelines")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
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
        /// Scene file whose lights and effects decide culling.
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Shader root (default: `shaders/` beside or above the pipeline file).
        #[arg(long)]
        shaders: Option<PathBuf>,
    },
    /// Print the Plan for one configuration: passes kept and culled, layouts, resources, memory.
    Plan {
        file: PathBuf,
        /// Choose a variant option, e.g. --variant cube_shadow=multiview (repeatable).
        #[arg(long = "variant", value_name = "K=V")]
        variants: Vec<String>,
        #[arg(long)]
        scene: Option<PathBuf>,
        #[arg(long, default_value = "vulkan")]
        profile: String,
        /// Say why each variant option was chosen and each pass culled; show full layouts.
        #[arg(long)]
        explain: bool,
        /// Print a Graphviz graph instead.
        #[arg(long, conflicts_with_all = ["explain", "json"])]
        dot: bool,
        /// Print the Plan as JSON (what the runtime consumes).
        #[arg(long)]
        json: bool,
        /// Resolution for sizes and the memory estimate (default: the scene's, else 1280x720).
        #[arg(long, value_name = "WxH")]
        size: Option<String>,
        /// Lights per kind for the memory estimate when no scene is given, e.g. point=4,spot=2.
        #[arg(long, value_name = "KIND=N,...")]
        lights: Option<String>,
        #[arg(long)]
        shaders: Option<PathBuf>,
    },
}

pub fn profile(name: &str) -> Result<Profile, String> {
    Profile::offline(name)
}

pub fn run(cli: Cli) -> i32 {
    match cli.command {
        Command::Check {
            paths,
            format,
            profile,
            scene,
            shaders,
        } => check::run(&paths, format, &profile, scene.as_deref(), shaders.as_deref()),
        Command::Plan {
            file,
            variants,
            scene,
            profile,
            explain,
            dot,
            json,
            size,
            lights,
            shaders,
        } => plan::run(plan::Args {
            file,
            variants,
            scene,
            profile,
            explain,
            dot,
            json,
            size,
            lights,
            shaders,
        }),
    }
}

pub fn usage_error(msg: impl std::fmt::Display) -> i32 {
    eprintln!("error: {msg}");
    EXIT_USAGE
}
