//! Each pass's attachments: formats that fit, equal sizes, layers that exist, repeated
//! passes that would clear what an earlier repetition wrote; raster instance and view counts.

use super::unknown_resource;
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::profile::Profile;
use crate::span::{Span, Spanned};

pub(super) fn targets(p: &Pipeline, pass: &Pass, profile: &Profile, diags: &mut Diagnostics) {
    if let PassKind::Raster(r) = &pass.kind {
        raster_counts(pass, r, diags);
    }
    let Some(t) = pass.targets() else { return };
    let missing = match &pass.kind {
        PassKind::Fullscreen(_) if t.color.is_empty() => Some(format!("fullscreen pass `{}` has no color target", pass.name.value)),
        PassKind::Raster(_) if t.color.is_empty() && t.depth.is_none() => {
            Some(format!("raster pass `{}` has no color or depth target", pass.name.value))
        }
        _ => None,
    };
    if let Some(msg) = missing {
        diags.push(Diagnostic::error(Code::NoTargets, msg, pass.name.span));
    }
    let mut sized: Vec<(&TextureDesc, &Spanned<String>)> = vec![];
    for c in &t.color {
        if let Some(tex) = color_target(p, (pass, c), profile, diags) {
            sized.push((tex, &c.resource));
            layer_check(p, pass, &c.resource, c.layer, c.span, diags);
        }
    }
    if let Some(d) = &t.depth {
        if let Some(tex) = depth_target(p, d, diags) {
            sized.push((tex, &d.resource));
            layer_check(p, pass, &d.resource, d.layer, d.span, diags);
        }
    }
    sizes(pass, &sized, diags);
    repeated_clears(p, pass, t, diags);
}

fn raster_counts(pass: &Pass, r: &Raster, diags: &mut Diagnostics) {
    if r.instances.value == 0 {
        diags.push(Diagnostic::error(
            Code::ValueOutOfRange,
            "a raster pass draws at least one instance",
            r.instances.span,
        ));
    }
    if matches!(r.draw, Draw::Vertices(0) | Draw::Triangles(0)) {
        diags.push(Diagnostic::error(
            Code::ValueOutOfRange,
            "a raster pass draws at least one vertex",
            pass.name.span,
        ));
    }
    if matches!(r.draw, Draw::Triangles(_)) && r.instances.value > 1 {
        diags.push(
            Diagnostic::error(
                Code::ValueOutOfRange,
                "`draw: Triangles(..)` draws one instance per scene triangle; it takes no `instances`",
                r.instances.span,
            )
            .with_secondary(pass.name.span, "in this pass"),
        );
    }
    if let Some(v) = &r.multiview {
        if pass.per_face {
            diags.push(Diagnostic::error(
                Code::MultiviewPerFace,
                "a multiview pass renders all faces at once; remove `per_face`",
                v.span,
            ));
        }
        if v.value < 2 {
            diags.push(Diagnostic::error(Code::ValueOutOfRange, "multiview needs at least 2 views", v.span));
        }
    }
}

/// The texture behind an attachment, or why there is none.
fn attachment<'a>(p: &'a Pipeline, res: &Spanned<String>, what: &str, diags: &mut Diagnostics) -> Option<&'a TextureDesc> {
    let Some(r) = p.resource(res) else {
        diags.push(unknown_resource(p, res));
        return None;
    };
    let t = r.texture();
    if t.is_none() {
        diags.push(Diagnostic::error(
            Code::NotATexture,
            format!("`{}` is a buffer and cannot be a {what} target", res.value),
            res.span,
        ));
    }
    t
}

fn color_target<'a>(
    p: &'a Pipeline,
    (pass, c): (&Pass, &ColorTarget),
    profile: &Profile,
    diags: &mut Diagnostics,
) -> Option<&'a TextureDesc> {
    let t = attachment(p, &c.resource, "color", diags)?;
    let f = t.format.value;
    if f.is_depth() {
        diags.push(
            Diagnostic::error(
                Code::DepthAsColor,
                format!("`{}` has depth format {} and cannot be a color target", c.resource.value, f.name()),
                c.resource.span,
            )
            .with_secondary(t.format.span, "format declared here")
            .with_note("use it as the pass's `depth` target instead"),
        );
        return None;
    }
    // A pass that runs only under variant options has what those options require.
    let mut with_options = profile.clone();
    if let Some(w) = &pass.when {
        with_options.features.extend(w.value.implied_features(p));
    }
    if !f.renderable(&with_options) {
        let msg = format!(
            "format {} of `{}` cannot be rendered to on profile `{}`",
            f.name(),
            c.resource.value,
            profile.name
        );
        // A conditional pass may be culled where it would fail: planning one that keeps it
        // is the error (plan::build), here a warning.
        let d = match pass.when {
            None => Diagnostic::error(Code::FormatNotRenderable, msg, c.resource.span),
            Some(_) => Diagnostic::warning(
                Code::FormatNotRenderable,
                format!("{msg}: a plan that keeps pass `{}` fails", pass.name.value),
                c.resource.span,
            ),
        };
        diags.push(
            d.with_secondary(t.format.span, "format declared here").with_note(
                "Rg11b10Ufloat needs the Rg11b10UfloatRenderable feature, 32-bit floats Float32Renderable (GL lacks it); Rgba16Float renders everywhere",
            ),
        );
    }
    if let Some(b) = c.blend.as_ref().filter(|_| !f.blendable()) {
        diags.push(
            Diagnostic::error(
                Code::BlendNotBlendable,
                format!("format {} of `{}` is not blendable", f.name(), c.resource.value),
                b.span,
            )
            .with_secondary(t.format.span, "format declared here")
            .with_note("blendable formats: 8-bit unorm, 16-bit float, Rgb10a2Unorm, Rg11b10Ufloat"),
        );
    }
    Some(t)
}

fn depth_target<'a>(p: &'a Pipeline, d: &DepthTarget, diags: &mut Diagnostics) -> Option<&'a TextureDesc> {
    let t = attachment(p, &d.resource, "depth", diags)?;
    if !t.format.value.is_depth() {
        diags.push(
            Diagnostic::error(
                Code::ColorAsDepth,
                format!(
                    "`{}` has color format {} and cannot be a depth target",
                    d.resource.value,
                    t.format.value.name()
                ),
                d.resource.span,
            )
            .with_secondary(t.format.span, "format declared here"),
        );
        return None;
    }
    Some(t)
}

/// All attachments of a pass have one size.
fn sizes(pass: &Pass, sized: &[(&TextureDesc, &Spanned<String>)], diags: &mut Diagnostics) {
    let Some((first, first_name)) = sized.first() else { return };
    for (t, name) in &sized[1..] {
        if t.size.value != first.size.value {
            let first_size = first.size.value.describe();
            diags.push(
                Diagnostic::error(
                    Code::AttachmentSize,
                    format!(
                        "attachments of pass `{}` differ in size: `{}` is {}, `{}` is {}",
                        pass.name.value,
                        first_name.value,
                        first_size,
                        name.value,
                        t.size.value.describe()
                    ),
                    name.span,
                )
                .with_secondary(first_name.span, first_size),
            );
        }
    }
}

fn layer_check(p: &Pipeline, pass: &Pass, res: &Spanned<String>, layer: LayerSel, span: Span, diags: &mut Diagnostics) {
    let Some(t) = p.resource(res).and_then(|r| r.texture()) else {
        return;
    };
    let layers = t.layers.value;
    let multiview = match &pass.kind {
        PassKind::Raster(r) => r.multiview.as_ref().map(|m| m.value),
        _ => None,
    };
    let msg = match (layer, multiview) {
        (LayerSel::Face, _) if !pass.per_face => "`layer: Face` needs a pass with `per_face: true`".to_string(),
        (LayerSel::Face, _) if layers < 6 => format!("`layer: Face` needs 6 layers, `{}` has {layers}", res.value),
        (LayerSel::Index(i), _) if i >= layers => format!("layer {i} is out of range: `{}` has {layers}", res.value),
        (LayerSel::Rep(_), _) if pass.repeat.is_none() => "`layer: Rep(..)` needs a pass with `repeat`".to_string(),
        (LayerSel::All, Some(views)) if views > layers => {
            format!("multiview renders {views} views but `{}` has {layers} layers", res.value)
        }
        (LayerSel::All, None) => "`layer: All` renders every layer at once and needs `multiview: N`".to_string(),
        _ => return,
    };
    diags.push(Diagnostic::error(Code::LayerSelect, msg, span));
}

/// A repeated pass that clears a shared target keeps only its last repetition's output.
fn repeated_clears(p: &Pipeline, pass: &Pass, t: &Targets, diags: &mut Diagnostics) {
    if pass.per_light.is_none() && !pass.per_face {
        return;
    }
    let all = t
        .color
        .iter()
        .map(|c| (&c.resource, !c.load.is_load(), c.layer, c.span))
        .chain(t.depth.iter().map(|d| (&d.resource, !d.load.is_load(), d.layer, d.span)));
    for (res, clears, layer, span) in all {
        let per_instance = p.resource(res).and_then(|r| r.per_light()).is_some() && pass.per_light.is_some();
        let per_face = layer == LayerSel::Face;
        let covered = per_instance && (per_face || !pass.per_face);
        if clears && !covered && !(per_face && pass.per_light.is_none()) {
            diags.push(
                Diagnostic::warning(
                    Code::RepeatedClear,
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
