//! Presets: the parameter values a variant option sets are declared parameters, fit their
//! types and ranges, and no parameter is set by the options of two variants (which would
//! make the value depend on the order variants are chosen in).

use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::span::Spanned;
use std::collections::BTreeMap;

pub(super) fn presets(p: &Pipeline, diags: &mut Diagnostics) {
    // Parameter -> the first variant setting it, and where.
    let mut setters: BTreeMap<&str, (&str, &Spanned<String>)> = BTreeMap::new();
    for v in &p.variants {
        for o in &v.options {
            for (name, lit) in &o.params {
                value(p, name, lit, diags);
                match setters.get(name.value.as_str()) {
                    Some((other, first)) if *other != v.name.value => diags.push(
                        Diagnostic::error(
                            Code::PresetOverlap,
                            format!("`{}` is set by options of variants `{other}` and `{}`", name.value, v.name.value),
                            name.span,
                        )
                        .with_secondary(first.span, format!("set by variant `{other}` here")),
                    ),
                    Some(_) => {}
                    None => {
                        setters.insert(&name.value, (&v.name.value, name));
                    }
                }
            }
        }
    }
}

/// The value a preset gives a parameter (`None`: not a parameter or not of its type).
pub fn preset_value(p: &Pipeline, name: &str, lit: &Literal) -> Option<ParamValue> {
    p.param(name)?.ty.value.value_of(lit.clone()).ok()
}

fn value(p: &Pipeline, name: &Spanned<String>, lit: &Spanned<Literal>, diags: &mut Diagnostics) {
    let Some(prm) = p.param(&name.value) else {
        let names: Vec<&str> = p.params.iter().map(|q| q.name.value.as_str()).collect();
        diags.push(
            Diagnostic::error(Code::UnknownParam, format!("no parameter named `{}`", name.value), name.span)
                .with_note(suggestion_note(name, &names)),
        );
        return;
    };
    let v = match prm.ty.value.value_of(lit.value.clone()) {
        Ok(v) => v,
        Err(e) => {
            let d = Diagnostic::error(e.code, format!("`{}`: {}", name.value, e.message), lit.span);
            diags.push(match e.note {
                Some(n) => d.with_note(n),
                None => d,
            });
            return;
        }
    };
    let bad = match (&prm.ty.value, &v) {
        (ParamType::Enum(opts), ParamValue::Enum(s)) if !opts.contains(s) => Some(format!("`{s}` is not an option of `{}`", name.value)),
        _ if v.as_floats().iter().any(|x| !x.is_finite()) => Some("the value is not finite".to_string()),
        _ => out_of_range(&v, prm.min.as_ref().map(|m| &m.value), prm.max.as_ref().map(|m| &m.value)).map(|(side, b)| {
            format!(
                "{} is {} the {side} {} of `{}`",
                v.describe(),
                if side == "min" { "below" } else { "above" },
                b.describe(),
                name.value
            )
        }),
    };
    if let Some(msg) = bad {
        diags.push(Diagnostic::error(Code::ValueOutOfRange, msg, lit.span).with_secondary(prm.span, "declared here"));
    }
}
