//! Encoding one pass of a frame: each repetition as a compute dispatch or a render pass
//! with its attachments, bind groups and draws, as the Plan describes them; consecutive
//! repetitions that load and render into the same attachments share one render pass (a light
//! pass over 1,000 lights is one render pass, its bind groups switched inside it), and so do
//! consecutive passes the Plan lets continue one another (ambient, then the lights).

use super::bind_groups::Rep;
use super::pipelines::{multiview_mask, Built, PipelineKind};
use super::scene_gpu::{DrawOrder, SceneGpu};
use super::timing::{Timer, Writes};
use lightbench_compiler::ir::{Draw, Load};
use lightbench_compiler::plan::{PlanPass, Work};
use std::sync::Arc;

/// A pass ready to encode: its pipeline, repetitions and per-mesh groups.
pub struct PassGpu {
    pub plan: PlanPass,
    pub built: Arc<Built>,
    pub reps: Vec<Rep>,
    /// (group index, one bind group per mesh) for `draw: Scene` passes with per-draw slots.
    pub draw_groups: Option<(u32, Vec<wgpu::BindGroup>)>,
}

/// A render pass left open after a pass, for the next one to continue when the Plan says it
/// may (`PlanPass::continues`) and its first repetition renders into the same subresources.
pub struct Open<'p> {
    rp: wgpu::RenderPass<'static>,
    /// The first repetition's subresources (borrowed from the pass: no copy per frame).
    targets: &'p [super::bind_groups::TargetKey],
}

/// Record the repetitions of pass number `index` that `run` selects into `enc` (the first
/// and last of them write the pass's timestamps); `merge`: let repetitions share render
/// passes where they can. `open`: where a render pass may be left open for the next pass
/// and found open from the one before (`None`: every render pass ends in this call). An open
/// pass must be dropped before `enc` is used otherwise.
pub fn encode<'p>(
    enc: &mut wgpu::CommandEncoder,
    (pass, index, run): (&'p PassGpu, usize, &[bool]),
    (parity, merge): (usize, bool),
    timer: Option<&Timer>,
    scene: (&SceneGpu, &DrawOrder),
    mut open: Option<&mut Option<Open<'p>>>,
) {
    let running: Vec<&Rep> = pass.reps.iter().zip(run).filter(|(_, r)| **r).map(|(rep, _)| rep).collect();
    let n = running.len();
    // Passes are merged only untimed: a timed pass keeps its own timestamps.
    let mergeable = merge && timer.is_none();
    let mut first = 0;
    while first < n {
        let last = if merge && shares_render_passes(pass) {
            first + running[first..].iter().take_while(|r| r.targets == running[first].targets).count()
        } else {
            first + 1
        };
        let reps = &running[first..last];
        let continued = first == 0
            && mergeable
            && pass.plan.continues
            && open
                .as_deref()
                .and_then(Option::as_ref)
                .is_some_and(|o| o.targets == reps[0].targets.as_slice());
        match open.as_deref_mut().and_then(Option::as_mut).filter(|_| continued) {
            Some(o) => record_into(&mut o.rp, (pass, reps), parity, scene),
            None => {
                // Whatever was open ends before anything else is recorded.
                if let Some(s) = open.as_deref_mut() {
                    *s = None;
                }
                let ts = timer.and_then(|t| t.writes(index, (first, last), n).map(|w| (t, w)));
                let left = record(enc, (pass, reps), parity, ts, scene);
                // Left open for the next pass, or ended here (dropped).
                if let (Some(s), Some(rp), true) = (open.as_deref_mut(), left, mergeable) {
                    *s = Some(Open {
                        rp,
                        targets: &reps[0].targets,
                    });
                }
            }
        }
        first = last;
    }
    // A compute pass, or a pass that ran nothing: the next pass cannot continue across it.
    if n == 0 || matches!(pass.built.pipeline, PipelineKind::Compute(_)) {
        if let Some(s) = open {
            *s = None;
        }
    }
}

/// Can repetitions with the same attachments share a render pass? When every attachment
/// loads (a clear per repetition would keep only the last) and the pass writes no storage
/// (a later repetition could read what an earlier one wrote, with no barrier between).
fn shares_render_passes(pass: &PassGpu) -> bool {
    let Some(t) = pass.plan.work.targets() else { return false };
    let loads = t.color.iter().all(|c| c.load == Load::Load) && t.depth.as_ref().is_none_or(|d| d.load == Load::Load);
    loads && pass.plan.writes.is_empty() && !matches!(pass.built.pipeline, PipelineKind::Compute(_))
}

/// One GPU pass recording `reps` (one compute repetition, or render repetitions that share
/// the first one's attachments); a render pass is handed back unended.
fn record(
    enc: &mut wgpu::CommandEncoder,
    (pass, reps): (&PassGpu, &[&Rep]),
    parity: usize,
    ts: Option<(&Timer, Writes)>,
    scene: (&SceneGpu, &DrawOrder),
) -> Option<wgpu::RenderPass<'static>> {
    let rep = reps[0];
    match (&pass.built.pipeline, &pass.plan.work) {
        (PipelineKind::Compute(p), Work::Compute { groups, .. }) => {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(&pass.plan.name),
                timestamp_writes: ts.map(|(t, (b, e))| wgpu::ComputePassTimestampWrites {
                    query_set: &t.set,
                    beginning_of_pass_write_index: b,
                    end_of_pass_write_index: e,
                }),
            });
            cp.set_pipeline(p);
            for (g, bg) in &rep.groups[parity] {
                cp.set_bind_group(*g, bg, &[]);
            }
            let g = rep.dispatch.unwrap_or(*groups);
            cp.dispatch_workgroups(g[0], g[1], g[2]);
            None
        }
        (PipelineKind::Render(_), work) => {
            let colors = color_attachments(pass, rep, parity);
            let depth = depth_attachment(pass, rep, parity);
            let mut rp = enc
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some(&pass.plan.name),
                    color_attachments: &colors,
                    depth_stencil_attachment: depth,
                    timestamp_writes: ts.map(|(t, (b, e))| wgpu::RenderPassTimestampWrites {
                        query_set: &t.set,
                        beginning_of_pass_write_index: b,
                        end_of_pass_write_index: e,
                    }),
                    occlusion_query_set: None,
                    multiview_mask: multiview_mask(work.multiview()),
                })
                .forget_lifetime();
            record_into(&mut rp, (pass, reps), parity, scene);
            Some(rp)
        }
        // The cache builds compute pipelines for compute work only.
        (PipelineKind::Compute(_), _) => None,
    }
}

/// Render repetitions into an open render pass: the pass's pipeline, then per repetition its
/// bind groups and draws.
fn record_into(rp: &mut wgpu::RenderPass, (pass, reps): (&PassGpu, &[&Rep]), parity: usize, scene: (&SceneGpu, &DrawOrder)) {
    let PipelineKind::Render(p) = &pass.built.pipeline else { return };
    rp.set_pipeline(p);
    for rep in reps {
        for (g, bg) in &rep.groups[parity] {
            rp.set_bind_group(*g, bg, &[]);
        }
        draw(rp, (pass, rep), &pass.plan.work, scene);
    }
}

fn draw(rp: &mut wgpu::RenderPass, (pass, rep): (&PassGpu, &Rep), work: &Work, (scene, order): (&SceneGpu, &DrawOrder)) {
    match work {
        Work::Raster { draw, instances, .. } if draw.uses_scene() => {
            let meshes = if *draw == Draw::Transparent {
                &order.back_to_front
            } else {
                &order.opaque
            };
            for &mi in meshes {
                let mesh = &scene.meshes[mi];
                if let Some((g, list)) = &pass.draw_groups {
                    rp.set_bind_group(*g, &list[mi], &[]);
                }
                rp.set_vertex_buffer(0, mesh.vertices.slice(..));
                rp.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                rp.draw_indexed(0..mesh.index_count, 0, 0..(*instances).max(1));
            }
        }
        Work::Raster {
            draw: Draw::Vertices(n),
            instances,
            ..
        } => rp.draw(0..*n, 0..(*instances).max(1)),
        Work::Raster {
            draw: Draw::Triangles(n), ..
        } => rp.draw(0..*n, 0..scene.triangle_count),
        Work::Raster {
            draw: Draw::LightVolume, ..
        } => rp.draw(rep.volume.clone(), 0..1),
        _ => rp.draw(0..3, 0..1),
    }
}

fn color_attachments<'a>(pass: &PassGpu, rep: &'a Rep, parity: usize) -> Vec<Option<wgpu::RenderPassColorAttachment<'a>>> {
    let targets = pass.plan.work.targets().map(|t| t.color.as_slice()).unwrap_or(&[]);
    targets
        .iter()
        .zip(&rep.color[parity])
        .map(|(a, v)| {
            Some(wgpu::RenderPassColorAttachment {
                view: v,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: match a.load {
                        Load::Clear([r, g, b, a]) => wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                        Load::Load => wgpu::LoadOp::Load,
                    },
                    store: wgpu::StoreOp::Store,
                },
            })
        })
        .collect()
}

fn depth_attachment<'a>(pass: &PassGpu, rep: &'a Rep, parity: usize) -> Option<wgpu::RenderPassDepthStencilAttachment<'a>> {
    let d = pass.plan.work.targets()?.depth.as_ref()?;
    Some(wgpu::RenderPassDepthStencilAttachment {
        view: rep.depth[parity].as_ref()?,
        depth_ops: Some(wgpu::Operations {
            load: match d.load {
                Load::Clear(v) => wgpu::LoadOp::Clear(v as f32),
                Load::Load => wgpu::LoadOp::Load,
            },
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    })
}
