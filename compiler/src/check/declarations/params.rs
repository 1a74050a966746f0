//! Parameters: defaults within their ranges and finite, Enum values among the options, and
//! no name shared with a per-pass value (both are set as `NAME=VALUE`).

use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::span::Spanned;

pub(super) fn params(p: &Pipeline, diags: &mut Diagnostics) {
    for prm in &p.params {
        if let ParamType::Enum(opts) = &prm.ty.value {
            enum_values(prm, opts, diags);
        } else {
            range(prm, diags);
        }
        if prm.default.as_floats().iter().any(|v| !v.is_finite()) {
            diags.push(Diagnostic::error(
                Code::NonFinite,
                format!("default of `{}` is not finite", prm.name.value),
                prm.default.span,
            ));
        }
    }
    pass_value_names(p, diags);
}

/// A per-pass value is addressed as `PASS.KEY`; a parameter of that name would make
/// `--param PASS.KEY=...` mean two things.
fn pass_value_names(p: &Pipeline, diags: &mut Diagnostics) {
    for pass in &p.passes {
        for (key, _) in &pass.values {
            let name = format!("{}.{}", pass.name.value, key.value);
            if let Some(prm) = p.params.iter().find(|q| q.name.value == name) {
                diags.push(
                    Diagnostic::error(
                        Code::DuplicateName,
                        format!("per-pass value `{name}` has the name of a parameter"),
                        key.span,
                    )
                    .with_secondary(prm.name.span, "parameter declared here")
                    .with_note("`--param`, sweeps and diff sides address this value as `PASS.KEY`: rename the parameter, or list it under the pass's `params` instead of setting a value"),
                );
            }
        }
    }
}

fn range(prm: &Param, diags: &mut Diagnostics) {
    let floats = |bound: &Option<Spanned<ParamValue>>| bound.as_ref().map(|b| b.as_floats());
    if let (Some(lo), Some(hi), Some(min)) = (floats(&prm.min), floats(&prm.max), &prm.min) {
        if lo.iter().zip(&hi).any(|(a, b)| a > b) {
            diags.push(Diagnostic::error(
                Code::EmptyRange,
                format!("parameter `{}` has min greater than max", prm.name.value),
                min.span,
            ));
            return;
        }
    }
    if let Some((name, b)) = out_of_range(&prm.default, prm.min.as_ref().map(|m| &m.value), prm.max.as_ref().map(|m| &m.value)) {
        let side = if name == "min" { "below" } else { "above" };
        let bound_span = if name == "min" { &prm.min } else { &prm.max }
            .as_ref()
            .map(|b| b.span)
            .unwrap_or(prm.span);
        diags.push(
            Diagnostic::error(
                Code::DefaultOutOfRange,
                format!(
                    "default {} of `{}` is {side} its {name} {}",
                    prm.default.describe(),
                    prm.name.value,
                    b.describe()
                ),
                prm.default.span,
            )
            .with_secondary(bound_span, format!("{name} given here")),
        );
    }
}

fn enum_values(prm: &Param, opts: &[String], diags: &mut Diagnostics) {
    if opts.is_empty() {
        diags.push(Diagnostic::error(
            Code::EmptyEnum,
            format!("Enum parameter `{}` needs at least one option", prm.name.value),
            prm.ty.span,
        ));
        return;
    }
    let names: Vec<&str> = opts.iter().map(|o| o.as_str()).collect();
    for v in [Some(&prm.default), prm.min.as_ref(), prm.max.as_ref()].into_iter().flatten() {
        if let ParamValue::Enum(s) = &v.value {
            if !opts.contains(s) {
                diags.push(
                    Diagnostic::error(Code::UnknownValue, format!("`{s}` is not an option of this Enum"), v.span)
                        .with_note(suggestion_note(s, &names)),
                );
            }
        }
    }
}
