//! Stage `declarations`: what can be checked from the pipeline file alone: unique names,
//! parameter defaults and ranges, resource shapes, names that refer to other declarations,
//! variant options, fallbacks and presets, and each pass's attachments. The lowering accepts any
//! value the IR can hold; everything about whether it makes sense is decided here.

mod mips;
mod params;
mod presets;
mod refs;
mod resources;
mod targets;
mod unique;
mod variants;

pub use presets::preset_value;

use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::profile::Profile;
use crate::span::Spanned;

pub fn check(p: &Pipeline, profile: &Profile, diags: &mut Diagnostics) {
    unique::check(p, diags);
    params::params(p, diags);
    resources::resources(p, profile, diags);
    refs::idents(p, diags);
    variants::variants(p, diags);
    presets::presets(p, diags);
    for pass in &p.passes {
        if pass.shadow_casters && pass.per_light.is_none() {
            diags.push(
                Diagnostic::error(
                    Code::CastersWithoutLights,
                    format!("pass `{}` runs for shadow-casting lights only but not per light", pass.name.value),
                    pass.name.span,
                )
                .with_note("add `per_light: [..]` (LBP `per_light(..)`), or remove `shadow_casters`"),
            );
        }
        let volume = matches!(&pass.kind, PassKind::Raster(r) if r.draw == Draw::LightVolume);
        if volume && pass.per_light.is_none() {
            diags.push(
                Diagnostic::error(
                    Code::VolumeWithoutLights,
                    format!("pass `{}` draws light volumes but does not run per light", pass.name.value),
                    pass.name.span,
                )
                .with_note("add `per_light: [..]` (LBP `per_light(..)`): each repetition draws its light's volume"),
            );
        }
        refs::pass_refs(p, pass, diags);
        targets::targets(p, pass, profile, diags);
        mips::mips(p, pass, diags);
    }
    for (what, out) in [("output", Some(&p.output)), ("hdr_output", p.hdr_output.as_ref())] {
        let Some(out) = out else { continue };
        if p.resource(out).is_none() {
            diags.push(unknown_resource(p, out));
        } else if p.resource(out).and_then(|r| r.texture()).is_none() {
            diags.push(Diagnostic::error(
                Code::OutputNotTexture,
                format!("{what} `{}` must be a texture", out.value),
                out.span,
            ));
        }
    }
}

pub(super) fn unknown_resource(p: &Pipeline, name: &Spanned<String>) -> Diagnostic {
    let names: Vec<&str> = p.resources.iter().map(|r| r.name.value.as_str()).collect();
    Diagnostic::error(Code::UnknownResource, format!("no resource named `{}`", name.value), name.span)
        .with_note(suggestion_note(name, &names))
}
