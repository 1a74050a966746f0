//! Stage `variants`: pick each variant's option (requested or default) and fall back
//! along declared fallbacks while the profile lacks what an option needs.

use super::ChosenVariant;
use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics, Severity};
use crate::ir::*;
use crate::profile::Profile;
use std::collections::BTreeMap;

/// Chosen option per variant, with the reason when it is not the requested one.
#[derive(Clone, Debug, Default)]
pub struct Selection {
    pub chosen: BTreeMap<String, String>,
    pub notes: Vec<ChosenVariant>,
}

/// What an option lacks on this profile, as text; empty when it is supported.
fn missing(o: &VariantOption, profile: &Profile) -> Vec<String> {
    let mut out: Vec<String> = o
        .requires
        .iter()
        .filter(|f| !profile.has(f.value))
        .map(|f| format!("feature {}", f.value.name()))
        .collect();
    for (name, min) in &o.limits {
        let have = profile.limits.get(name).unwrap_or(0);
        if have < min.value {
            out.push(format!("limit {} >= {} (has {have})", name.value, min.value));
        }
    }
    out
}

/// Pick every variant's option; requested variants and options must exist.
pub fn select(p: &Pipeline, profile: &Profile, requested: &[(String, String)], diags: &mut Diagnostics) -> Option<Selection> {
    let before = diags.error_count();
    check_requested(p, requested, diags);
    if diags.error_count() > before {
        return None;
    }
    let mut sel = Selection::default();
    for var in &p.variants {
        let requested_opt = requested.iter().rev().find(|(k, _)| *k == var.name.value).map(|(_, v)| v.clone());
        let (start, forced) = match &requested_opt {
            Some(v) => (strip_forced(v).to_string(), v.ends_with('!')),
            None => (var.default.value.clone(), false),
        };
        let (chosen, reasons) = choose(var, (start, forced), profile, diags)?;
        let reason = if !reasons.is_empty() {
            Some(reasons.join("; "))
        } else {
            requested_opt.map(|_| "requested".to_string())
        };
        sel.chosen.insert(var.name.value.clone(), chosen.clone());
        sel.notes.push(ChosenVariant {
            variant: var.name.value.clone(),
            option: chosen,
            reason,
        });
    }
    (diags.error_count() == before).then_some(sel)
}

/// `multiview!`: the option, with fallbacks refused.
/// Every option of every variant that `profile` cannot run and that has no usable fallback,
/// reported as planning it would (`variant-unsupported`): for `check` when other errors stop
/// it before planning, so that one kind of error does not hide the other.
pub fn unsupported_options(p: &Pipeline, profile: &Profile, diags: &mut Diagnostics) {
    for var in &p.variants {
        for o in &var.options {
            choose(var, (o.name.value.clone(), false), profile, diags);
        }
    }
}

fn strip_forced(v: &str) -> &str {
    v.strip_suffix('!').unwrap_or(v)
}

fn check_requested(p: &Pipeline, requested: &[(String, String)], diags: &mut Diagnostics) {
    for (k, v) in requested {
        let v = strip_forced(v);
        let d = match p.variant(k) {
            None => {
                let names: Vec<&str> = p.variants.iter().map(|v| v.name.value.as_str()).collect();
                Diagnostic::unlocated(
                    Severity::Error,
                    Code::UnknownVariant,
                    format!("pipeline `{}` has no variant `{k}`", p.name.value),
                )
                .with_note(suggestion_note(k, &names))
            }
            Some(var) if var.option(v).is_none() => Diagnostic::unlocated(
                Severity::Error,
                Code::UnknownVariantOption,
                format!("variant `{k}` has no option `{v}`"),
            )
            .with_note(suggestion_note(v, &var.option_names())),
            _ => continue,
        };
        diags.push(d);
    }
}

/// Follow fallbacks from `start` while the profile lacks what an option needs; the chosen
/// option and why each step fell back. An option without a usable fallback, or asked for
/// with `!` (`forced`: no fallback wanted), is an error.
fn choose(var: &Variant, (start, forced): (String, bool), profile: &Profile, diags: &mut Diagnostics) -> Option<(String, Vec<String>)> {
    let mut cur = start;
    let mut reasons = vec![];
    let mut seen = vec![];
    loop {
        let o = var.option(&cur)?;
        let lacks = missing(o, profile);
        if lacks.is_empty() {
            return Some((cur, reasons));
        }
        if forced {
            diags.push(
                Diagnostic::unlocated(
                    Severity::Error,
                    Code::VariantUnsupported,
                    format!(
                        "variant `{}` option `{cur}` was asked for without fallback (`{cur}!`) but needs {}, which profile `{}` lacks",
                        var.name.value,
                        lacks.join(", "),
                        profile.name
                    ),
                )
                .with_note(format!("drop the `!` to let `{cur}` fall back along its declared fallbacks")),
            );
            return Some((cur, reasons));
        }
        seen.push(cur.clone());
        match &o.fallback {
            Some(fb) if !seen.contains(&fb.value) => {
                reasons.push(format!(
                    "`{cur}` needs {}, which profile `{}` lacks; falling back to `{}`",
                    lacks.join(", "),
                    profile.name,
                    fb.value
                ));
                cur = fb.value.clone();
            }
            _ => {
                let span = o
                    .requires
                    .iter()
                    .find(|f| !profile.has(f.value))
                    .map(|f| f.span)
                    .or_else(|| o.limits.first().map(|l| l.0.span))
                    .unwrap_or(o.span);
                let mut d = Diagnostic::error(
                    Code::VariantUnsupported,
                    format!(
                        "variant `{}` option `{cur}` needs {}, which profile `{}` lacks, and declares no fallback",
                        var.name.value,
                        lacks.join(", "),
                        profile.name
                    ),
                    span,
                )
                .with_note(format!(
                    "add `fallback: \"...\"` to option `{cur}`, or choose another option with --variant {}=...",
                    var.name.value
                ));
                if !reasons.is_empty() {
                    d = d.with_note(reasons.join("; "));
                }
                diags.push(d);
                return Some((cur, reasons));
            }
        }
    }
}
