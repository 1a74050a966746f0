//! Stage `verify` (numerical stability): every configuration of a pipeline — variant options
//! one at a time or all combinations — on every scene, rendered for a few frames; every value
//! of every resource read back and checked to be finite. On a finding the configuration is
//! rendered again pass by pass to name the first pass that produced a non-finite value.

pub mod bisect;
pub mod scan;

use crate::error::Result;
use crate::gpu::{Executor, Gpu};
use crate::scene::Scene;
use bisect::Offender;
use lightbench_compiler::ir::ParamValue;
use scan::Bad;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Which variant configurations are checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum VariantMode {
    /// The defaults, then every option of every variant once (others at their default).
    Each,
    /// Every combination of options.
    All,
}

pub struct Options {
    pub frames: u32,
    /// The largest size rendered: scenes keep a smaller size of their own.
    pub max_size: Option<(u32, u32)>,
    pub variants: VariantMode,
    pub shaders: Option<PathBuf>,
    /// Parameter overrides (`NAME=VALUE`), checked against each configuration's Plan.
    pub params: Vec<(String, String)>,
    /// Compiled shader modules are shared by every configuration of the run.
    pub workspace: lightbench_compiler::Workspace,
}

/// What one configuration (pipeline × chosen options × scene) came to.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub pipeline: String,
    pub scene: String,
    /// The options the configuration ran (`variant=option`), after fallbacks.
    pub variants: Vec<String>,
    pub problem: Option<Problem>,
}

#[derive(Clone, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Problem {
    /// Resources holding non-finite values after the last frame, and the pass that first
    /// produced one.
    NonFinite { found: Vec<Bad>, first: Option<Offender> },
    /// The configuration could not be compiled or rendered.
    Failed(String),
}

/// The variant requests to compile: `each` or `all` of the pipeline's options.
pub fn requests(pipeline: &Path, mode: VariantMode) -> Vec<Vec<(String, String)>> {
    let mut s = lightbench_compiler::Session::new();
    let Some(p) = s.load_pipeline(pipeline) else {
        return vec![vec![]];
    };
    let options = |v: &lightbench_compiler::ir::Variant| -> Vec<(String, String)> {
        v.options.iter().map(|o| (v.name.value.clone(), o.name.value.clone())).collect()
    };
    match mode {
        VariantMode::Each => std::iter::once(vec![])
            .chain(p.variants.iter().flat_map(options).map(|c| vec![c]))
            .collect(),
        VariantMode::All => p.variants.iter().fold(vec![vec![]], |acc, v| {
            acc.iter()
                .flat_map(|prefix| {
                    options(v).into_iter().map(move |c| {
                        let mut next = prefix.clone();
                        next.push(c);
                        next
                    })
                })
                .collect()
        }),
    }
}

/// Every configuration of `pipeline` on one scene; configurations whose options fall back to
/// one already checked are checked once.
pub fn pipeline_on_scene(gpu: &Gpu, pipeline: &Path, (label, scene): (&str, &Scene), opts: &Options) -> Vec<Report> {
    let mut seen: Vec<Vec<String>> = vec![];
    let mut out = vec![];
    for req in requests(pipeline, opts.variants) {
        let report = |variants: Vec<String>, problem| Report {
            pipeline: pipeline.display().to_string(),
            scene: label.to_string(),
            variants,
            problem,
        };
        let asked: Vec<String> = req.iter().map(|(v, o)| format!("{v}={o}")).collect();
        let exe = match crate::render::compile_in(&opts.workspace, gpu, pipeline, opts.shaders.as_deref(), scene, &req) {
            Ok((exe, _)) => exe,
            Err(e) => {
                out.push(report(asked, Some(Problem::Failed(e.to_string()))));
                continue;
            }
        };
        let chosen: Vec<String> = exe.plan.variants.iter().map(|c| format!("{}={}", c.variant, c.option)).collect();
        if seen.contains(&chosen) {
            continue;
        }
        seen.push(chosen.clone());
        let problem =
            match crate::render::parse_params(&exe.plan, &opts.params).and_then(|p| configuration(gpu, &exe, scene, opts.frames, &p)) {
                Ok(p) => p,
                Err(e) => Some(Problem::Failed(e.to_string())),
            };
        out.push(report(chosen, problem));
    }
    out
}

/// Render `frames` frames (every pass every frame) and scan every resource.
pub fn configuration(
    gpu: &Gpu,
    exe: &lightbench_compiler::Executable,
    scene: &Scene,
    frames: u32,
    params: &[(String, ParamValue)],
) -> Result<Option<Problem>> {
    let mut ex = executor(gpu, exe, scene, params)?;
    for f in 0..frames.max(1) {
        let inputs = ex.inputs(f as f32 / 60.0);
        ex.render_frame(gpu, &inputs)?;
    }
    let found = scan::all(gpu, &ex)?;
    if found.is_empty() {
        return Ok(None);
    }
    let first = bisect::first_offender(gpu, exe, scene, frames, params)?;
    Ok(Some(Problem::NonFinite { found, first }))
}

/// An executor that runs every pass every frame, with the parameter overrides.
fn executor(gpu: &Gpu, exe: &lightbench_compiler::Executable, scene: &Scene, params: &[(String, ParamValue)]) -> Result<Executor> {
    let mut ex = Executor::new(gpu, exe, scene)?;
    ex.set_reuse(false);
    for (name, value) in params {
        ex.set_param(name, value.clone())?;
    }
    Ok(ex)
}

/// A scene as verify renders it: no larger than `max` each way.
pub fn capped(mut scene: Scene, max: Option<(u32, u32)>) -> Scene {
    if let Some((w, h)) = max {
        scene.size = (scene.size.0.min(w), scene.size.1.min(h));
    }
    scene
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `each`: the defaults, then every option once; `all`: every combination.
    #[test]
    fn variant_requests() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
        let each = requests(&p, VariantMode::Each);
        assert_eq!(each.len(), 1 + 3 + 2, "{each:?}");
        assert!(each[0].is_empty());
        assert!(each.contains(&vec![("cube_shadow".to_string(), "instanced".to_string())]));
        let all = requests(&p, VariantMode::All);
        assert_eq!(all.len(), 3 * 2, "{all:?}");
        assert!(all.iter().all(|r| r.len() == 2));
        assert!(all.contains(&vec![
            ("cube_shadow".to_string(), "multiview".to_string()),
            ("tonemap".to_string(), "simple".to_string())
        ]));
    }
}
