//! `lightbench view`: open the viewer on a pipeline and a scene (optionally scripted).

use super::{failed, EXIT_ERRORS, EXIT_OK};
use crate::error::{Error, Result};
use crate::viewer::{Options, Step};
use lightbench_compiler::vfs;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Pipeline file; default `pipelines/deferred.ron`, or the bundled one when none is here.
    #[arg(long)]
    pub pipeline: Option<PathBuf>,
    /// Scene file (.ron), glTF model (.gltf, .glb) or built-in scene.
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    #[command(flatten)]
    pub effects: super::EffectArgs,
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    #[arg(long = "variant", value_name = "K=V")]
    pub variants: Vec<String>,
    #[arg(long)]
    pub shaders: Option<PathBuf>,
    /// Run these actions, one per line, then close: next-view, prev-view, next-slice,
    /// prev-slice, view NAME, light N, toggle-light, rotate-light YAW PITCH, move X Y Z,
    /// look YAW PITCH, param NAME=VALUE, variant NAME=OPTION, screenshot FILE,
    /// add-light Point|Spot|Directional, remove-light, effect NAME=true|false, trace on|off
    /// (the path-traced view), frames N.
    #[arg(long, value_name = "FILE")]
    pub script: Option<PathBuf>,
    /// Save a screenshot of the shown image to FILE after N frames, then close.
    #[arg(long, value_name = "N")]
    pub screenshot_after: Option<u32>,
    #[arg(long, value_name = "FILE", default_value = "lightbench-view.png")]
    pub screenshot: PathBuf,
}

/// The steps of `--script` (and `--screenshot-after`), each line's syntax checked before any
/// window opens; errors name `FILE:LINE`.
fn script(a: &Args) -> Result<Vec<Step>> {
    let mut steps = vec![];
    if let Some(f) = &a.script {
        // The guarded reader: a FIFO or /dev/zero named as a script is refused, not read.
        let text = vfs::read_bytes(f, vfs::MAX_FILE_BYTES)
            .and_then(vfs::utf8)
            .map_err(|e| Error::io(f, e))?;
        steps = crate::viewer::script::parse(&text, &f.display().to_string())?;
    }
    if let Some(n) = a.screenshot_after {
        steps.push(Step::Frames(n));
        steps.push(Step::Line(format!("screenshot {}", a.screenshot.display()), "--screenshot".into()));
    }
    Ok(steps)
}

fn execute(a: &Args) -> Result<()> {
    let variants = super::parse_variants(&a.variants)?;
    let steps = script(a)?;
    let (pipeline, workspace) = super::render::resolve_pipeline(a.pipeline.as_deref())?;
    let size = a.size.as_deref().map(super::plan::parse_size).transpose()?;
    let mut models = crate::scene::model_cache::ModelCache::keeping();
    let scene = crate::scene::load::load_sized_with(&a.scene, size, &a.effects.effects, &mut models)?;
    let opts = Options {
        workspace,
        pipeline,
        shaders: a.shaders.clone(),
        scene,
        scene_file: Some(std::path::PathBuf::from(&a.scene)).filter(|f| f.is_file()),
        effects: a.effects.effects.clone(),
        models,
        variants,
        // A script, even one of comments only, ends the viewer when it is done.
        scripted: a.script.is_some() || a.screenshot_after.is_some(),
    };
    crate::viewer::run(opts, steps)
}

pub fn run(a: Args) -> i32 {
    match execute(&a) {
        Ok(()) => EXIT_OK,
        Err(Error::Executor(crate::gpu::Error::Compile(report)) | Error::Scene(crate::scene::Error::Scene(report))) => {
            eprint!("{report}");
            EXIT_ERRORS
        }
        Err(e) => failed(e),
    }
}
