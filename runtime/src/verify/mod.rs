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
    /// Only these variants change (the others stay at their default); empty: all of them.
    pub vary: Vec<String>,
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

/// The variant requests to compile: `each` or `all` of the pipeline's options, of the
/// variants in `vary` (all when empty).
pub fn requests(pipeline: &Path, mode: VariantMode, vary: &[String]) -> Vec<Vec<(String, String)>> {
    let mut s = lightbench_compiler::Session::new();
    let Some(p) = s.load_pipeline(pipeline) else {
        return vec![vec![]];
    };
    let options = |v: &lightbench_compiler::ir::Variant| -> Vec<(String, String)> {
        v.options.iter().map(|o| (v.name.value.clone(), o.name.value.clone())).collect()
    };
    let varied = p.variants.iter().filter(|v| vary.is_empty() || vary.contains(&v.name.value));
    match mode {
        VariantMode::Each => std::iter::once(vec![]).chain(varied.flat_map(options).map(|c| vec![c])).collect(),
        VariantMode::All => varied.fold(vec![vec![]], |acc, v| {
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

/// What a configuration runs, to tell configurations apart: its passes (shaders, targets,
/// blocks), resources and samplers, and the values of the parameters its passes read. Options
/// that only differ in culled passes or in parameters nothing reads plan alike.
fn plan_key(plan: &lightbench_compiler::plan::Plan) -> String {
    use lightbench_compiler::layout::FieldSource;
    let read: std::collections::BTreeSet<usize> = plan
        .passes
        .iter()
        .flat_map(|p| p.uniform_blocks.iter().flat_map(|b| b.fields.iter()))
        .filter_map(|f| match &f.source {
            FieldSource::Param(id) => Some(id.0 as usize),
            FieldSource::Fixed(_) => None,
        })
        .collect();
    let params: Vec<_> = read
        .iter()
        .filter_map(|&i| plan.params.get(i))
        .map(|p| (&p.name, &p.default))
        .collect();
    serde_json::to_string(&(&plan.passes, &plan.resources, &plan.samplers, params, plan.jitter)).unwrap_or_default()
}

/// Every configuration of `pipeline` on one scene; configurations that plan alike (their
/// options fall back to one already checked, or differ only where nothing runs) are checked
/// once.
pub fn pipeline_on_scene(gpu: &Gpu, pipeline: &Path, (label, scene): (&str, &Scene), opts: &Options) -> Vec<Report> {
    let mut seen = std::collections::HashSet::new();
    let mut out = vec![];
    // Pass pipelines compiled for one configuration serve the next (the driver's shader
    // compilation is most of a configuration's cost on lavapipe).
    let mut cache = crate::gpu::PipelineCache::default();
    for req in requests(pipeline, opts.variants, &opts.vary) {
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
        if !seen.insert(plan_key(&exe.plan)) {
            continue;
        }
        let problem = match crate::render::parse_params(&exe.plan, &opts.params)
            .map_err(crate::error::Error::from)
            .and_then(|p| configuration(gpu, &exe, scene, (opts.frames, &mut cache), &p))
        {
            Ok(p) => p,
            Err(e) => Some(Problem::Failed(e.to_string())),
        };
        out.push(report(chosen, problem));
    }
    out
}

/// Render `frames` frames (every pass every frame) and scan every resource.
/// Pipelines come from `cache` and go back to it.
pub fn configuration(
    gpu: &Gpu,
    exe: &lightbench_compiler::Executable,
    scene: &Scene,
    (frames, cache): (u32, &mut crate::gpu::PipelineCache),
    params: &[(String, ParamValue)],
) -> Result<Option<Problem>> {
    let mut ex = executor(gpu, exe, scene, params, std::mem::take(cache))?;
    for f in 0..frames.max(1) {
        let inputs = ex.inputs(f as f32 / 60.0);
        ex.render_frame(gpu, &inputs)?;
    }
    let found = scan::all(gpu, &ex)?;
    *cache = ex.take_cache();
    if found.is_empty() {
        return Ok(None);
    }
    let first = bisect::first_offender(gpu, exe, scene, frames, params)?;
    Ok(Some(Problem::NonFinite { found, first }))
}

/// An executor that runs every pass every frame, with the parameter overrides, starting from
/// the pipelines in `cache`.
fn executor(
    gpu: &Gpu,
    exe: &lightbench_compiler::Executable,
    scene: &Scene,
    params: &[(String, ParamValue)],
    cache: crate::gpu::PipelineCache,
) -> Result<Executor> {
    let mut ex = Executor::with_cache(gpu, exe, scene.clone(), cache)?;
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

    /// `each`: the defaults, then every option once; `all`: every combination; `vary` limits
    /// either to some variants.
    #[test]
    fn variant_requests() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
        let each = requests(&p, VariantMode::Each, &[]);
        // Defaults, then cube_shadow (4), shadows (2), gbuffer (2), lighting (4), tonemap (2),
        // transparency (3), aa (3), luminance (3), area_lights (5).
        assert_eq!(each.len(), 1 + 4 + 2 + 2 + 4 + 2 + 3 + 3 + 3 + 5, "{each:?}");
        assert!(each[0].is_empty());
        assert!(each.contains(&vec![("cube_shadow".to_string(), "instanced".to_string())]));
        let all = requests(&p, VariantMode::All, &[]);
        assert_eq!(all.len(), 4 * 2 * 2 * 4 * 2 * 3 * 3 * 3 * 5, "{all:?}");
        assert!(all.iter().all(|r| r.len() == 9));
        assert!(all.contains(&vec![
            ("cube_shadow".to_string(), "multiview".to_string()),
            ("shadows".to_string(), "rt".to_string()),
            ("gbuffer".to_string(), "fat".to_string()),
            ("lighting".to_string(), "deferred_volumes".to_string()),
            ("tonemap".to_string(), "simple".to_string()),
            ("transparency".to_string(), "fragment_lists".to_string()),
            ("aa".to_string(), "fxaa".to_string()),
            ("luminance".to_string(), "single".to_string()),
            ("area_lights".to_string(), "ltc".to_string())
        ]));
        // `--vary tonemap`: its options alone, cube shadows at their default.
        let varied = requests(&p, VariantMode::All, &["tonemap".to_string()]);
        assert_eq!(varied.len(), 2, "{varied:?}");
        assert!(varied.iter().all(|r| r.len() == 1 && r[0].0 == "tonemap"));
    }
}
