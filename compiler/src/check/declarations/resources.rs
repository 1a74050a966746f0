//! Resource shapes: sizes, layers against the view, mips, against the profile's limits;
//! flags that exclude each other; names that would bind ambiguously.

use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::profile::Profile;
use crate::span::Spanned;

pub(super) fn resources(p: &Pipeline, profile: &Profile, diags: &mut Diagnostics) {
    for r in &p.resources {
        match &r.kind {
            ResourceKind::Texture(t) => {
                size(p, r, t, profile, diags);
                layers(r, t, profile, diags);
                mips(r, t, diags);
            }
            ResourceKind::Buffer(b) if b.size.value == 0 => diags.push(Diagnostic::error(
                Code::ValueOutOfRange,
                "buffer size must be a positive number of bytes",
                b.size.span,
            )),
            ResourceKind::Buffer(b) if b.size.value > profile.limits.max_buffer_size => {
                let max = profile.limits.max_buffer_size;
                let msg = format!(
                    "buffer `{}` has {} bytes, over the {max}-byte limit of profile `{}`",
                    r.name.value, b.size.value, profile.name
                );
                diags.push(Diagnostic::error(Code::LimitExceeded, msg, b.size.span).with_note("limit: max_buffer_size"));
            }
            ResourceKind::Buffer(b) => {
                if let Some(d) = r.data().filter(|_| b.per_pixel) {
                    let msg = format!(
                        "`{}` is `per_pixel`: its size follows the viewport, so no `data` can fill it",
                        r.name.value
                    );
                    diags.push(Diagnostic::error(Code::ConflictingKeys, msg, d.span).with_note("drop `data`, or give a fixed size"));
                }
            }
            ResourceKind::AccelerationStructure => {}
        }
        if let Some(k) = r.per_light() {
            empty_kinds(k, diags);
        }
        if let Some(v) = r.valid.as_ref().filter(|v| v.value.0 > v.value.1) {
            diags.push(Diagnostic::error(
                Code::ValueOutOfRange,
                format!(
                    "`valid` of `{}` is an empty range: {} is above {}",
                    r.name.value, v.value.0, v.value.1
                ),
                v.span,
            ));
        }
        if r.history() && r.external() {
            diags.push(Diagnostic::error(
                Code::HistoryExternal,
                format!("`{}` cannot be both history and external", r.name.value),
                r.span,
            ));
        }
    }
    ambiguous(p, diags);
}

pub(super) fn empty_kinds(k: &Spanned<Vec<LightKind>>, diags: &mut Diagnostics) {
    if k.is_empty() {
        diags.push(Diagnostic::error(
            Code::EmptyLightKinds,
            "a per-light list needs at least one light kind",
            k.span,
        ));
    }
}

fn size(p: &Pipeline, r: &Resource, t: &TextureDesc, profile: &Profile, diags: &mut Diagnostics) {
    let err = |msg: String| Diagnostic::error(Code::ValueOutOfRange, msg, t.size.span);
    match t.size.value {
        SizeSpec::Viewport { scale } if !(scale > 0.0 && scale <= 16.0) => {
            diags.push(err(format!("viewport scale must be in (0, 16], `{}` has {scale}", r.name.value)))
        }
        SizeSpec::Fixed { width, height } if width == 0 || height == 0 => diags.push(err(format!(
            "texture size must be at least 1×1, `{}` is {width}×{height}",
            r.name.value
        ))),
        SizeSpec::Fixed { width, height } => {
            let max = profile.limits.max_texture_dimension_2d;
            if width as u64 > max || height as u64 > max {
                diags.push(
                    Diagnostic::error(
                        Code::TextureTooLarge,
                        format!(
                            "`{}` is {width}×{height}, over the {max} texel limit of profile `{}`",
                            r.name.value, profile.name
                        ),
                        t.size.span,
                    )
                    .with_note("limit: max_texture_dimension_2d"),
                );
            }
        }
        SizeSpec::Viewport { .. } => {}
        SizeSpec::Param(ref name) => size_param(p, r, t, name, profile, diags),
        SizeSpec::ViewportParam(ref name) => scale_param(p, r, t, name, diags),
    }
}

/// What a parameter that sizes a texture must be: its type, a test of its range, and how
/// the range reads in the message.
struct SizeRule {
    verb: &'static str,
    ty: ParamType,
    /// The type with its article, as the message says it ("an Int").
    ty_word: &'static str,
    range_ok: fn(f64, f64, f64) -> bool,
    wanted: String,
}

/// `size: Viewport(Param("name"))`: a Float parameter whose range lies within the viewport
/// scales a literal may have, (0, 16].
fn scale_param(p: &Pipeline, r: &Resource, t: &TextureDesc, name: &str, diags: &mut Diagnostics) {
    let rule = SizeRule {
        verb: "scaled",
        ty: ParamType::Float,
        ty_word: "a Float",
        range_ok: |lo, hi, _| lo > 0.0 && hi <= 16.0,
        wanted: "a range within (0, 16] (`min` above 0, `max` at most 16)".into(),
    };
    sizing_param(p, r, t, name, (rule, 16.0), diags);
}

/// `size: Param("name")`: an Int parameter whose range keeps the size within 1 and the
/// profile's texture limit, so that every value `--param` accepts plans.
fn size_param(p: &Pipeline, r: &Resource, t: &TextureDesc, name: &str, profile: &Profile, diags: &mut Diagnostics) {
    let max = profile.limits.max_texture_dimension_2d as f64;
    let rule = SizeRule {
        verb: "sized",
        ty: ParamType::Int,
        ty_word: "an Int",
        range_ok: |lo, hi, max| lo >= 1.0 && hi <= max,
        wanted: format!("a range within 1..{max} (`min` and `max`), the profile's texture limit"),
    };
    sizing_param(p, r, t, name, (rule, max), diags);
}

fn sizing_param(p: &Pipeline, r: &Resource, t: &TextureDesc, name: &str, (rule, max): (SizeRule, f64), diags: &mut Diagnostics) {
    let (res, verb) = (&r.name.value, rule.verb);
    let why = match p.param(name) {
        None => Some(format!("`{res}` is {verb} by parameter `{name}`, which is not declared")),
        Some(prm) if prm.ty.value != rule.ty => Some(format!("`{res}` is {verb} by `{name}`, which must be {} parameter", rule.ty_word)),
        Some(prm) => {
            let lo = prm.min.as_ref().and_then(|m| m.as_floats().first().copied());
            let hi = prm.max.as_ref().and_then(|m| m.as_floats().first().copied());
            match (lo, hi) {
                (Some(lo), Some(hi)) if (rule.range_ok)(lo, hi, max) => None,
                _ => Some(format!("`{res}` is {verb} by `{name}`: give it {}", rule.wanted)),
            }
        }
    };
    if let Some(msg) = why {
        diags.push(Diagnostic::error(Code::ValueOutOfRange, msg, t.size.span));
    }
}

fn layers(r: &Resource, t: &TextureDesc, profile: &Profile, diags: &mut Diagnostics) {
    let layers = t.layers.value;
    let d = match t.view.value {
        _ if layers == 0 => Diagnostic::error(Code::ValueOutOfRange, "a texture needs at least one layer", t.layers.span),
        ViewDim::Cube if layers != 6 => Diagnostic::error(
            Code::CubeLayers,
            format!("cube texture `{}` needs exactly 6 layers, has {layers}", r.name.value),
            t.layers.span,
        )
        .with_note("use `layers: 6` (one layer per face)"),
        ViewDim::D2 if layers != 1 => Diagnostic::error(
            Code::ViewLayers,
            format!("`{}` has {layers} layers but a D2 view shows one", r.name.value),
            t.layers.span,
        )
        .with_note("use `view: D2Array` for a layered texture"),
        _ if layers as u64 > profile.limits.max_texture_array_layers => Diagnostic::error(
            Code::TooManyLayers,
            format!(
                "`{}` has {layers} layers, over the limit {} of profile `{}`",
                r.name.value, profile.limits.max_texture_array_layers, profile.name
            ),
            t.layers.span,
        ),
        _ => return,
    };
    diags.push(d);
}

fn mips(r: &Resource, t: &TextureDesc, diags: &mut Diagnostics) {
    if t.mips.value == 0 {
        diags.push(Diagnostic::error(
            Code::MipCount,
            "a texture needs at least one mip level",
            t.mips.span,
        ));
        return;
    }
    if let SizeSpec::Fixed { width, height } = t.size.value {
        let max_mips = 32 - width.max(height).leading_zeros();
        if t.mips.value > max_mips {
            diags.push(Diagnostic::error(
                Code::MipCount,
                format!("`{}` can have at most {max_mips} mip levels", r.name.value),
                t.mips.span,
            ));
        }
    }
}

/// Two names that map to one shader identifier would make binding by name ambiguous.
fn ambiguous(p: &Pipeline, diags: &mut Diagnostics) {
    // Names by shader identifier (by hash: linear in the declarations).
    let mut seen: std::collections::HashMap<String, Vec<&Spanned<String>>> = Default::default();
    let names = p
        .resources
        .iter()
        .map(|r| &r.name)
        .chain(p.samplers.iter().map(|s| &s.name))
        .chain(p.params.iter().map(|s| &s.name));
    for n in names {
        let id = shader_ident(n);
        let same_id = seen.entry(id.clone()).or_default();
        // Equal names are `duplicate-name`, reported once already.
        if let Some(prev) = same_id.iter().find(|prev| prev.value != n.value) {
            diags.push(
                Diagnostic::error(
                    Code::AmbiguousName,
                    format!("`{}` and `{}` both bind to the shader name `{id}`", prev.value, n.value),
                    n.span,
                )
                .with_secondary(prev.span, "first here"),
            );
        }
        same_id.push(n);
    }
}
