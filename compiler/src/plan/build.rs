//! Plan building as a chain of named stages, in the order a reader expects (like Granite's
//! `RenderGraph::bake()`): select variants (`select`, done by the caller) -> evaluate
//! conditions and cull -> order -> derive resources and usages -> lay out passes, bindings
//! and parameter blocks -> lift per-pass values to parameters -> value shader constants ->
//! estimate memory -> data resources' bytes -> per-light copies of each repetition -> alias
//! transient memory -> merge render passes.

use super::*;
use crate::check::Checked;
use crate::diag::{Code, Diagnostic, Diagnostics};

pub fn build_plan(checked: &Checked, cfg: &Config, diags: &mut Diagnostics) -> Option<Plan> {
    let p = &checked.pipeline;
    let before = diags.error_count();
    let (schedule, kept, resources) = checked_stages(checked, cfg, diags)?;
    let samplers = resources::samplers(p, &kept);
    // Passes with targets, bindings and blocks addressed by index.
    let ids = passes::Ids::new(&resources, &samplers, &schedule.ordered.order);
    let mut passes = passes::assemble(p, cfg, &schedule, &kept, &ids)?;
    let mut params = params::plan_params(p, cfg);
    params::lift_pass_values(p, &cfg.selection.chosen, &mut passes, &mut params);
    constants::apply(p, cfg, &kept, &mut passes, diags);
    let memory_bytes = resources::memory(&resources);
    let mut plan = Plan {
        format: FORMAT,
        pipeline: p.name.value.clone(),
        profile: cfg.profile.name.clone(),
        scene: cfg.scene.name.clone(),
        resolution: cfg.scene.size,
        lights: cfg.scene.lights.iter().map(|(k, n)| (*k, *n)).collect(),
        variants: cfg.selection.notes.clone(),
        params,
        samplers,
        passes,
        culled: schedule
            .culled
            .iter()
            .map(|(&i, &cause)| CulledPass {
                name: p.passes[i].name.value.clone(),
                reason: cull::reason(p, cfg, i, cause),
            })
            .collect(),
        uncalled_effects: uncalled_effects(p, cfg, &schedule),
        unserved_effects: unserved_effects(p, cfg, &schedule),
        output: ids.res(&p.output.value)?,
        hdr_output: match &p.hdr_output {
            Some(h) => Some(ids.res(&h.value)?),
            None => None,
        },
        resources,
        memory_bytes,
        physical_bytes: memory_bytes,
        jitter: jitters(p, &cfg.selection.chosen),
        shaders: shaders(&kept),
    };
    // Data resources carry their bytes.
    for r in plan.resources.iter_mut().filter(|r| r.data) {
        r.contents = checked.data.get(&r.name).cloned();
    }
    // Each repetition's copy of the per-light resources it uses.
    copies::assign(&mut plan, &cfg.scene.light_order());
    // Transient resources with disjoint lifetimes may share memory.
    alias::assign(&mut plan);
    // Consecutive passes into the same attachments may share a render pass.
    merge::mark(&mut plan);
    (diags.error_count() == before).then_some(plan)
}

/// Every check a configuration's Plan makes, without assembling it (what `check` runs for
/// each configuration): the stages that can fail, in `build_plan`'s order. `false` when one
/// did (the errors are in `diags`).
pub fn check_configuration(checked: &Checked, cfg: &Config, diags: &mut Diagnostics) -> bool {
    let before = diags.error_count();
    if let Some((_, kept, _)) = checked_stages(checked, cfg, diags) {
        constants::value_kept(&checked.pipeline, cfg, &kept, diags);
    }
    diags.error_count() == before
}

/// Conditions, culling and order; the kept passes' versions; what the scene cannot render;
/// the resources the kept passes touch, with usages, extents and sizes, checked.
fn checked_stages<'c>(checked: &'c Checked, cfg: &Config, diags: &mut Diagnostics) -> Option<(Schedule, Kept<'c>, Vec<PlanResource>)> {
    let p = &checked.pipeline;
    let schedule = schedule(checked, cfg, diags)?;
    let kept: Kept = schedule
        .ordered
        .order
        .iter()
        .map(|&i| checked.version(i, &cfg.selection.chosen).map(|v| (i, v)))
        .collect::<Option<_>>()?;
    if cfg.scene_known {
        renderable(p, cfg, &kept, diags);
    }
    let resources = resources::derive(p, &checked.casters_only, cfg, &kept);
    resources::check_extents(p, cfg, &resources, diags);
    resources::check_buffer_sizes(p, cfg, &resources, diags);
    Some((schedule, kept, resources))
}

/// Each shader file the kept passes' stages name, once, as the compiler read it.
fn shaders(kept: &Kept) -> Vec<PlanShader> {
    let mut out: Vec<PlanShader> = vec![];
    for s in kept.iter().flat_map(|(_, v)| &v.stages) {
        if out.iter().all(|x| x.file != s.sref.file.value) {
            out.push(PlanShader {
                file: s.sref.file.value.clone(),
                language: match s.module.lang {
                    crate::shader::Lang::Wgsl => ShaderLanguage::Wgsl,
                    crate::shader::Lang::Glsl(_) => ShaderLanguage::Glsl,
                },
                text: s.module.expanded.text.clone(),
            });
        }
    }
    out
}

/// The camera jitters when the pipeline says so or a chosen option does (`aa = taa`).
fn jitters(p: &crate::ir::Pipeline, chosen: &std::collections::BTreeMap<String, String>) -> bool {
    p.jitter
        || p.variants.iter().any(|v| {
            let option = chosen.get(&v.name.value).and_then(|o| v.option(o));
            option.is_some_and(|o| o.jitter)
        })
}

/// Effects that conditions of culled passes ask for and the scene does not call for.
fn uncalled_effects(p: &crate::ir::Pipeline, cfg: &Config, schedule: &Schedule) -> Vec<Effect> {
    let mut out: Vec<Effect> = vec![];
    for &i in schedule.culled.keys() {
        let Some(when) = &p.passes[i].when else { continue };
        for e in when.value.effects() {
            if !cfg.scene.effects.contains(&e) && !out.contains(&e) {
                out.push(e);
            }
        }
    }
    out.sort_by_key(|e| Effect::ALL.iter().position(|a| a == e));
    out
}

/// Effects the scene calls for that passes serve (their conditions name them) but no kept pass
/// does, where a serving pass is culled for want of a light kind or of blended meshes — not
/// where every one is culled by a condition (an option chosen off says so itself).
fn unserved_effects(p: &crate::ir::Pipeline, cfg: &Config, schedule: &Schedule) -> Vec<UnservedEffect> {
    // A copy of a pass written with choices whose arms are not chosen serves nothing here.
    let serves = |i: usize, e: Effect| {
        let pass = &p.passes[i];
        let when = pass.choice.as_ref().map_or(&pass.when, |c| &c.when);
        pass.choice.as_ref().is_none_or(|c| c.serves(&cfg.selection.chosen))
            && when.as_ref().is_some_and(|w| w.value.effects().contains(&e))
    };
    let mut out = vec![];
    for &e in Effect::ALL.iter().filter(|e| cfg.scene.effects.contains(e)) {
        let serving: Vec<usize> = (0..p.passes.len()).filter(|&i| serves(i, e)).collect();
        if serving.iter().any(|i| !schedule.culled.contains_key(i)) {
            continue;
        }
        let lacking = serving.iter().find_map(|&i| match schedule.culled.get(&i) {
            Some(&c @ (cull::Cause::NoLights | cull::Cause::NoBlended)) => Some((i, c)),
            _ => None,
        });
        if let Some((i, cause)) = lacking {
            out.push(UnservedEffect {
                effect: e,
                pass: p.passes[i].name.value.clone(),
                reason: cull::reason(p, cfg, i, cause),
            });
        }
    }
    out
}

/// Every color target of a kept pass renders on the profile (the declaration check only warns
/// about conditional passes, which may be culled).
fn renderable(p: &crate::ir::Pipeline, cfg: &Config, kept: &Kept, diags: &mut Diagnostics) {
    for &(i, _) in kept {
        let pass = &p.passes[i];
        for c in pass.targets().map(|t| t.color.as_slice()).unwrap_or(&[]) {
            let Some(t) = p.resource(&c.resource).and_then(|r| r.texture()) else {
                continue;
            };
            if !t.format.value.is_depth() && !t.format.value.renderable(cfg.profile) {
                diags.push(
                    Diagnostic::error(
                        Code::FormatNotRenderable,
                        format!(
                            "pass `{}` renders to `{}`, whose format {} profile `{}` cannot render to",
                            pass.name.value,
                            c.resource.value,
                            t.format.value.name(),
                            cfg.profile.name
                        ),
                        c.resource.span,
                    )
                    .with_secondary(t.format.span, "format declared here"),
                );
            }
        }
    }
}
