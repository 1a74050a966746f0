//! Stage `passes`: each kept pass in execution order with its work, stages, targets and
//! repetitions, and its bind groups and parameter blocks laid out by index.

use super::*;
use crate::check::bindings::NamedGroup;
use crate::check::PassVersion;
use crate::ir::{ColorTarget, DepthTarget, Dispatch, Pass, PassKind, Pipeline, Targets};

/// Names to Plan indices.
pub(super) struct Ids {
    resources: Vec<String>,
    samplers: Vec<String>,
    /// Pipeline pass index of each Plan pass.
    order: Vec<usize>,
}

impl Ids {
    pub fn new(resources: &[PlanResource], samplers: &[PlanSampler], order: &[usize]) -> Ids {
        Ids {
            resources: resources.iter().map(|r| r.name.clone()).collect(),
            samplers: samplers.iter().map(|s| s.name.clone()).collect(),
            order: order.to_vec(),
        }
    }
    pub fn res(&self, name: &str) -> Option<ResourceId> {
        self.resources.iter().position(|r| r == name).map(|i| ResourceId(i as u32))
    }
    fn sampler(&self, name: &str) -> Option<SamplerId> {
        self.samplers.iter().position(|s| s == name).map(|i| SamplerId(i as u32))
    }
    fn pass(&self, index: usize) -> Option<PassId> {
        self.order.iter().position(|&i| i == index).map(|i| PassId(i as u32))
    }
}

pub(super) fn assemble(p: &Pipeline, cfg: &Config, schedule: &Schedule, kept: &Kept, ids: &Ids) -> Option<Vec<PlanPass>> {
    kept.iter()
        .map(|(i, version)| plan_pass(p, cfg, schedule, *i, version, ids))
        .collect()
}

fn plan_pass(p: &Pipeline, cfg: &Config, schedule: &Schedule, i: usize, version: &PassVersion, ids: &Ids) -> Option<PlanPass> {
    let pass = &p.passes[i];
    let repeat = cfg.repeat_count(p, pass.repeat.as_ref().map(|r| &r.value));
    let reps = reps(cfg, pass, repeat);
    let after = schedule.ordered.after.get(&i).map(Vec::as_slice).unwrap_or(&[]);
    Some(PlanPass {
        name: pass.name.value.clone(),
        work: work(p, cfg, pass, version, ids)?,
        stages: version
            .stages
            .iter()
            .map(|s| PlanStage {
                stage: s.stage,
                file: s.sref.file.value.clone(),
                entry: s.sref.entry.value.clone(),
                // Valued by stage `constants`.
                constants: vec![],
            })
            .collect(),
        per_light: pass.per_light.as_ref().map(|k| k.value.clone()).unwrap_or_default(),
        arms: pass.choice.as_ref().map(|c| c.arms.clone()).unwrap_or_default(),
        from: pass.from.clone(),
        origin: pass.origin.clone(),
        // Stage `merge`.
        continues: false,
        per_face: pass.per_face,
        shadow_casters: pass.shadow_casters,
        per_mip: pass.per_mip.as_ref().map(|m| m.value),
        repeat,
        repetitions: reps.len() as u32,
        reps,
        reads: pass
            .reads
            .iter()
            .map(|r| {
                Some(PlanRead {
                    resource: ids.res(r.name())?,
                    prev: r.is_prev(),
                    mip: r.mip(),
                    layer: r.layer(),
                })
            })
            .collect::<Option<_>>()?,
        writes: pass.writes.iter().map(|w| ids.res(w)).collect::<Option<_>>()?,
        bind_groups: version.resolved.groups.iter().map(|g| bind_group(g, ids)).collect::<Option<_>>()?,
        uniform_blocks: version.resolved.uniform_blocks.clone(),
        after: after.iter().map(|&j| ids.pass(j)).collect::<Option<_>>()?,
        depends: super::deps::depends(p, pass, version),
    })
}

/// Every run of a pass for this scene: per light of its kinds (casting lights only for
/// `shadow_casters`), per cube face, per mip level, per run of a `repeat`.
fn reps(cfg: &Config, pass: &Pass, repeat: u32) -> Vec<PlanRep> {
    let lights: Vec<Option<u32>> = match &pass.per_light {
        None => vec![None],
        Some(kinds) => {
            let order = cfg.scene.light_order();
            let wanted = |(k, casts): &(crate::ir::LightKind, bool)| kinds.value.contains(k) && (*casts || !pass.shadow_casters);
            order
                .iter()
                .enumerate()
                .filter(|(_, l)| wanted(l))
                .map(|(i, _)| Some(i as u32))
                .collect()
        }
    };
    let faces = if pass.per_face { 6 } else { 1 };
    let mips: Vec<Option<u32>> = match &pass.per_mip {
        Some(m) => m.value.levels().into_iter().map(Some).collect(),
        None => vec![None],
    };
    let mut out = vec![];
    for &light in &lights {
        for face in 0..faces {
            for &mip in &mips {
                out.extend((0..repeat.max(1)).map(|run| PlanRep {
                    light,
                    face,
                    mip,
                    run,
                    copies: vec![],
                }));
            }
        }
    }
    out
}

fn work(p: &Pipeline, cfg: &Config, pass: &Pass, version: &PassVersion, ids: &Ids) -> Option<Work> {
    Some(match &pass.kind {
        PassKind::Raster(r) => Work::Raster {
            draw: r.draw.clone(),
            cull: r.cull,
            instances: r.instances.value,
            multiview: r.multiview.as_ref().map(|m| m.value),
            targets: targets(p, &r.targets, ids)?,
        },
        PassKind::Fullscreen(f) => Work::Fullscreen {
            targets: targets(p, &f.targets, ids)?,
        },
        PassKind::Compute(c) => {
            let wg = version.workgroup_size.unwrap_or([1, 1, 1]);
            let (groups, sized_from) = match &c.dispatch.value {
                // One invocation per texel: workgroups to cover the resource at this resolution.
                Dispatch::Size(r) => {
                    let extent = cfg.extent(p, &p.resource(r)?.texture()?.size.value);
                    (
                        [extent.0.div_ceil(wg[0].max(1)), extent.1.div_ceil(wg[1].max(1)), 1],
                        Some(ids.res(r)?),
                    )
                }
                Dispatch::Groups(x, y, z) => ([*x, *y, *z], None),
            };
            Work::Compute {
                groups,
                workgroup_size: wg,
                sized_from,
            }
        }
    })
}

fn targets(p: &Pipeline, t: &Targets, ids: &Ids) -> Option<PlanTargets> {
    let format = |name: &str| p.resource(name).and_then(|r| r.texture()).map(|t| t.format.value);
    let color = |c: &ColorTarget| {
        Some(ColorAttachment {
            resource: ids.res(&c.resource)?,
            format: format(&c.resource)?,
            load: c.load,
            blend: c.blend.as_ref().map(|b| b.value),
            layer: c.layer,
            mip: c.mip.value,
        })
    };
    let depth = |d: &DepthTarget| {
        Some(DepthAttachment {
            resource: ids.res(&d.resource)?,
            format: format(&d.resource)?,
            load: d.load,
            compare: d.compare,
            write: d.write,
            layer: d.layer,
            mip: d.mip.value,
        })
    };
    Some(PlanTargets {
        color: t.color.iter().map(color).collect::<Option<_>>()?,
        depth: match &t.depth {
            Some(d) => Some(depth(d)?),
            None => None,
        },
    })
}

/// A checked bind group with names replaced by Plan indices.
fn bind_group(g: &NamedGroup, ids: &Ids) -> Option<PlanBindGroup> {
    let entries = g
        .entries
        .iter()
        .map(|e| {
            let source = match &e.source {
                BindSource::Resource(n) => BindSource::Resource(ids.res(n)?),
                BindSource::Prev(n) => BindSource::Prev(ids.res(n)?),
                BindSource::Sampler(n) => BindSource::Sampler(ids.sampler(n)?),
                BindSource::Params => BindSource::Params,
                BindSource::Frame => BindSource::Frame,
                BindSource::Instance => BindSource::Instance,
                BindSource::Lights => BindSource::Lights,
                BindSource::Triangles => BindSource::Triangles,
                BindSource::LightVolumes => BindSource::LightVolumes,
                BindSource::AreaLights => BindSource::AreaLights,
                BindSource::HitTriangles => BindSource::HitTriangles,
                BindSource::HitMaterials => BindSource::HitMaterials,
                BindSource::HitEmitters => BindSource::HitEmitters,
                BindSource::HitCorners => BindSource::HitCorners,
                BindSource::HitMaps => BindSource::HitMaps,
                BindSource::Draw(d) => BindSource::Draw(*d),
            };
            Some(Binding {
                binding: e.binding,
                name: e.name.clone(),
                source,
                ty: e.ty.clone(),
                visibility: e.visibility.clone(),
            })
        })
        .collect::<Option<_>>()?;
    Some(BindGroupLayout { group: g.group, entries })
}
