//! Stage `constants`: each kept pass's constants valued for the configuration (parameters
//! as planned, variants as chosen) and applied to its shaders as the GPU will apply them:
//! naga replaces the `override`s and validates again, so values that break a shader (an
//! array or workgroup size of 0, a value its type cannot hold) fail the Plan, located.

use super::*;
use crate::check::StageShader;
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::{Constant, Pass, Pipeline};
use naga::back::pipeline_constants::{process_overrides, PipelineConstantError};

/// A constant's value in this configuration.
pub fn value(p: &Pipeline, cfg: &Config, c: &Constant) -> f64 {
    match c {
        Constant::Number(x) => *x,
        Constant::Bool(b) => f64::from(u8::from(*b)),
        Constant::Param(name) => match p.param(name) {
            Some(prm) => match cfg.params.get(name).cloned().unwrap_or_else(|| cfg.default_of(p, prm).0) {
                ParamValue::Int(i) => i as f64,
                ParamValue::Float(f) => f,
                ParamValue::Bool(b) => f64::from(u8::from(b)),
                _ => 0.0,
            },
            None => 0.0,
        },
        Constant::Variant(v, o) => f64::from(u8::from(cfg.selection.chosen.get(v) == Some(o))),
    }
}

/// The pipeline-constant keys of a module's overrides: `@id(n)` as `"n"`, else the name.
fn key_of(o: &naga::Override) -> Option<String> {
    o.id.map(|id| id.to_string()).or_else(|| o.name.clone())
}

/// The constants a stage's module declares an `override` for, by pipeline-constant key.
fn stage_constants(p: &Pipeline, cfg: &Config, pass: &Pass, st: &StageShader) -> Vec<(String, f64)> {
    let overrides = &st.module.module.overrides;
    let mut out = vec![];
    for (name, c) in &pass.constants {
        let declared = overrides
            .iter()
            .find(|(_, o)| o.name.as_deref() == Some(name.value.as_str()) || key_of(o).as_deref() == Some(name.value.as_str()));
        if let Some(key) = declared.and_then(|(_, o)| key_of(o)) {
            out.push((key, value(p, cfg, &c.value)));
        }
    }
    out
}

/// Value every kept pass's constants per stage, and check the shaders with them.
pub(super) fn apply(p: &Pipeline, cfg: &Config, kept: &Kept, passes: &mut [PlanPass], diags: &mut Diagnostics) {
    for (valued, pp) in value_kept(p, cfg, kept, diags).into_iter().zip(passes.iter_mut()) {
        for (constants, ps) in valued.into_iter().zip(pp.stages.iter_mut()) {
            ps.constants = constants;
        }
    }
}

/// Each kept pass's constants per stage, checked by naga's override processing (what
/// fails is in `diags`).
pub(super) fn value_kept(p: &Pipeline, cfg: &Config, kept: &Kept, diags: &mut Diagnostics) -> Vec<Vec<Vec<(String, f64)>>> {
    let mut out = vec![];
    for (i, version) in kept {
        let pass = &p.passes[*i];
        let mut stages = vec![];
        for st in &version.stages {
            let constants = stage_constants(p, cfg, pass, st);
            if let Err(d) = check_stage((p, pass), st, &constants, cfg) {
                diags.push(d);
            }
            stages.push(constants);
        }
        out.push(stages);
    }
    out
}

/// naga's override processing for the stage's entry point, as the GPU will do it.
fn check_stage((p, pass): (&Pipeline, &Pass), st: &StageShader, constants: &[(String, f64)], cfg: &Config) -> Result<(), Diagnostic> {
    let m = &st.module;
    if m.module.overrides.is_empty() {
        return Ok(());
    }
    let key = (
        st.sref.entry.value.clone(),
        constants.iter().map(|(k, v)| (k.clone(), v.to_bits())).collect(),
    );
    if m.overrides_accepted.lock().is_ok_and(|set| set.contains(&key)) {
        return Ok(());
    }
    let map: naga::back::PipelineConstants = constants.iter().cloned().collect();
    let stage = st.stage.naga();
    let Err(e) = process_overrides(&m.module, &m.info, Some((stage, &st.sref.entry.value)), &map) else {
        if let Ok(mut set) = m.overrides_accepted.lock() {
            // A long-running process (viewer, language server) sees new sets as parameters
            // change: start afresh now and then rather than grow without bound.
            if set.len() >= 4096 {
                set.clear();
            }
            set.insert(key);
        }
        return Ok(());
    };
    let at = pass.constants.first().map_or(pass.name.span, |(k, _)| k.span);
    let shader = format!("`{}#{}`", st.sref.file.value, st.sref.entry.value);
    let (code, what) = match &e {
        PipelineConstantError::MissingValue(name) => (
            Code::ConstantMissing,
            format!(
                "`override {name}` of {shader} has no default and pass `{}` gives it no value",
                pass.name.value
            ),
        ),
        PipelineConstantError::SrcNeedsToBeFinite | PipelineConstantError::DstRangeTooSmall => (
            Code::ConstantType,
            format!(
                "a constant of pass `{}` does not fit its `override` in {shader}: {e}",
                pass.name.value
            ),
        ),
        _ => (
            Code::ConstantInvalid,
            format!("the constants of pass `{}` make {shader} invalid: {e}", pass.name.value),
        ),
    };
    let mut d = Diagnostic::error(code, what, at).with_note(configuration(cfg, p, pass));
    if let PipelineConstantError::ValidationError(v) = &e {
        for (span, label) in v.spans() {
            if let Some(s) = m.map_span(*span) {
                d = d.with_secondary(s, label.clone());
            }
        }
    }
    Err(d)
}

/// `whenever contact = full`: the options this Plan was made with, of the variants that decide
/// what the pass gets: named by it (its condition, its choices' arms, its constants), or whose
/// chosen option sets a parameter its constants read or substitutes its shader. The other
/// variants' choices do not matter here.
fn configuration(cfg: &Config, p: &Pipeline, pass: &Pass) -> String {
    let mut named = pass.when.as_ref().map(|w| w.value.variants()).unwrap_or_default();
    let mut read = std::collections::BTreeSet::new();
    for (_, c) in &pass.constants {
        match &c.value {
            Constant::Variant(v, _) => _ = named.insert(v.as_str()),
            Constant::Param(name) => _ = read.insert(name.as_str()),
            _ => {}
        }
    }
    let decides = |v: &str, o: &str| {
        let option = p.variants.iter().find(|x| x.name.value == v).and_then(|x| x.option(o));
        named.contains(v)
            || option.is_some_and(|o| {
                o.params.iter().any(|(n, _)| read.contains(n.value.as_str())) || o.shaders.iter().any(|(n, _)| n.value == pass.name.value)
            })
    };
    let chosen: Vec<String> = (cfg.selection.chosen.iter())
        .filter(|(v, o)| decides(v, o))
        .map(|(v, o)| format!("{v} = {o}"))
        .collect();
    if chosen.is_empty() {
        "in every configuration".into()
    } else {
        format!("whenever {}", chosen.join(", "))
    }
}
