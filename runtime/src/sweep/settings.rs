//! Stage `settings` of `sweep`: every point's settings against the pipeline before anything
//! renders — names, variant options, parameter values (type, range, finiteness) and the
//! compared resource — each error located at what the spec wrote.

use super::spec::{Loaded, Point};
use crate::error::Result;
use lightbench_compiler::check::Checked;
use lightbench_compiler::plan::{declared_param, pass_value_params, ParamError, ParamValues, Plan, PlanParam};

/// Check every distinct setting of `points`. `plan` is the pipeline's default Plan for the
/// first scene (its culled passes count for `effect`); `checked` gives the declared
/// parameters, the per-pass values of every pass and the variants.
pub fn check(l: &Loaded, plan: &Plan, checked: &Checked, points: &[Point]) -> Result<()> {
    let mut settable: Vec<PlanParam> = checked.pipeline.params.iter().map(declared_param).collect();
    settable.extend(pass_value_params(checked));
    let mut seen: Vec<&(String, String)> = vec![];
    for kv in points.iter().flat_map(|p| &p.settings) {
        if seen.contains(&kv) {
            continue;
        }
        seen.push(kv);
        let (k, v) = kv;
        match checked.pipeline.variant(k) {
            Some(var) => option(l, (k, v), var)?,
            None => value(l, (k, v), &settable)?,
        }
    }
    for pass in &l.spec.effect {
        if !plan.passes.iter().any(|q| q.name == *pass) && !plan.culled.iter().any(|c| c.name == *pass) {
            return Err(l.error_in("effect", &format!("\"{pass}\""), format!("the pipeline has no pass `{pass}`")));
        }
    }
    compared(l, plan, checked, points)
}

/// A variant's option (`multiview!` as `multiview`) is one it declares.
fn option(l: &Loaded, (k, v): (&str, &str), var: &lightbench_compiler::ir::Variant) -> Result<()> {
    let option = v.strip_suffix('!').unwrap_or(v);
    if var.option(option).is_some() {
        return Ok(());
    }
    let hint = lightbench_compiler::diag::did_you_mean(option, var.option_names())
        .map(|m| format!("; did you mean `{m}`?"))
        .unwrap_or_default();
    Err(at_value(l, (k, v), format!("variant `{k}` has no option `{option}`{hint}")))
}

/// A parameter's (or per-pass value's) value parses as its type and lies in its range.
fn value(l: &Loaded, (k, v): (&str, &str), settable: &[PlanParam]) -> Result<()> {
    match ParamValues::parse_text(settable, k, v) {
        Ok(_) => Ok(()),
        Err(ParamError::Unknown { suggestion, .. }) => {
            let hint = suggestion.map(|m| format!("; did you mean `{m}`?")).unwrap_or_default();
            Err(l.error_at(
                &format!("\"{k}\""),
                format!("`{k}` is neither a parameter, a per-pass value nor a variant of the pipeline{hint}"),
            ))
        }
        Err(e) => Err(at_value(l, (k, v), e)),
    }
}

/// The compared resource is one the pipeline declares and, where the default Plan has it,
/// a texture (a buffer has no pixels to hold against the reference). A declared resource
/// the default Plan culls is checked in each point's configuration.
fn compared(l: &Loaded, plan: &Plan, checked: &Checked, points: &[Point]) -> Result<()> {
    for p in points {
        let why = if checked.pipeline.resource(&p.compare).is_none() {
            let names = checked.pipeline.resources.iter().map(|r| r.name.value.as_str());
            let hint = lightbench_compiler::diag::did_you_mean(&p.compare, names)
                .map(|m| format!("; did you mean `{m}`?"))
                .unwrap_or_default();
            format!("the pipeline has no resource `{}`{hint}", p.compare)
        } else if plan.resource(&p.compare).is_some_and(|r| r.is_buffer()) {
            format!("`{}` is a buffer: compare a texture with the reference", p.compare)
        } else {
            continue;
        };
        let needle = format!("\"{}\"", p.compare);
        return Err(if p.compare == l.spec.compare {
            l.error_in("compare", &needle, why)
        } else {
            l.error_at(&needle, why)
        });
    }
    Ok(())
}

/// An error at a setting's value as written after its key (any of the key's places: `set`,
/// a listed point, `grid`), else at the key.
fn at_value(l: &Loaded, (k, v): (&str, &str), msg: impl std::fmt::Display) -> crate::error::Error {
    let key = format!("\"{k}\"");
    let text = &l.text;
    let mut from = 0;
    while let Some(i) = text[from..].find(&key).map(|i| i + from) {
        let after = i + key.len();
        // The key's values end where the next key begins.
        let end = text[after..].find("\":").map_or(text.len(), |j| after + j);
        if let Some(j) = text[after..end].find(v) {
            return l.error_at_offset(after + j, msg);
        }
        from = after;
    }
    l.error_at(&key, msg)
}
