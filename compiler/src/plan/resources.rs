//! Stages `resources` and `memory`: the resources and samplers the kept passes touch, with
//! usages derived from how each pass uses them, extents at the plan's resolution and bytes.

use super::*;
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::{Pipeline, Resource, ResourceKind};
use crate::layout::BindingType;
use std::collections::HashMap;

/// Every resource a kept pass reads, writes, renders into or binds, in declaration order.
/// `casters_only`: per resource, whether shadow-caster passes alone write it.
pub(super) fn derive(p: &Pipeline, casters_only: &[bool], cfg: &Config, kept: &Kept) -> Vec<PlanResource> {
    let mut used = usages(p, kept);
    p.resources
        .iter()
        .zip(casters_only)
        .filter_map(|(r, &casters_only)| {
            let (true, mut usage) = used.remove(r.name.value.as_str())? else {
                return None;
            };
            if r.supplied() && !r.is_accel() {
                usage.insert(Usage::CopyDst); // filled by the runtime
            }
            let mut pr = plan_resource(p, r, casters_only, cfg, usage);
            if let ResourceShape::Buffer { words, .. } = &mut pr.shape {
                *words = buffer_words(r, kept);
            }
            Some(pr)
        })
        .collect()
}

/// The scalar type of a buffer's words, from every shader global bound to it (the check's
/// reflection of each kept version).
fn buffer_words(r: &Resource, kept: &Kept) -> Words {
    let kinds: BTreeSet<naga::ScalarKind> = kept
        .iter()
        .filter_map(|(_, v)| v.buffer_scalars.get(&r.name.value))
        .flatten()
        .copied()
        .collect();
    match kinds.into_iter().collect::<Vec<_>>().as_slice() {
        [naga::ScalarKind::Uint] => Words::U32,
        [naga::ScalarKind::Sint] => Words::I32,
        _ => Words::F32,
    }
}

/// Per resource name: whether a kept pass touches it (or it is saved), and how the kept
/// passes use it. One walk over the passes: planning runs for every configuration `check`
/// covers, and a walk per resource made this the larger part of it.
fn usages<'p>(p: &'p Pipeline, kept: &'p Kept) -> HashMap<&'p str, (bool, BTreeSet<Usage>)> {
    let mut used: HashMap<&str, (bool, BTreeSet<Usage>)> = HashMap::new();
    for (i, version) in kept {
        let pass = &p.passes[*i];
        for r in pass.touched() {
            used.entry(r.value.as_str()).or_default().0 = true;
        }
        let attachments = pass.color().iter().map(|c| &c.resource).chain(pass.depth().map(|d| &d.resource));
        for a in attachments {
            used.entry(a.value.as_str()).or_default().1.insert(Usage::RenderAttachment);
        }
        for e in version.resolved.groups.iter().flat_map(|g| &g.entries) {
            let (BindSource::Resource(n) | BindSource::Prev(n)) = &e.source else {
                continue;
            };
            let usage = match &e.ty {
                BindingType::Texture { .. } => Usage::TextureBinding,
                BindingType::StorageTexture { .. } => Usage::StorageBinding,
                BindingType::Storage { .. } => Usage::Storage,
                BindingType::Uniform { .. } => Usage::Uniform,
                BindingType::AccelerationStructure => Usage::RayQuery,
                BindingType::Sampler(_) => continue,
            };
            used.entry(n.as_str()).or_default().1.insert(usage);
        }
    }
    // Read back to save the image.
    for saved in std::iter::once(&p.output).chain(&p.hdr_output) {
        let entry = used.entry(saved.value.as_str()).or_default();
        entry.0 = true;
        entry.1.insert(Usage::CopySrc);
    }
    used
}

fn plan_resource(p: &Pipeline, r: &Resource, casters_only: bool, cfg: &Config, usage: BTreeSet<Usage>) -> PlanResource {
    let per_light = r.per_light().map(|k| k.value.clone()).unwrap_or_default();
    // Maps only shadow passes write need an instance per casting light only (at least one,
    // which the lights that cast none bind and ignore).
    let instances = match (per_light.is_empty(), casters_only) {
        (true, _) => 1,
        (false, true) => cfg.scene.caster_count(&per_light).max(1),
        (false, false) => cfg.scene.light_count(&per_light),
    };
    let copies = if r.history() { 2 } else { 1 };
    let (shape, one) = match &r.kind {
        ResourceKind::Texture(t) => {
            let extent = cfg.extent(p, &t.size.value);
            let texel = t.format.value.bytes() as u64;
            // (A count past 32 levels is `mip-count`, reported below: no level beyond is summed.)
            let level = |e: u32, m: u32| e.checked_shr(m).unwrap_or(0).max(1) as u64;
            let per_layer: u64 = (0..t.mips.value.min(32))
                .map(|m| level(extent.0, m) * level(extent.1, m) * texel)
                .sum();
            let shape = ResourceShape::Texture {
                format: t.format.value,
                size: t.size.value.clone(),
                extent,
                layers: t.layers.value,
                view: t.view.value,
                mips: t.mips.value,
            };
            (shape, per_layer * t.layers.value as u64)
        }
        ResourceKind::Buffer(b) => {
            let size = buffer_bytes(b, cfg);
            let shape = ResourceShape::Buffer { size, words: Words::F32 };
            (shape, size)
        }
        // Its size is the driver's business, known only once built (the executor reports it).
        ResourceKind::AccelerationStructure => (ResourceShape::AccelerationStructure, 0),
    };
    PlanResource {
        name: r.name.value.clone(),
        shape,
        per_light,
        casters_only,
        instances,
        history: r.history(),
        external: r.external(),
        data: r.data().is_some(),
        // Stage `contents`, from the decoded data.
        contents: None,
        valid: r.valid.as_ref().map(|v| v.value),
        usage,
        bytes: one * instances as u64 * copies,
        shares: None,
    }
}

/// A buffer's bytes at this viewport (`per_pixel`: its size for each pixel).
fn buffer_bytes(b: &crate::ir::BufferDesc, cfg: &Config) -> u64 {
    let (w, h) = cfg.scene.size;
    match b.per_pixel {
        true => b.size.value.saturating_mul(w as u64 * h as u64),
        false => b.size.value,
    }
}

/// `per_pixel` buffers are sized only now: each within the profile's buffer limits (bound as
/// storage, as a whole: `max_storage_buffer_binding_size`), errors at the declaration.
pub(super) fn check_buffer_sizes(p: &Pipeline, cfg: &Config, resources: &[PlanResource], diags: &mut Diagnostics) {
    let limits = &cfg.profile.limits;
    for r in resources {
        let ResourceShape::Buffer { size, .. } = r.shape else { continue };
        let Some(ResourceKind::Buffer(decl)) = p.resource(&r.name).map(|d| &d.kind) else {
            continue;
        };
        if !decl.per_pixel {
            continue;
        }
        let storage = r.usage.contains(&Usage::Storage);
        let (limit, max) = match storage {
            true => (
                "max_storage_buffer_binding_size",
                limits.max_storage_buffer_binding_size.min(limits.max_buffer_size),
            ),
            false => ("max_buffer_size", limits.max_buffer_size),
        };
        if size > max {
            let (w, h) = cfg.scene.size;
            let msg = format!(
                "`{}` is {size} bytes at {w}×{h} ({} per pixel), over the {max}-byte limit of profile `{}`",
                r.name, decl.size.value, cfg.profile.name
            );
            diags.push(Diagnostic::error(Code::LimitExceeded, msg, decl.size.span).with_note(format!("limit: {limit}")));
        }
    }
}

/// Viewport-sized textures are sized only now: each extent within the profile's limit, and
/// the declared mip count possible at that extent (errors at the declaration).
pub(super) fn check_extents(p: &Pipeline, cfg: &Config, resources: &[PlanResource], diags: &mut Diagnostics) {
    let max = cfg.profile.limits.max_texture_dimension_2d;
    for r in resources {
        let ResourceShape::Texture { extent: (w, h), mips, .. } = r.shape else {
            continue;
        };
        let Some(decl) = p.resource(&r.name).and_then(|d| d.texture()) else {
            continue;
        };
        let at = format!("at {}×{}", cfg.scene.size.0, cfg.scene.size.1);
        if w as u64 > max || h as u64 > max {
            let msg = format!(
                "`{}` is {w}×{h} {at}, over the {max} texel limit of profile `{}`",
                r.name, cfg.profile.name
            );
            diags.push(Diagnostic::error(Code::TextureTooLarge, msg, decl.size.span).with_note("limit: max_texture_dimension_2d"));
        }
        let possible = 32 - w.max(h).max(1).leading_zeros();
        if mips > possible {
            let msg = format!(
                "`{}` is {w}×{h} {at}, which allows at most {possible} mip levels, not {mips}",
                r.name
            );
            diags.push(Diagnostic::error(Code::MipCount, msg, decl.mips.span));
        }
    }
}

/// The declared samplers some kept pass binds, in declaration order.
pub(super) fn samplers(p: &Pipeline, kept: &Kept) -> Vec<PlanSampler> {
    let used: Vec<&str> = kept
        .iter()
        .flat_map(|(_, v)| v.resolved.groups.iter().flat_map(|g| &g.entries))
        .filter_map(|e| match &e.source {
            BindSource::Sampler(s) => Some(s.as_str()),
            _ => None,
        })
        .collect();
    p.samplers
        .iter()
        .filter(|s| used.contains(&s.name.value.as_str()))
        .map(|s| PlanSampler {
            name: s.name.value.clone(),
            kind: s.binding_kind(),
            filter: s.filter,
            mipmap: s.mipmap,
            address: s.address,
            compare: s.compare,
        })
        .collect()
}

pub(super) fn memory(resources: &[PlanResource]) -> u64 {
    resources.iter().map(|r| r.bytes).sum()
}
