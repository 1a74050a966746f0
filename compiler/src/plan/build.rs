//! Planning: choose variants against the profile, cull passes for the scene, order the
//! rest, and lay out resources and bindings for the runtime.

use super::*;
use crate::check::{graph, Checked};
use crate::diag::{suggestion_note, Diagnostic, Diagnostics, Severity};
use crate::ir::*;
use crate::profile::Profile;
use crate::scene::SceneFeatures;
use std::collections::BTreeMap;

/// Chosen option per variant, with the reason when it is not the requested one.
#[derive(Clone, Debug, Default)]
pub struct Selection {
    pub chosen: BTreeMap<String, String>,
    pub notes: Vec<ChosenVariant>,
}

pub struct Config<'a> {
    pub profile: &'a Profile,
    pub scene: &'a SceneFeatures,
    pub selection: Selection,
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

/// Stage `variants`: pick each variant's option (requested or default) and fall back along
/// declared fallbacks while the profile lacks what an option needs.
pub fn select(p: &Pipeline, profile: &Profile, requested: &[(String, String)], diags: &mut Diagnostics) -> Option<Selection> {
    let before = diags.error_count();
    for (k, v) in requested {
        match p.variant(k) {
            None => {
                let names: Vec<&str> = p.variants.iter().map(|v| v.name.value.as_str()).collect();
                diags.push(
                    Diagnostic::unlocated(
                        Severity::Error,
                        "unknown-variant",
                        format!("pipeline `{}` has no variant `{k}`", p.name.value),
                    )
                    .with_note(suggestion_note(k, &names)),
                );
            }
            Some(var) if var.option(v).is_none() => {
                diags.push(
                    Diagnostic::unlocated(
                        Severity::Error,
                        "unknown-variant-option",
                        format!("variant `{k}` has no option `{v}`"),
                    )
                    .with_note(suggestion_note(v, &var.option_names())),
                );
            }
            _ => {}
        }
    }
    if diags.error_count() > before {
        return None;
    }
    let mut sel = Selection::default();
    for var in &p.variants {
        let requested_opt = requested.iter().rev().find(|(k, _)| *k == var.name.value).map(|(_, v)| v.clone());
        let start = requested_opt.clone().unwrap_or_else(|| var.default.value.clone());
        let mut cur = start.clone();
        let mut reasons = vec![];
        let mut seen = vec![];
        loop {
            let o = var.option(&cur)?;
            let lacks = missing(o, profile);
            if lacks.is_empty() {
                break;
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
                        "variant-unsupported",
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
                    break;
                }
            }
        }
        let reason = if !reasons.is_empty() {
            Some(reasons.join("; "))
        } else if requested_opt.is_some() {
            Some("requested".into())
        } else {
            None
        };
        sel.chosen.insert(var.name.value.clone(), cur.clone());
        sel.notes.push(ChosenVariant {
            variant: var.name.value.clone(),
            option: cur,
            reason,
        });
    }
    (diags.error_count() == before).then_some(sel)
}

/// `Ok(())` if true, else the reason it is false and whether a variant choice decided it.
fn eval(c: &Condition, p: &Pipeline, cfg: &Config) -> Result<(), (String, bool)> {
    match c {
        Condition::Light(k) => {
            if cfg.scene.lights.get(k).copied().unwrap_or(0) > 0 {
                Ok(())
            } else {
                Err((format!("the scene has no {} light", k.name()), false))
            }
        }
        Condition::Effect(e) => {
            if cfg.scene.effects.contains(e) {
                Ok(())
            } else {
                Err((format!("the scene does not call for {}", e.name()), false))
            }
        }
        Condition::Reflective => {
            if cfg.scene.reflective {
                Ok(())
            } else {
                Err(("the scene has no reflective material".into(), false))
            }
        }
        Condition::Toggle(name) => match p.param(name).map(|prm| &prm.default.value) {
            Some(ParamValue::Bool(true)) => Ok(()),
            _ => Err((format!("toggle `{}` is off", name.value), false)),
        },
        Condition::Variant(v, o) => {
            let chosen = cfg.selection.chosen.get(&v.value).cloned().unwrap_or_default();
            if chosen == o.value {
                Ok(())
            } else {
                Err((
                    format!(
                        "variant not chosen: `{}` is `{chosen}`, this pass belongs to `{}`",
                        v.value, o.value
                    ),
                    true,
                ))
            }
        }
        Condition::Not(inner) if matches!(inner.value, Condition::Variant(..)) => match eval(inner, p, cfg) {
            Ok(()) => {
                let Condition::Variant(v, o) = &inner.value else {
                    return Ok(());
                };
                Err((
                    format!(
                        "variant not chosen: `{}` is `{}`, this pass serves the other options",
                        v.value, o.value
                    ),
                    true,
                ))
            }
            Err(_) => Ok(()),
        },
        Condition::Not(inner) => match eval(inner, p, cfg) {
            Ok(()) => Err((format!("{} holds", inner.describe()), inner.mentions_variant())),
            Err(_) => Ok(()),
        },
        Condition::All(cs) => cs.iter().try_for_each(|c| eval(c, p, cfg)),
        Condition::Any(cs) => {
            let mut reasons = vec![];
            let mut by_variant = true;
            for c in cs {
                match eval(c, p, cfg) {
                    Ok(()) => return Ok(()),
                    Err((r, v)) => {
                        reasons.push(r);
                        by_variant &= v;
                    }
                }
            }
            Err((format!("none holds: {}", reasons.join("; ")), by_variant && !cs.is_empty()))
        }
    }
}

/// Which passes a configuration keeps, in what order, and why the others are culled.
pub struct Schedule {
    pub culled: BTreeMap<usize, String>,
    pub ordered: graph::Ordered,
}

/// The checks of a configuration without assembling the Plan (what `check` needs).
pub fn schedule(checked: &Checked, cfg: &Config, diags: &mut Diagnostics) -> Option<Schedule> {
    let p = &checked.pipeline;
    let mut culled: BTreeMap<usize, String> = BTreeMap::new();
    let mut candidates = vec![];
    for (i, pass) in p.passes.iter().enumerate() {
        if let Some(w) = &pass.when {
            if let Err((why, by_variant)) = eval(w, p, cfg) {
                let reason = if by_variant {
                    why
                } else {
                    format!("condition `{}` is false: {why}", w.describe())
                };
                culled.insert(i, reason);
                continue;
            }
        }
        if let Some(kinds) = &pass.per_light {
            if cfg.scene.light_count(kinds) == 0 {
                let names: Vec<&str> = kinds.iter().map(|k| k.name()).collect();
                culled.insert(i, format!("runs per {} light and the scene has none", names.join(" or ")));
                continue;
            }
        }
        candidates.push(i);
    }
    // Output reachability: keep the passes whose writes the output (transitively) needs.
    let mut needed: Vec<String> = vec![p.output.value.clone()];
    let mut kept: Vec<usize> = vec![];
    loop {
        let mut changed = false;
        for &i in candidates.iter().rev() {
            if kept.contains(&i) {
                continue;
            }
            let pass = &p.passes[i];
            if pass.written().any(|w| needed.contains(&w.value)) {
                kept.push(i);
                changed = true;
                for r in pass.reads.iter().map(|r| r.name()).chain(pass.written()) {
                    if !needed.contains(&r.value) {
                        needed.push(r.value.clone());
                    }
                }
            }
        }
        if !changed {
            break;
        }
    }
    kept.sort();
    for &i in &candidates {
        if !kept.contains(&i) {
            let writes: Vec<String> = p.passes[i].written().map(|w| format!("`{}`", w.value)).collect();
            culled.insert(
                i,
                format!(
                    "output unreachable: nothing on the way to `{}` reads {}",
                    p.output.value,
                    writes.join(", ")
                ),
            );
        }
    }
    if !kept.iter().any(|&i| p.passes[i].written().any(|w| w.value == p.output.value)) {
        let mut d = Diagnostic::error(
            "output-unreachable",
            format!("no kept pass writes the output `{}`", p.output.value),
            p.output.span,
        );
        for (i, why) in &culled {
            if p.passes[*i].written().any(|w| w.value == p.output.value) {
                d = d.with_note(format!("its writer `{}` was culled: {why}", p.passes[*i].name.value));
            }
        }
        diags.push(d);
        return None;
    }
    let ordered = graph::order(p, &kept, &culled, diags)?;
    // A pass whose shaders failed to check has no version; its errors are already reported.
    if ordered.order.iter().any(|&i| checked.version(i, &cfg.selection.chosen).is_none()) {
        return None;
    }
    Some(Schedule { culled, ordered })
}

pub fn build_plan(checked: &Checked, cfg: &Config, diags: &mut Diagnostics) -> Option<Plan> {
    let p = &checked.pipeline;
    let before = diags.error_count();
    let Schedule { culled, ordered } = schedule(checked, cfg, diags)?;
    let viewport = cfg.scene.size;
    let mut passes = vec![];
    for &i in &ordered.order {
        let pass = &p.passes[i];
        let Some(version) = checked.version(i, &cfg.selection.chosen) else {
            // Its shaders failed to check; the errors are already reported.
            return None;
        };
        let repetitions = pass.per_light.as_ref().map(|k| cfg.scene.light_count(k)).unwrap_or(1) * if pass.per_face { 6 } else { 1 };
        let fmt = |name: &str| {
            p.resource(name)
                .and_then(|r| r.texture())
                .map(|t| t.format.value.name().to_string())
                .unwrap_or_default()
        };
        let clear = |l: &LoadOp| match l {
            LoadOp::Clear(v) => Some(v.clone()),
            LoadOp::Load => None,
        };
        let workgroup_size = version
            .stages
            .iter()
            .find(|s| s.stage == naga::ShaderStage::Compute)
            .map(|s| s.module.module.entry_points[s.entry].workgroup_size);
        let (work, cull, instances, multiview) = match &pass.kind {
            PassKind::Raster {
                draw,
                cull,
                instances,
                multiview,
            } => (
                match draw {
                    Draw::Scene => Work::Scene,
                    Draw::Vertices(n) => Work::Vertices(*n),
                },
                Some(*cull),
                *instances,
                multiview.as_ref().map(|m| m.value),
            ),
            PassKind::Fullscreen => (Work::Fullscreen, None, 1, None),
            PassKind::Compute { dispatch } => {
                let work = match dispatch {
                    // One invocation per texel: workgroups to cover the resource at this resolution.
                    Dispatch::Size(r) => {
                        let wg = workgroup_size.unwrap_or([1, 1, 1]);
                        let extent = p
                            .resource(r)
                            .and_then(|r| r.texture())
                            .map(|t| t.size.value.resolve(viewport))
                            .unwrap_or((1, 1));
                        Work::Dispatch {
                            groups: [extent.0.div_ceil(wg[0].max(1)), extent.1.div_ceil(wg[1].max(1)), 1],
                            sized_from: Some(r.value.clone()),
                        }
                    }
                    Dispatch::Groups(x, y, z) => Work::Dispatch {
                        groups: [*x, *y, *z],
                        sized_from: None,
                    },
                };
                (work, None, 1, None)
            }
        };
        passes.push(PlanPass {
            name: pass.name.value.clone(),
            kind: pass.kind.word().to_string(),
            stages: version
                .stages
                .iter()
                .map(|s| PlanStage {
                    stage: crate::check::entry::stage_word(s.stage).into(),
                    file: s.sref.file.value.clone(),
                    entry: s.sref.entry.value.clone(),
                })
                .collect(),
            work,
            workgroup_size,
            cull,
            instances,
            multiview,
            per_light: pass.per_light.as_ref().map(|k| k.value.clone()).unwrap_or_default(),
            per_face: pass.per_face,
            repetitions,
            color: pass
                .color
                .iter()
                .map(|c| PlanAttachment {
                    resource: c.resource.value.clone(),
                    format: fmt(&c.resource),
                    clear: clear(&c.load),
                    blend: c.blend.as_ref().map(|b| b.value),
                    layer: c.layer,
                    depth_compare: None,
                    depth_write: None,
                })
                .collect(),
            depth: pass.depth.as_ref().map(|d| PlanAttachment {
                resource: d.resource.value.clone(),
                format: fmt(&d.resource),
                clear: clear(&d.load),
                blend: None,
                layer: d.layer,
                depth_compare: Some(d.compare),
                depth_write: Some(d.write),
            }),
            reads: pass
                .reads
                .iter()
                .map(|r| {
                    if r.is_prev() {
                        format!("Prev({})", r.name().value)
                    } else {
                        r.name().value.clone()
                    }
                })
                .collect(),
            writes: pass.writes.iter().map(|w| w.value.clone()).collect(),
            bind_groups: version.resolved.groups.clone(),
            uniform_blocks: version.resolved.uniform_blocks.clone(),
            after: ordered
                .after
                .get(&i)
                .map(|v| v.iter().map(|&j| p.passes[j].name.value.clone()).collect())
                .unwrap_or_default(),
        });
    }

    // Resources the kept passes touch, with usage derived from how they are used.
    let mut resources = vec![];
    for r in &p.resources {
        let mut usage: Vec<&str> = vec![];
        let mut add = |u: &'static str| {
            if !usage.contains(&u) {
                usage.push(u)
            }
        };
        for pp in &passes {
            if pp.color.iter().chain(pp.depth.iter()).any(|a| a.resource == r.name.value) {
                add("RENDER_ATTACHMENT");
            }
            for g in &pp.bind_groups {
                for e in &g.entries {
                    let hit = matches!(&e.source, BindSource::Resource(n) | BindSource::Prev(n) if *n == r.name.value);
                    if !hit {
                        continue;
                    }
                    match &e.ty {
                        BindingType::Texture { .. } => add("TEXTURE_BINDING"),
                        BindingType::StorageTexture { .. } => add("STORAGE_BINDING"),
                        BindingType::Storage { .. } => add("STORAGE"),
                        BindingType::Uniform { .. } => add("UNIFORM"),
                        BindingType::Sampler(_) => {}
                    }
                }
            }
        }
        if r.name.value == p.output.value {
            add("COPY_SRC"); // read back to save the image
        }
        if r.external() {
            add("COPY_DST"); // filled by the runtime
        }
        if usage.is_empty() {
            continue;
        }
        let per_light = r.per_light().map(|k| k.value.clone()).unwrap_or_default();
        let instances = if per_light.is_empty() {
            1
        } else {
            cfg.scene.light_count(&per_light)
        };
        let copies = if r.history() { 2 } else { 1 };
        let pr = match &r.kind {
            ResourceKind::Texture(t) => {
                let extent = t.size.value.resolve(viewport);
                let mut bytes = 0u64;
                for m in 0..t.mips.value {
                    let w = (extent.0 >> m).max(1) as u64;
                    let h = (extent.1 >> m).max(1) as u64;
                    bytes += w * h * t.format.value.bytes() as u64;
                }
                bytes *= t.layers.value as u64;
                PlanResource {
                    name: r.name.value.clone(),
                    kind: "texture".into(),
                    format: Some(t.format.value.name().into()),
                    size: t.size.value.describe(),
                    extent,
                    layers: t.layers.value,
                    view: Some(t.view.value.name().into()),
                    mips: t.mips.value,
                    per_light,
                    instances,
                    history: t.history,
                    external: t.external,
                    usage: usage.iter().map(|s| s.to_string()).collect(),
                    bytes: bytes * instances as u64 * copies,
                }
            }
            ResourceKind::Buffer(b) => PlanResource {
                name: r.name.value.clone(),
                kind: "buffer".into(),
                format: None,
                size: format!("{} bytes", b.size.value),
                extent: (0, 0),
                layers: 1,
                view: None,
                mips: 1,
                per_light,
                instances,
                history: b.history,
                external: b.external,
                usage: usage.iter().map(|s| s.to_string()).collect(),
                bytes: b.size.value * instances as u64 * copies,
            },
        };
        resources.push(pr);
    }
    let memory_bytes = resources.iter().map(|r| r.bytes).sum();
    let used_samplers: Vec<&str> = passes
        .iter()
        .flat_map(|pp| pp.bind_groups.iter().flat_map(|g| g.entries.iter()))
        .filter_map(|e| match &e.source {
            BindSource::Sampler(s) => Some(s.as_str()),
            _ => None,
        })
        .collect();
    let plan = Plan {
        pipeline: p.name.value.clone(),
        profile: cfg.profile.name.clone(),
        scene: cfg.scene.name.clone(),
        resolution: viewport,
        lights: cfg.scene.lights.iter().map(|(k, n)| (*k, *n)).collect(),
        variants: cfg.selection.notes.clone(),
        params: p
            .params
            .iter()
            .map(|prm| PlanParam {
                name: prm.name.value.clone(),
                ty: prm.ty.value.clone(),
                default: prm.default.value.clone(),
                min: prm.min.as_ref().map(|m| m.value.clone()),
                max: prm.max.as_ref().map(|m| m.value.clone()),
                doc: prm.doc.clone(),
            })
            .collect(),
        samplers: p
            .samplers
            .iter()
            .filter(|s| used_samplers.contains(&s.name.value.as_str()))
            .map(|s| PlanSampler {
                name: s.name.value.clone(),
                kind: s.binding_kind(),
                filter: s.filter,
                mipmap: s.mipmap,
                address: s.address,
                compare: s.compare,
            })
            .collect(),
        passes,
        culled: culled
            .iter()
            .map(|(i, why)| CulledPass {
                name: p.passes[*i].name.value.clone(),
                reason: why.clone(),
            })
            .collect(),
        resources,
        output: p.output.value.clone(),
        memory_bytes,
    };
    (diags.error_count() == before).then_some(plan)
}
