//! Stage `limits`: a pass's attachments, bind groups and blocks against the capability profile.

use super::bindings::Resolved;
use super::StageShader;
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::layout::BindingType;
use crate::profile::Profile;

fn over(what: String, limit: &str, value: u64, max: u64, profile: &Profile, span: crate::span::Span) -> Diagnostic {
    Diagnostic::error(
        Code::LimitExceeded,
        format!("{what}: {value} exceeds {max} on profile `{}`", profile.name),
        span,
    )
    .with_note(format!("limit: {limit}"))
}

pub fn check(p: &Pipeline, pass: &Pass, stages: &[StageShader], res: &Resolved, profile: &Profile, diags: &mut Diagnostics) {
    attachments(p, pass, profile, diags);
    groups(pass, stages, res, profile, diags);
    per_stage(pass, res, profile, diags);
    storage_buffers(p, pass, res, profile, diags);
    if let PassKind::Compute(c) = &pass.kind {
        dispatch(pass, &c.dispatch, profile, diags);
    }
    if let Some(cs) = stages.iter().find(|s| s.stage == Stage::Compute) {
        workgroup(cs, profile, diags);
    }
}

fn attachments(p: &Pipeline, pass: &Pass, profile: &Profile, diags: &mut Diagnostics) {
    let (l, color) = (&profile.limits, pass.color());
    let (Some(first), Some(last)) = (color.first(), color.last()) else {
        return;
    };
    if color.len() as u64 > l.max_color_attachments {
        let span = color[l.max_color_attachments as usize].span.to(last.span);
        let what = format!("pass `{}` has too many color attachments", pass.name.value);
        diags.push(over(
            what,
            "max_color_attachments",
            color.len() as u64,
            l.max_color_attachments,
            profile,
            span,
        ));
        return;
    }
    let bytes: u64 = color
        .iter()
        .filter_map(|c| p.resource(&c.resource)?.texture())
        .map(|t| t.format.value.bytes().max(4) as u64)
        .sum();
    if bytes > l.max_color_attachment_bytes_per_sample {
        diags.push(over(
            format!("color attachments of pass `{}` take too many bytes per sample", pass.name.value),
            "max_color_attachment_bytes_per_sample",
            bytes,
            l.max_color_attachment_bytes_per_sample,
            profile,
            first.span.to(last.span),
        ));
    }
}

/// Bind group indices, binding indices and uniform block sizes.
fn groups(pass: &Pass, stages: &[StageShader], res: &Resolved, profile: &Profile, diags: &mut Diagnostics) {
    let l = &profile.limits;
    let first_span = |group: u32| {
        stages
            .iter()
            .flat_map(|st| st.module.globals.iter().map(move |g| (st, g)))
            .find(|(_, g)| g.group == group)
            .map(|(st, g)| st.module.global_span(g.handle))
            .unwrap_or(pass.name.span)
    };
    if let Some(g) = res.groups.last().filter(|g| g.group as u64 + 1 > l.max_bind_groups) {
        let what = format!("pass `{}` uses bind group {}", pass.name.value, g.group);
        diags.push(over(
            what,
            "max_bind_groups",
            g.group as u64 + 1,
            l.max_bind_groups,
            profile,
            first_span(g.group),
        ));
    }
    for g in &res.groups {
        if let Some(max_b) = g
            .entries
            .iter()
            .map(|e| e.binding)
            .max()
            .filter(|b| *b as u64 >= l.max_bindings_per_bind_group)
        {
            let what = format!("binding index in group {}", g.group);
            let (v, max) = (max_b as u64 + 1, l.max_bindings_per_bind_group);
            diags.push(over(what, "max_bindings_per_bind_group", v, max, profile, first_span(g.group)));
        }
    }
    for b in res
        .uniform_blocks
        .iter()
        .filter(|b| b.size as u64 > l.max_uniform_buffer_binding_size)
    {
        let what = format!("uniform block `{}`", b.global);
        let max = l.max_uniform_buffer_binding_size;
        diags.push(over(
            what,
            "max_uniform_buffer_binding_size",
            b.size as u64,
            max,
            profile,
            pass.name.span,
        ));
    }
}

/// Textures, samplers and buffers each stage binds.
fn per_stage(pass: &Pass, res: &Resolved, profile: &Profile, diags: &mut Diagnostics) {
    let l = &profile.limits;
    for (stage, c) in &res.per_stage {
        let counts = [
            (
                "sampled textures",
                "max_sampled_textures_per_shader_stage",
                c.sampled_textures,
                l.max_sampled_textures_per_shader_stage,
            ),
            (
                "samplers",
                "max_samplers_per_shader_stage",
                c.samplers,
                l.max_samplers_per_shader_stage,
            ),
            (
                "storage textures",
                "max_storage_textures_per_shader_stage",
                c.storage_textures,
                l.max_storage_textures_per_shader_stage,
            ),
            (
                "uniform buffers",
                "max_uniform_buffers_per_shader_stage",
                c.uniform_buffers,
                l.max_uniform_buffers_per_shader_stage,
            ),
            (
                "storage buffers",
                "max_storage_buffers_per_shader_stage",
                c.storage_buffers,
                l.max_storage_buffers_per_shader_stage,
            ),
        ];
        for (what, limit, v, max) in counts.into_iter().filter(|(_, _, v, max)| v > max) {
            let what = format!("{} stage of pass `{}` uses too many {what}", stage.word(), pass.name.value);
            diags.push(over(what, limit, v, max, profile, pass.name.span));
        }
    }
}

fn workgroup(cs: &StageShader, profile: &Profile, diags: &mut Diagnostics) {
    let l = &profile.limits;
    let [x, y, z] = cs.module.module.entry_points[cs.entry].workgroup_size;
    let sizes = [
        (x as u64, l.max_compute_workgroup_size_x, "max_compute_workgroup_size_x"),
        (y as u64, l.max_compute_workgroup_size_y, "max_compute_workgroup_size_y"),
        (z as u64, l.max_compute_workgroup_size_z, "max_compute_workgroup_size_z"),
        (
            x as u64 * y as u64 * z as u64,
            l.max_compute_invocations_per_workgroup,
            "max_compute_invocations_per_workgroup",
        ),
    ];
    for (v, max, limit) in sizes.into_iter().filter(|(v, max, _)| v > max) {
        let what = format!("workgroup size of `{}`", cs.sref.entry.value);
        diags.push(over(what, limit, v, max, profile, cs.sref.entry.span));
    }
}

/// Explicit workgroup counts: each at least 1 (zero dispatches nothing, which is never what a
/// pass is for) and within the profile's per-dimension limit.
fn dispatch(pass: &Pass, d: &crate::span::Spanned<Dispatch>, profile: &Profile, diags: &mut Diagnostics) {
    let Dispatch::Groups(x, y, z) = d.value else { return };
    let max = profile.limits.max_compute_workgroups_per_dimension;
    if [x, y, z].contains(&0) {
        let msg = format!(
            "pass `{}` dispatches Groups({x}, {y}, {z}): every count must be at least 1",
            pass.name.value
        );
        diags.push(Diagnostic::error(Code::ValueOutOfRange, msg, d.span));
    } else if let Some(v) = [x, y, z].into_iter().find(|v| *v as u64 > max) {
        let what = format!("pass `{}` dispatches {v} workgroups in one dimension", pass.name.value);
        diags.push(over(what, "max_compute_workgroups_per_dimension", v as u64, max, profile, d.span));
    }
}

/// Buffers bound as storage: the whole buffer is bound, so its size must fit one binding.
fn storage_buffers(p: &Pipeline, pass: &Pass, res: &Resolved, profile: &Profile, diags: &mut Diagnostics) {
    let max = profile.limits.max_storage_buffer_binding_size;
    let bound = res
        .groups
        .iter()
        .flat_map(|g| &g.entries)
        .filter(|b| matches!(b.ty, BindingType::Storage { .. }));
    let mut reported: Vec<&str> = vec![];
    for b in bound {
        let (crate::layout::BindSource::Resource(name) | crate::layout::BindSource::Prev(name)) = &b.source else {
            continue;
        };
        let Some(ResourceKind::Buffer(buf)) = p.resource(name).map(|r| &r.kind) else {
            continue;
        };
        if buf.size.value > max && !reported.contains(&name.as_str()) {
            reported.push(name);
            let what = format!(
                "buffer `{name}`, bound as storage by pass `{}`, has {} bytes",
                pass.name.value, buf.size.value
            );
            diags.push(over(
                what,
                "max_storage_buffer_binding_size",
                buf.size.value,
                max,
                profile,
                buf.size.span,
            ));
        }
    }
}
