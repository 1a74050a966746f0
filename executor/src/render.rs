//! Compile a pipeline for a scene on a live device and render it: the path every command
//! and test that draws goes through.

use crate::error::{Error, Result};
use crate::{Executor, Gpu};
use lightbench_compiler::ir::ParamValue;
use lightbench_compiler::plan::ParamValues;
use lightbench_compiler::{Executable, Workspace};
use lightbench_scene::Scene;
use std::path::Path;

/// Compile `pipeline` for `scene` against the live adapter's capabilities, in `ws` (whose
/// compiled modules later compilations reuse). Warnings come back rendered as `lightbench
/// check` shows them; errors as `Error::Compile`.
pub fn compile_in(
    ws: &Workspace,
    gpu: &Gpu,
    pipeline: &Path,
    shader_root: Option<&Path>,
    scene: &Scene,
    variants: &[(String, String)],
) -> Result<(Executable, String)> {
    compile_with(ws, gpu, (pipeline, shader_root), scene, variants, &ParamValues::new())
}

/// `compile_in` with parameter overrides, which size resources declared `size: Param(..)`.
pub fn compile_with(
    ws: &Workspace,
    gpu: &Gpu,
    (pipeline, shader_root): (&Path, Option<&Path>),
    scene: &Scene,
    variants: &[(String, String)],
    params: &ParamValues,
) -> Result<(Executable, String)> {
    let mut s = ws.session();
    let features = scene.features();
    let exe = s.executable_with(pipeline, shader_root, (&gpu.profile, &features), variants, params);
    let report = s.render();
    match exe {
        Some(e) => Ok((e, report)),
        None if report.is_empty() => Err(Error::Compile(format!("{}: could not be compiled", pipeline.display()))),
        None => Err(request_error(&s).unwrap_or(Error::Compile(report))),
    }
}

/// A compilation that failed only because variants or options were asked for that the
/// pipeline does not have: `Error::Variant`, a message each.
pub fn request_error(s: &lightbench_compiler::Session) -> Option<Error> {
    use lightbench_compiler::diag::{Code, Severity};
    let errors: Vec<_> = s.diags.list.iter().filter(|d| d.severity == Severity::Error).collect();
    let requested = |d: &&lightbench_compiler::diag::Diagnostic| {
        d.labels.is_empty() && matches!(d.code, Code::UnknownVariant | Code::UnknownVariantOption)
    };
    if errors.is_empty() || !errors.iter().all(requested) {
        return None;
    }
    let lines: Vec<String> = errors
        .iter()
        .map(|d| {
            std::iter::once(d.message.clone())
                .chain(d.notes.iter().cloned())
                .collect::<Vec<_>>()
                .join("; ")
        })
        .collect();
    Some(Error::Variant(lines))
}

/// `compile_in` a workspace of its own, reading the disk.
pub fn compile(
    gpu: &Gpu,
    pipeline: &Path,
    shader_root: Option<&Path>,
    scene: &Scene,
    variants: &[(String, String)],
) -> Result<(Executable, String)> {
    compile_in(&Workspace::disk(), gpu, pipeline, shader_root, scene, variants)
}

/// A pipeline planned in one configuration.
pub struct Configured {
    pub exe: Executable,
    /// The parameter overrides among the settings, typed.
    pub params: Vec<(String, ParamValue)>,
    /// Warnings, rendered as `lightbench check` shows them.
    pub warnings: String,
}

/// Plan `pipeline` for `scene` against `profile` with `settings` (`key=value`): a key naming
/// one of the pipeline's variants chooses its option, any other is a parameter (which may
/// size resources, so the pipeline is planned again with them). Errors come back rendered,
/// as `Error::Compile`.
pub fn plan_configured(
    ws: &Workspace,
    (pipeline, shader_root): (&Path, Option<&Path>),
    (profile, scene): (&lightbench_compiler::profile::Profile, &Scene),
    settings: &[(String, String)],
) -> Result<Configured> {
    let features = scene.features();
    let compile = |variants: &[(String, String)], params: &ParamValues| {
        let mut s = ws.session();
        let exe = s.executable_with(pipeline, shader_root, (profile, &features), variants, params);
        let report = s.render();
        exe.map(|e| (e, report.clone()))
            .ok_or_else(|| request_error(&s).unwrap_or(Error::Compile(report)))
    };
    let (first, _) = compile(&[], &ParamValues::new())?;
    let (variants, params): (Vec<_>, Vec<_>) = settings
        .iter()
        .cloned()
        .partition(|(k, _)| first.plan.variants.iter().any(|v| v.variant == *k));
    let parsed = parse_params(&first.plan, &params)?;
    let values = param_values(&first.plan, &parsed)?;
    let (exe, warnings) = compile(&variants, &values)?;
    Ok(Configured {
        exe,
        params: parsed,
        warnings,
    })
}

/// Build an executor and render `frames` frames (time advancing 1/60 s per frame).
pub fn render(gpu: &Gpu, exe: &Executable, scene: &Scene, frames: u32) -> Result<Executor> {
    render_with(gpu, exe, scene, frames, &[])
}

/// `render` with parameter overrides (each checked against the Plan's parameters).
pub fn render_with(gpu: &Gpu, exe: &Executable, scene: &Scene, frames: u32, params: &[(String, ParamValue)]) -> Result<Executor> {
    render_scene(gpu, exe, scene.clone(), (frames, true, false), params, &[])
}

/// `render_with` taking the scene, whose textures are dropped once on the GPU, with external
/// resources filled from files (`(name, file)`), and with reuse and aliasing of transient
/// memory as asked.
pub fn render_scene(
    gpu: &Gpu,
    exe: &Executable,
    scene: Scene,
    (frames, reuse, alias): (u32, bool, bool),
    params: &[(String, ParamValue)],
    inputs: &[(String, std::path::PathBuf)],
) -> Result<Executor> {
    let mut ex = Executor::with_scene(gpu, exe, scene)?;
    ex.log_timings = true;
    ex.set_reuse(reuse);
    if alias {
        ex.set_aliasing(gpu, exe, true)?;
    }
    for (name, value) in params {
        ex.set_param(name, value.clone())?;
    }
    for (name, file) in inputs {
        ex.load_input(gpu, name, file)?;
    }
    for f in 0..frames.max(1) {
        let inputs = ex.inputs(f as f32 / 60.0);
        ex.render_frame(gpu, &inputs)?;
    }
    Ok(ex)
}

/// Parsed parameter values as overrides (for planning: sizes may depend on them).
pub fn param_values(plan: &lightbench_compiler::plan::Plan, parsed: &[(String, ParamValue)]) -> Result<ParamValues> {
    let mut v = ParamValues::new();
    for (name, value) in parsed {
        v.set(&plan.params, name, value.clone())?;
    }
    Ok(v)
}

/// Parameter values written as text (`NAME`, `VALUE`) as typed values of the Plan's
/// parameters: `Error::Param` for an unknown name (with the nearest one) or a value of the
/// wrong type or outside the range.
pub fn parse_params(plan: &lightbench_compiler::plan::Plan, args: &[(String, String)]) -> Result<Vec<(String, ParamValue)>> {
    let mut out = vec![];
    for (name, text) in args {
        out.push((name.clone(), ParamValues::parse_text(&plan.params, name, text)?));
    }
    Ok(out)
}
