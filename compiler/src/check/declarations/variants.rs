//! Variants: defaults and fallbacks that are options, fallback chains that end, shader
//! substitutions for passes that exist, limits wgpu has, no geometry stage.

use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::profile::{Feature, Limits};

pub(super) fn variants(p: &Pipeline, diags: &mut Diagnostics) {
    for v in &p.variants {
        if v.option(&v.default).is_none() {
            diags.push(
                Diagnostic::error(
                    Code::UnknownVariantOption,
                    format!("default `{}` is not an option of variant `{}`", v.default.value, v.name.value),
                    v.default.span,
                )
                .with_note(suggestion_note(&v.default, &v.option_names())),
            );
        }
        for o in &v.options {
            option(p, v, o, diags);
        }
    }
}

fn option(p: &Pipeline, v: &Variant, o: &VariantOption, diags: &mut Diagnostics) {
    for f in &o.requires {
        if f.value == Feature::GeometryShader {
            diags.push(crate::diag::geometry_shader(f.span));
        }
    }
    for (k, _) in &o.limits {
        if !Limits::NAMES.contains(&k.value.as_str()) {
            diags.push(
                Diagnostic::error(Code::UnknownLimit, format!("unknown limit `{}`", k.value), k.span)
                    .with_note(suggestion_note(&k.value, Limits::NAMES)),
            );
        }
    }
    if let Some(fb) = &o.fallback {
        fallback(v, o, fb, diags);
    }
    for (pass, _) in &o.shaders {
        if p.pass(pass).is_none() {
            let names: Vec<&str> = p.passes.iter().map(|r| r.name.value.as_str()).collect();
            diags.push(
                Diagnostic::error(Code::UnknownPass, format!("no pass named `{}`", pass.value), pass.span)
                    .with_note(suggestion_note(pass, &names)),
            );
        }
    }
}

/// The fallback is an option, and following fallbacks from it ends.
fn fallback(v: &Variant, o: &VariantOption, fb: &crate::span::Spanned<String>, diags: &mut Diagnostics) {
    if v.option(fb).is_none() {
        diags.push(
            Diagnostic::error(
                Code::UnknownVariantOption,
                format!("fallback `{}` is not an option of variant `{}`", fb.value, v.name.value),
                fb.span,
            )
            .with_note(suggestion_note(fb, &v.option_names())),
        );
        return;
    }
    let mut seen = vec![o.name.value.as_str()];
    let mut cur = fb.value.as_str();
    while let Some(next) = v.option(cur) {
        if seen.contains(&cur) {
            diags.push(Diagnostic::error(
                Code::FallbackCycle,
                format!(
                    "fallbacks of variant `{}` form a cycle: {} -> {cur}",
                    v.name.value,
                    seen.join(" -> ")
                ),
                fb.span,
            ));
            return;
        }
        seen.push(cur);
        match &next.fallback {
            Some(f) => cur = f.value.as_str(),
            None => return,
        }
    }
}
