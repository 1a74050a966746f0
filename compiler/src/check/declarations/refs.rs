//! Names that refer to other declarations: each pass's conditions, reads, writes,
//! parameters and bindings, and per-light resources used by passes that iterate lights.

use super::unknown_resource;
use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::span::Spanned;

fn condition_refs(p: &Pipeline, c: &Spanned<Condition>, diags: &mut Diagnostics) {
    match &c.value {
        Condition::Toggle(name) => match p.param(name) {
            None => {
                let names: Vec<&str> = p.params.iter().map(|r| r.name.value.as_str()).collect();
                diags.push(
                    Diagnostic::error(Code::UnknownParam, format!("no parameter named `{}`", name.value), name.span)
                        .with_note(suggestion_note(name, &names)),
                );
            }
            Some(prm) if prm.ty.value != ParamType::Bool => diags.push(
                Diagnostic::error(
                    Code::ToggleNotBool,
                    format!("`{}` is a {} parameter; a toggle needs a Bool", name.value, prm.ty.name()),
                    name.span,
                )
                .with_secondary(prm.ty.span, "declared here"),
            ),
            _ => {}
        },
        Condition::Variant(v, o) => match p.variant(v) {
            None => {
                let names: Vec<&str> = p.variants.iter().map(|r| r.name.value.as_str()).collect();
                diags.push(
                    Diagnostic::error(Code::UnknownVariant, format!("no variant named `{}`", v.value), v.span)
                        .with_note(suggestion_note(v, &names)),
                );
            }
            Some(var) if var.option(o).is_none() => diags.push(
                Diagnostic::error(
                    Code::UnknownVariantOption,
                    format!("variant `{}` has no option `{}`", v.value, o.value),
                    o.span,
                )
                .with_note(suggestion_note(o, &var.option_names())),
            ),
            _ => {}
        },
        Condition::Not(c) | Condition::Named(_, c) => condition_refs(p, c, diags),
        Condition::All(cs) | Condition::Any(cs) => cs.iter().for_each(|c| condition_refs(p, c, diags)),
        _ => {}
    }
}

pub(super) fn idents(p: &Pipeline, diags: &mut Diagnostics) {
    for pass in &p.passes {
        if let Some(w) = &pass.when {
            condition_refs(p, w, diags);
        }
    }
}

pub(super) fn pass_refs(p: &Pipeline, pass: &Pass, diags: &mut Diagnostics) {
    reads(p, pass, diags);
    for w in &pass.writes {
        if p.resource(w).is_none() {
            diags.push(unknown_resource(p, w));
        }
    }
    for prm in &pass.params {
        if p.param(prm).is_none() {
            let names: Vec<&str> = p.params.iter().map(|r| r.name.value.as_str()).collect();
            diags.push(
                Diagnostic::error(Code::UnknownParam, format!("no parameter named `{}`", prm.value), prm.span)
                    .with_note(suggestion_note(prm, &names)),
            );
        }
    }
    binds(p, pass, diags);
    constants(p, pass, diags);
    if let PassKind::Compute(Compute { dispatch, .. }) = &pass.kind {
        if let Dispatch::Size(r) = &dispatch.value {
            if p.resource(r).and_then(|r| r.texture()).is_none() {
                diags.push(unknown_resource(p, r).with_note("`Size(..)` dispatches need a texture to size from"));
            }
        }
    }
    per_light(p, pass, diags);
}

/// A constant's parameter is a declared Int, Float or Bool; its variant and option exist.
fn constants(p: &Pipeline, pass: &Pass, diags: &mut Diagnostics) {
    for (_, c) in &pass.constants {
        match &c.value {
            Constant::Param(name) => match p.param(name) {
                None => {
                    let names: Vec<&str> = p.params.iter().map(|r| r.name.value.as_str()).collect();
                    diags.push(
                        Diagnostic::error(Code::UnknownParam, format!("no parameter named `{name}`"), c.span)
                            .with_note(suggestion_note(name, &names)),
                    );
                }
                Some(prm) if !matches!(prm.ty.value, ParamType::Int | ParamType::Float | ParamType::Bool) => diags.push(
                    Diagnostic::error(
                        Code::ConstantType,
                        format!("`{name}` is a {} parameter; a constant takes an Int, Float or Bool", prm.ty.name()),
                        c.span,
                    )
                    .with_secondary(prm.ty.span, "declared here"),
                ),
                _ => {}
            },
            Constant::Variant(v, o) => {
                let at = |s: &String| Spanned::new(s.clone(), c.span);
                condition_refs(p, &Spanned::new(Condition::Variant(at(v), at(o)), c.span), diags);
            }
            Constant::Number(_) | Constant::Bool(_) => {}
        }
    }
}

fn reads(p: &Pipeline, pass: &Pass, diags: &mut Diagnostics) {
    for r in &pass.reads {
        let name = r.name();
        match p.resource(name) {
            None => diags.push(unknown_resource(p, name)),
            Some(res) if r.is_prev() && !res.history() => diags.push(
                Diagnostic::error(
                    Code::NotHistory,
                    format!(
                        "`Prev(\"{}\")` reads the previous frame, but `{}` is not a history resource",
                        name.value, name.value
                    ),
                    name.span,
                )
                .with_secondary(res.span, "add `history: true` here"),
            ),
            _ => {}
        }
    }
}

fn binds(p: &Pipeline, pass: &Pass, diags: &mut Diagnostics) {
    for (_, target) in &pass.bind {
        if p.resource(target).is_none() && p.sampler(target).is_none() && target.value != "params" {
            let names: Vec<&str> = p
                .resources
                .iter()
                .map(|r| r.name.value.as_str())
                .chain(p.samplers.iter().map(|s| s.name.value.as_str()))
                .collect();
            diags.push(
                Diagnostic::error(
                    Code::UnknownResource,
                    format!("no resource or sampler named `{}`", target.value),
                    target.span,
                )
                .with_note(suggestion_note(target, &names)),
            );
        }
    }
}

/// A per-light pass touching a per-light resource uses the current light's instance, so
/// the pass may only iterate lights that have one; a pass that does not iterate lights
/// cannot use a per-light resource at all.
fn per_light(p: &Pipeline, pass: &Pass, diags: &mut Diagnostics) {
    if let Some(kinds) = &pass.per_light {
        super::resources::empty_kinds(kinds, diags);
    }
    for name in pass.touched() {
        let Some(rk) = p.resource(name).and_then(|r| r.per_light()) else {
            continue;
        };
        let d = match &pass.per_light {
            Some(kinds) => match kinds.iter().find(|k| !rk.contains(k)) {
                Some(k) => Diagnostic::error(
                    Code::PerLightMismatch,
                    format!(
                        "pass runs per {} light but `{}` has no instance for {} lights",
                        k.name(),
                        name.value,
                        k.name()
                    ),
                    name.span,
                )
                .with_secondary(rk.span, "instances exist for these kinds"),
                None => continue,
            },
            None => Diagnostic::error(
                Code::PerLightMismatch,
                format!(
                    "`{}` has one instance per light, but pass `{}` does not run per light",
                    name.value, pass.name.value
                ),
                name.span,
            )
            .with_secondary(rk.span, "per-light resource declared here")
            .with_note("add `per_light: [...]` to the pass"),
        };
        diags.push(d);
    }
}
