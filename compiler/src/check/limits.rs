//! Stage `limits`: a pass's attachments, bind groups and blocks against the capability profile.

use super::bindings::Resolved;
use super::StageShader;
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::*;
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
    let l = &profile.limits;
    let n = pass.color().len() as u64;
    if n > l.max_color_attachments {
        let span = pass.color()[l.max_color_attachments as usize]
            .span
            .to(pass.color()[pass.color().len() - 1].span);
        diags.push(over(
            format!("pass `{}` has too many color attachments", pass.name.value),
            "max_color_attachments",
            n,
            l.max_color_attachments,
            profile,
            span,
        ));
    } else {
        let bytes: u64 = pass
            .color()
            .iter()
            .filter_map(|c| p.resource(&c.resource)?.texture())
            .map(|t| t.format.value.bytes().max(4) as u64)
            .sum();
        if bytes > l.max_color_attachment_bytes_per_sample && !pass.color().is_empty() {
            diags.push(over(
                format!("color attachments of pass `{}` take too many bytes per sample", pass.name.value),
                "max_color_attachment_bytes_per_sample",
                bytes,
                l.max_color_attachment_bytes_per_sample,
                profile,
                pass.color()[0].span.to(pass.color()[pass.color().len() - 1].span),
            ));
        }
    }
    let first_span = |group: u32| {
        stages
            .iter()
            .flat_map(|st| st.module.globals.iter().cloned().map(move |g| (st, g)))
            .find(|(_, g)| g.group == group)
            .map(|(st, g)| st.module.global_span(g.handle))
            .unwrap_or(pass.name.span)
    };
    if let Some(g) = res.groups.last() {
        if g.group as u64 + 1 > l.max_bind_groups {
            diags.push(over(
                format!("pass `{}` uses bind group {}", pass.name.value, g.group),
                "max_bind_groups",
                g.group as u64 + 1,
                l.max_bind_groups,
                profile,
                first_span(g.group),
            ));
        }
    }
    for g in &res.groups {
        if let Some(max_b) = g.entries.iter().map(|e| e.binding).max() {
            if max_b as u64 >= l.max_bindings_per_bind_group {
                diags.push(over(
                    format!("binding index in group {}", g.group),
                    "max_bindings_per_bind_group",
                    max_b as u64 + 1,
                    l.max_bindings_per_bind_group,
                    profile,
                    first_span(g.group),
                ));
            }
        }
    }
    for b in &res.uniform_blocks {
        if b.size as u64 > l.max_uniform_buffer_binding_size {
            diags.push(over(
                format!("uniform block `{}`", b.global),
                "max_uniform_buffer_binding_size",
                b.size as u64,
                l.max_uniform_buffer_binding_size,
                profile,
                pass.name.span,
            ));
        }
    }
    for (stage, c) in &res.per_stage {
        for (what, limit, v, max) in [
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
        ] {
            if v > max {
                diags.push(over(
                    format!("{} stage of pass `{}` uses too many {what}", stage.word(), pass.name.value),
                    limit,
                    v,
                    max,
                    profile,
                    pass.name.span,
                ));
            }
        }
    }
    if let Some(cs) = stages.iter().find(|s| s.stage == Stage::Compute) {
        let [x, y, z] = cs.module.module.entry_points[cs.entry].workgroup_size;
        let inv = x as u64 * y as u64 * z as u64;
        for (v, max, limit) in [
            (x as u64, l.max_compute_workgroup_size_x, "max_compute_workgroup_size_x"),
            (y as u64, l.max_compute_workgroup_size_y, "max_compute_workgroup_size_y"),
            (z as u64, l.max_compute_workgroup_size_z, "max_compute_workgroup_size_z"),
            (
                inv,
                l.max_compute_invocations_per_workgroup,
                "max_compute_invocations_per_workgroup",
            ),
        ] {
            if v > max {
                diags.push(over(
                    format!("workgroup size of `{}`", cs.sref.entry.value),
                    limit,
                    v,
                    max,
                    profile,
                    cs.sref.entry.span,
                ));
            }
        }
    }
}
