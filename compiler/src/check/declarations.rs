//! Stage `declarations`: what can be checked from the pipeline file alone: parameter
//! defaults and ranges, resource shapes, names that refer to other declarations,
//! variant options and fallbacks, and each pass's attachments.

use crate::diag::{suggestion_note, Diagnostic, Diagnostics};
use crate::format::TextureFormat;
use crate::ir::*;
use crate::profile::{Feature, Profile};
use crate::span::{Span, Spanned};

pub fn check(p: &Pipeline, profile: &Profile, diags: &mut Diagnostics) {
    params(p, diags);
    resources(p, profile, diags);
    idents(p, diags);
    variants(p, diags);
    for pass in &p.passes {
        pass_refs(p, pass, diags);
        targets(p, pass, profile, diags);
    }
    if p.resource(&p.output).is_none() {
        diags.push(unknown_resource(p, &p.output));
    } else if p.resource(&p.output).and_then(|r| r.texture()).is_none() {
        diags.push(Diagnostic::error(
            "output-not-texture",
            format!("output `{}` must be a texture", p.output.value),
            p.output.span,
        ));
    }
}

fn params(p: &Pipeline, diags: &mut Diagnostics) {
    for prm in &p.params {
        let d = prm.default.as_floats();
        let range = |bound: &Option<Spanned<ParamValue>>| bound.as_ref().map(|b| (b.as_floats(), b.span));
        if let (Some((lo, ls)), Some((hi, _))) = (range(&prm.min), range(&prm.max)) {
            if lo.iter().zip(&hi).any(|(a, b)| a > b) {
                diags.push(Diagnostic::error(
                    "empty-range",
                    format!("parameter `{}` has min greater than max", prm.name.value),
                    ls,
                ));
                continue;
            }
        }
        if let Some((lo, _)) = range(&prm.min) {
            if d.iter().zip(&lo).any(|(v, l)| v < l) {
                diags.push(
                    Diagnostic::error(
                        "default-out-of-range",
                        format!(
                            "default {} of `{}` is below its min {}",
                            prm.default.describe(),
                            prm.name.value,
                            prm.min.as_ref().map(|m| m.describe()).unwrap_or_default()
                        ),
                        prm.default.span,
                    )
                    .with_secondary(prm.min.as_ref().map(|m| m.span).unwrap_or(prm.span), "min given here"),
                );
            }
        }
        if let Some((hi, _)) = range(&prm.max) {
            if d.iter().zip(&hi).any(|(v, h)| v > h) {
                diags.push(
                    Diagnostic::error(
                        "default-out-of-range",
                        format!(
                            "default {} of `{}` is above its max {}",
                            prm.default.describe(),
                            prm.name.value,
                            prm.max.as_ref().map(|m| m.describe()).unwrap_or_default()
                        ),
                        prm.default.span,
                    )
                    .with_secondary(prm.max.as_ref().map(|m| m.span).unwrap_or(prm.span), "max given here"),
                );
            }
        }
        if d.iter().any(|v| !v.is_finite()) {
            diags.push(Diagnostic::error(
                "non-finite",
                format!("default of `{}` is not finite", prm.name.value),
                prm.default.span,
            ));
        }
    }
}

fn resources(p: &Pipeline, profile: &Profile, diags: &mut Diagnostics) {
    for r in &p.resources {
        let Some(t) = r.texture() else { continue };
        let layers = t.layers.value;
        match t.view.value {
            ViewDim::Cube if layers != 6 => diags.push(
                Diagnostic::error(
                    "cube-layers",
                    format!("cube texture `{}` needs exactly 6 layers, has {layers}", r.name.value),
                    t.layers.span,
                )
                .with_note("use `layers: 6` (one layer per face)"),
            ),
            ViewDim::D2 if layers != 1 => diags.push(
                Diagnostic::error(
                    "view-layers",
                    format!("`{}` has {layers} layers but a D2 view shows one", r.name.value),
                    t.layers.span,
                )
                .with_note("use `view: D2Array` for a layered texture"),
            ),
            _ => {}
        }
        if layers == 0 {
            diags.push(Diagnostic::error(
                "value-out-of-range",
                "a texture needs at least one layer",
                t.layers.span,
            ));
        }
        if let SizeSpec::Fixed { width, height } = t.size.value {
            let max = profile.limits.max_texture_dimension_2d;
            if width as u64 > max || height as u64 > max {
                diags.push(
                    Diagnostic::error(
                        "texture-too-large",
                        format!(
                            "`{}` is {width}×{height}, over the {max} texel limit of profile `{}`",
                            r.name.value, profile.name
                        ),
                        t.size.span,
                    )
                    .with_note("limit: max_texture_dimension_2d"),
                );
            }
            let max_mips = 32 - width.max(height).leading_zeros();
            if t.mips.value > max_mips {
                diags.push(Diagnostic::error(
                    "mip-count",
                    format!("`{}` can have at most {max_mips} mip levels", r.name.value),
                    t.mips.span,
                ));
            }
        }
        if t.mips.value == 0 {
            diags.push(Diagnostic::error(
                "mip-count",
                "a texture needs at least one mip level",
                t.mips.span,
            ));
        }
        if layers as u64 > profile.limits.max_texture_array_layers {
            diags.push(Diagnostic::error(
                "too-many-layers",
                format!(
                    "`{}` has {layers} layers, over the limit {} of profile `{}`",
                    r.name.value, profile.limits.max_texture_array_layers, profile.name
                ),
                t.layers.span,
            ));
        }
        if t.history && t.external {
            diags.push(Diagnostic::error(
                "history-external",
                format!("`{}` cannot be both history and external", r.name.value),
                r.span,
            ));
        }
    }
    // Two names that map to one shader identifier would make binding by name ambiguous.
    let mut seen: Vec<(String, &Spanned<String>)> = vec![];
    let names = p
        .resources
        .iter()
        .map(|r| &r.name)
        .chain(p.samplers.iter().map(|s| &s.name))
        .chain(p.params.iter().map(|s| &s.name));
    for n in names {
        let id = shader_ident(n);
        if let Some((_, prev)) = seen.iter().find(|(i, _)| *i == id) {
            diags.push(
                Diagnostic::error(
                    "ambiguous-name",
                    format!("`{}` and `{}` both bind to the shader name `{id}`", prev.value, n.value),
                    n.span,
                )
                .with_secondary(prev.span, "first here"),
            );
        }
        seen.push((id, n));
    }
}

fn unknown_resource(p: &Pipeline, name: &Spanned<String>) -> Diagnostic {
    let names: Vec<&str> = p.resources.iter().map(|r| r.name.value.as_str()).collect();
    Diagnostic::error("unknown-resource", format!("no resource named `{}`", name.value), name.span).with_note(suggestion_note(name, &names))
}

fn condition_refs(p: &Pipeline, c: &Spanned<Condition>, diags: &mut Diagnostics) {
    match &c.value {
        Condition::Toggle(name) => match p.param(name) {
            None => {
                let names: Vec<&str> = p.params.iter().map(|r| r.name.value.as_str()).collect();
                diags.push(
                    Diagnostic::error("unknown-param", format!("no parameter named `{}`", name.value), name.span)
                        .with_note(suggestion_note(name, &names)),
                );
            }
            Some(prm) if prm.ty.value != ParamType::Bool => diags.push(
                Diagnostic::error(
                    "toggle-not-bool",
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
                    Diagnostic::error("unknown-variant", format!("no variant named `{}`", v.value), v.span)
                        .with_note(suggestion_note(v, &names)),
                );
            }
            Some(var) if var.option(o).is_none() => diags.push(
                Diagnostic::error(
                    "unknown-variant-option",
                    format!("variant `{}` has no option `{}`", v.value, o.value),
                    o.span,
                )
                .with_note(suggestion_note(o, &var.option_names())),
            ),
            _ => {}
        },
        Condition::Not(c) => condition_refs(p, c, diags),
        Condition::All(cs) | Condition::Any(cs) => cs.iter().for_each(|c| condition_refs(p, c, diags)),
        _ => {}
    }
}

fn idents(p: &Pipeline, diags: &mut Diagnostics) {
    for pass in &p.passes {
        if let Some(w) = &pass.when {
            condition_refs(p, w, diags);
        }
    }
}

fn variants(p: &Pipeline, diags: &mut Diagnostics) {
    for v in &p.variants {
        if v.option(&v.default).is_none() {
            diags.push(
                Diagnostic::error(
                    "unknown-variant-option",
                    format!("default `{}` is not an option of variant `{}`", v.default.value, v.name.value),
                    v.default.span,
                )
                .with_note(suggestion_note(&v.default, &v.option_names())),
            );
        }
        for o in &v.options {
            for f in &o.requires {
                if f.value == Feature::GeometryShader {
                    diags.push(crate::front::ron::geometry_error(f.span));
                }
            }
            if let Some(fb) = &o.fallback {
                if v.option(fb).is_none() {
                    diags.push(
                        Diagnostic::error(
                            "unknown-variant-option",
                            format!("fallback `{}` is not an option of variant `{}`", fb.value, v.name.value),
                            fb.span,
                        )
                        .with_note(suggestion_note(fb, &v.option_names())),
                    );
                } else {
                    // A fallback chain must end.
                    let mut seen = vec![o.name.value.as_str()];
                    let mut cur = fb.value.as_str();
                    while let Some(next) = v.option(cur) {
                        if seen.contains(&cur) {
                            diags.push(Diagnostic::error(
                                "fallback-cycle",
                                format!(
                                    "fallbacks of variant `{}` form a cycle: {} -> {cur}",
                                    v.name.value,
                                    seen.join(" -> ")
                                ),
                                fb.span,
                            ));
                            break;
                        }
                        seen.push(cur);
                        match &next.fallback {
                            Some(f) => cur = f.value.as_str(),
                            None => break,
                        }
                    }
                }
            }
            for (pass, _) in &o.shaders {
                if p.pass(pass).is_none() {
                    let names: Vec<&str> = p.passes.iter().map(|r| r.name.value.as_str()).collect();
                    diags.push(
                        Diagnostic::error("unknown-pass", format!("no pass named `{}`", pass.value), pass.span)
                            .with_note(suggestion_note(pass, &names)),
                    );
                }
            }
        }
    }
}

fn pass_refs(p: &Pipeline, pass: &Pass, diags: &mut Diagnostics) {
    for r in &pass.reads {
        let name = r.name();
        match p.resource(name) {
            None => diags.push(unknown_resource(p, name)),
            Some(res) if r.is_prev() && !res.history() => diags.push(
                Diagnostic::error(
                    "not-history",
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
    for w in &pass.writes {
        if p.resource(w).is_none() {
            diags.push(unknown_resource(p, w));
        }
    }
    for prm in &pass.params {
        if p.param(prm).is_none() {
            let names: Vec<&str> = p.params.iter().map(|r| r.name.value.as_str()).collect();
            diags.push(
                Diagnostic::error("unknown-param", format!("no parameter named `{}`", prm.value), prm.span)
                    .with_note(suggestion_note(prm, &names)),
            );
        }
    }
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
                    "unknown-resource",
                    format!("no resource or sampler named `{}`", target.value),
                    target.span,
                )
                .with_note(suggestion_note(target, &names)),
            );
        }
    }
    if let PassKind::Compute {
        dispatch: Dispatch::Size(r),
    } = &pass.kind
    {
        if p.resource(r).and_then(|r| r.texture()).is_none() {
            diags.push(unknown_resource(p, r).with_note("`Size(..)` dispatches need a texture to size from"));
        }
    }
    if let Some(kinds) = &pass.per_light {
        // A per-light pass touching a per-light resource uses the current light's instance,
        // so the pass may only iterate lights that have one.
        for name in pass.reads.iter().map(|r| r.name()).chain(pass.written()) {
            if let Some(rk) = p.resource(name).and_then(|r| r.per_light()) {
                if let Some(k) = kinds.iter().find(|k| !rk.contains(k)) {
                    diags.push(
                        Diagnostic::error(
                            "per-light-mismatch",
                            format!(
                                "pass runs per {} light but `{}` has no instance for {} lights",
                                k.name(),
                                name.value,
                                k.name()
                            ),
                            name.span,
                        )
                        .with_secondary(rk.span, "instances exist for these kinds"),
                    );
                }
            }
        }
    } else {
        for name in pass.reads.iter().map(|r| r.name()).chain(pass.written()) {
            if let Some(rk) = p.resource(name).and_then(|r| r.per_light()) {
                diags.push(
                    Diagnostic::error(
                        "per-light-mismatch",
                        format!(
                            "`{}` has one instance per light, but pass `{}` does not run per light",
                            name.value, pass.name.value
                        ),
                        name.span,
                    )
                    .with_secondary(rk.span, "per-light resource declared here")
                    .with_note("add `per_light: [...]` to the pass"),
                );
            }
        }
    }
}

fn layer_check(p: &Pipeline, pass: &Pass, res: &Spanned<String>, layer: LayerSel, span: Span, diags: &mut Diagnostics) {
    let Some(t) = p.resource(res).and_then(|r| r.texture()) else {
        return;
    };
    let layers = t.layers.value;
    match layer {
        LayerSel::Face if !pass.per_face => diags.push(Diagnostic::error(
            "layer-select",
            "`layer: Face` needs a pass with `per_face: true`",
            span,
        )),
        LayerSel::Face if layers < 6 => diags.push(Diagnostic::error(
            "layer-select",
            format!("`layer: Face` needs 6 layers, `{}` has {layers}", res.value),
            span,
        )),
        LayerSel::Index(i) if i >= layers => diags.push(Diagnostic::error(
            "layer-select",
            format!("layer {i} is out of range: `{}` has {layers}", res.value),
            span,
        )),
        LayerSel::All => match &pass.kind {
            PassKind::Raster {
                multiview: Some(views), ..
            } if views.value > layers => diags.push(Diagnostic::error(
                "layer-select",
                format!("multiview renders {} views but `{}` has {layers} layers", views.value, res.value),
                span,
            )),
            PassKind::Raster { multiview: Some(_), .. } => {}
            _ => diags.push(Diagnostic::error(
                "layer-select",
                "`layer: All` renders every layer at once and needs `multiview: N`",
                span,
            )),
        },
        _ => {}
    }
}

fn targets(p: &Pipeline, pass: &Pass, profile: &Profile, diags: &mut Diagnostics) {
    let mut size: Option<(SizeSpec, Spanned<String>)> = None;
    let mut check_size = |t: &TextureDesc, name: &Spanned<String>, diags: &mut Diagnostics| match &size {
        None => size = Some((t.size.value.clone(), name.clone())),
        Some((s, first)) if *s != t.size.value => {
            let first_size = s.describe();
            diags.push(
                Diagnostic::error(
                    "attachment-size",
                    format!(
                        "attachments of pass `{}` differ in size: `{}` is {}, `{}` is {}",
                        pass.name.value,
                        first.value,
                        first_size,
                        name.value,
                        t.size.value.describe()
                    ),
                    name.span,
                )
                .with_secondary(first.span, first_size.to_string()),
            );
        }
        _ => {}
    };
    if matches!(pass.kind, PassKind::Compute { .. }) && (!pass.color.is_empty() || pass.depth.is_some()) {
        diags.push(Diagnostic::error(
            "compute-attachments",
            "compute passes have no attachments; write storage resources with `writes`",
            pass.span,
        ));
    }
    if matches!(pass.kind, PassKind::Fullscreen) && pass.color.is_empty() {
        diags.push(Diagnostic::error(
            "no-targets",
            format!("fullscreen pass `{}` has no color target", pass.name.value),
            pass.name.span,
        ));
    }
    if let PassKind::Raster { .. } = pass.kind {
        if pass.color.is_empty() && pass.depth.is_none() {
            diags.push(Diagnostic::error(
                "no-targets",
                format!("raster pass `{}` has no color or depth target", pass.name.value),
                pass.name.span,
            ));
        }
    }
    for c in &pass.color {
        let Some(res) = p.resource(&c.resource) else {
            diags.push(unknown_resource(p, &c.resource));
            continue;
        };
        let Some(t) = res.texture() else {
            diags.push(Diagnostic::error(
                "not-a-texture",
                format!("`{}` is a buffer and cannot be a color target", c.resource.value),
                c.resource.span,
            ));
            continue;
        };
        let f: TextureFormat = t.format.value;
        if f.is_depth() {
            diags.push(
                Diagnostic::error(
                    "depth-as-color",
                    format!("`{}` has depth format {} and cannot be a color target", c.resource.value, f.name()),
                    c.resource.span,
                )
                .with_secondary(t.format.span, "format declared here")
                .with_note("use it as the pass's `depth` target instead"),
            );
            continue;
        }
        if !f.renderable(profile) {
            diags.push(
                Diagnostic::error(
                    "format-not-renderable",
                    format!(
                        "format {} of `{}` cannot be rendered to on profile `{}`",
                        f.name(),
                        c.resource.value,
                        profile.name
                    ),
                    c.resource.span,
                )
                .with_secondary(t.format.span, "format declared here")
                .with_note("Rg11b10Ufloat needs the Rg11b10UfloatRenderable feature; Rgba16Float renders everywhere"),
            );
        }
        if let Some(b) = &c.blend {
            if !f.blendable() {
                diags.push(
                    Diagnostic::error(
                        "blend-not-blendable",
                        format!("format {} of `{}` is not blendable", f.name(), c.resource.value),
                        b.span,
                    )
                    .with_secondary(t.format.span, "format declared here")
                    .with_note("blendable formats: 8-bit unorm, 16-bit float, Rgb10a2Unorm, Rg11b10Ufloat"),
                );
            }
        }
        if c.load == LoadOp::Load && t.history {
            // fine: accumulate into this frame's instance
        }
        check_size(t, &c.resource, diags);
        layer_check(p, pass, &c.resource, c.layer, c.span, diags);
    }
    if let Some(d) = &pass.depth {
        match p.resource(&d.resource) {
            None => diags.push(unknown_resource(p, &d.resource)),
            Some(res) => match res.texture() {
                None => diags.push(Diagnostic::error(
                    "not-a-texture",
                    format!("`{}` is a buffer and cannot be a depth target", d.resource.value),
                    d.resource.span,
                )),
                Some(t) if !t.format.value.is_depth() => diags.push(
                    Diagnostic::error(
                        "color-as-depth",
                        format!(
                            "`{}` has color format {} and cannot be a depth target",
                            d.resource.value,
                            t.format.value.name()
                        ),
                        d.resource.span,
                    )
                    .with_secondary(t.format.span, "format declared here"),
                ),
                Some(t) => {
                    check_size(t, &d.resource, diags);
                    layer_check(p, pass, &d.resource, d.layer, d.span, diags);
                }
            },
        }
    }
    // A repeated pass that clears a shared target keeps only its last repetition's output.
    if pass.per_light.is_some() || pass.per_face {
        let targets = pass
            .color
            .iter()
            .map(|c| (&c.resource, &c.load, c.layer, c.span))
            .chain(pass.depth.iter().map(|d| (&d.resource, &d.load, d.layer, d.span)));
        for (res, load, layer, span) in targets {
            let per_instance = p.resource(res).and_then(|r| r.per_light()).is_some() && pass.per_light.is_some();
            let per_face = layer == LayerSel::Face;
            let covered = per_instance && (per_face || !pass.per_face);
            if matches!(load, LoadOp::Clear(_)) && !covered && !(per_face && pass.per_light.is_none()) {
                diags.push(
                    Diagnostic::warning(
                        "repeated-clear",
                        format!(
                            "pass `{}` runs once per {} and clears `{}` each time: only the last repetition's output remains",
                            pass.name.value,
                            if pass.per_face { "face" } else { "light" },
                            res.value
                        ),
                        span,
                    )
                    .with_note("use `load: Load` (with `blend: Add` to accumulate), or make the target per light / per face"),
                );
            }
        }
    }
    if let PassKind::Raster { multiview: Some(v), .. } = &pass.kind {
        if pass.per_face {
            diags.push(Diagnostic::error(
                "multiview-per-face",
                "a multiview pass renders all faces at once; remove `per_face`",
                v.span,
            ));
        }
        if v.value < 2 {
            diags.push(Diagnostic::error("value-out-of-range", "multiview needs at least 2 views", v.span));
        }
    }
}
