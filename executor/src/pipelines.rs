//! Render and compute pipelines built from Plan passes, cached across Plans: a pipeline is
//! reused when its shader modules (by content hash), entry points, bind group layouts and
//! fixed-function state are all unchanged, so a hot reload rebuilds only what an edit touched.

use super::convert;
use crate::error::{Error, Result};
use lightbench_compiler::abi::Vertex;
use lightbench_compiler::format::TextureFormat;
use lightbench_compiler::ir::{Blend, CompareFn, CullMode, Draw, Stage};
use lightbench_compiler::layout::BindingType;
use lightbench_compiler::plan::{PlanPass, Work};
use lightbench_compiler::shader::ShaderModule;
use std::collections::HashMap;
use std::num::NonZeroU32;
use std::sync::Arc;

/// `abi::Vertex` as wgpu reads it: locations 0..4 of the standard vertex layout.
const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 5] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4, 4 => Float32x2];

/// A bind group layout entry: binding, type, visibility.
type LayoutEntry = (u32, BindingType, Vec<Stage>);

/// (stage, module content hash, entry point, constants as (key, value bits)).
type StageKey = (Stage, u64, String, Vec<(String, u64)>);

/// Everything a pipeline's descriptor depends on.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    stages: Vec<StageKey>,
    /// Per bind group: (binding, type, visibility) of each entry.
    groups: Vec<(u32, Vec<LayoutEntry>)>,
    state: State,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum State {
    Compute,
    Render {
        color: Vec<(TextureFormat, Option<Blend>)>,
        depth: Option<(TextureFormat, CompareFn, bool)>,
        cull: Option<CullMode>,
        multiview: Option<u32>,
        scene_vertices: bool,
    },
}

impl PipelineKey {
    pub fn of(pp: &PlanPass, modules: &[Arc<ShaderModule>]) -> PipelineKey {
        let stages = pp
            .stages
            .iter()
            .zip(modules)
            .map(|(s, m)| {
                let constants = s.constants.iter().map(|(k, v)| (k.clone(), v.to_bits())).collect();
                (s.stage, m.hash, s.entry.clone(), constants)
            })
            .collect();
        let groups = pp
            .bind_groups
            .iter()
            .map(|g| {
                (
                    g.group,
                    g.entries.iter().map(|e| (e.binding, e.ty.clone(), e.visibility.clone())).collect(),
                )
            })
            .collect();
        let state = match &pp.work {
            Work::Compute { .. } => State::Compute,
            Work::Raster { targets, .. } | Work::Fullscreen { targets } => {
                let (cull, draw) = match &pp.work {
                    Work::Raster { cull, draw, .. } => (Some(*cull), Some(draw)),
                    _ => (None, None),
                };
                State::Render {
                    color: targets.color.iter().map(|c| (c.format, c.blend)).collect(),
                    depth: targets.depth.as_ref().map(|d| (d.format, d.compare, d.write)),
                    cull,
                    multiview: pp.work.multiview(),
                    scene_vertices: draw.is_some_and(Draw::uses_scene),
                }
            }
        };
        PipelineKey { stages, groups, state }
    }
}

pub enum PipelineKind {
    Render(wgpu::RenderPipeline),
    Compute(wgpu::ComputePipeline),
}

/// A pipeline with the bind group layouts its bind groups must be made with (index = group).
pub struct Built {
    pub pipeline: PipelineKind,
    pub layouts: Vec<wgpu::BindGroupLayout>,
}

/// Pipelines and shader modules that outlive a Plan.
#[derive(Default)]
pub struct PipelineCache {
    modules: HashMap<u64, wgpu::ShaderModule>,
    pipelines: HashMap<PipelineKey, (Arc<Built>, u64)>,
    clock: u64,
}

/// Pipelines kept beyond those the running Plan uses (switching variants back is then free).
const SPARE: usize = 64;

impl PipelineCache {
    pub fn get(&mut self, key: &PipelineKey) -> Option<Arc<Built>> {
        self.clock += 1;
        let now = self.clock;
        self.pipelines.get_mut(key).map(|(b, used)| {
            *used = now;
            b.clone()
        })
    }

    /// Keep pipelines built for a Plan that now runs; forget the least recently used spares,
    /// and the shader modules no kept pipeline uses (each edit makes a new module).
    pub fn insert(&mut self, fresh: Vec<(PipelineKey, Arc<Built>)>, in_use: usize) {
        for (k, b) in fresh {
            self.clock += 1;
            self.pipelines.insert(k, (b, self.clock));
        }
        while self.pipelines.len() > in_use + SPARE {
            let Some(oldest) = self.pipelines.iter().min_by_key(|(_, (_, used))| *used).map(|(k, _)| k.clone()) else {
                break;
            };
            self.pipelines.remove(&oldest);
        }
        let live: std::collections::HashSet<u64> = self.pipelines.keys().flat_map(|k| k.stages.iter().map(|s| s.1)).collect();
        self.modules.retain(|hash, _| live.contains(hash));
    }

    /// Pipelines and shader modules held (for reports and tests).
    pub fn len(&self) -> (usize, usize) {
        (self.pipelines.len(), self.modules.len())
    }

    fn module(&mut self, device: &wgpu::Device, m: &ShaderModule) -> wgpu::ShaderModule {
        self.modules
            .entry(m.hash)
            .or_insert_with(|| {
                device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(&m.path),
                    source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(m.module.clone())),
                })
            })
            .clone()
    }

    /// Build the pipeline of a pass (not cached until the caller commits it).
    pub fn build(&mut self, device: &wgpu::Device, pp: &PlanPass, modules: &[Arc<ShaderModule>]) -> Result<Built> {
        let layouts = group_layouts(device, pp);
        let refs: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(Some).collect();
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&pp.name),
            bind_group_layouts: &refs,
            immediate_size: 0,
        });
        let mut stage = |s: Stage| -> Result<StageModule> {
            let i = pp
                .stages
                .iter()
                .position(|x| x.stage == s)
                .ok_or_else(|| Error::Plan(format!("pass `{}` has no {} stage", pp.name, s.word())))?;
            let m = modules
                .get(i)
                .ok_or_else(|| Error::Plan(format!("pass `{}` has no {} module", pp.name, s.word())))?;
            let constants = pp.stages[i].constants.iter().map(|(k, v)| (k.as_str(), *v)).collect();
            Ok((self.module(device, m), pp.stages[i].entry.clone(), constants))
        };
        let pipeline = match &pp.work {
            Work::Compute { .. } => {
                let (m, entry, constants) = stage(Stage::Compute)?;
                PipelineKind::Compute(device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(&pp.name),
                    layout: Some(&layout),
                    module: &m,
                    entry_point: Some(&entry),
                    compilation_options: options(&constants),
                    cache: None,
                }))
            }
            _ => {
                let vertex = stage(Stage::Vertex)?;
                let fragment = pp.stage(Stage::Fragment).map(|_| stage(Stage::Fragment)).transpose()?;
                PipelineKind::Render(render_pipeline(device, pp, &layout, vertex, fragment))
            }
        };
        Ok(Built { pipeline, layouts })
    }
}

/// A stage's module, entry point and pipeline constants (`override` values).
type StageModule<'p> = (wgpu::ShaderModule, String, Vec<(&'p str, f64)>);

/// Compilation options with the Plan's constants for a stage.
fn options<'a>(constants: &'a [(&'a str, f64)]) -> wgpu::PipelineCompilationOptions<'a> {
    wgpu::PipelineCompilationOptions {
        constants,
        ..Default::default()
    }
}

/// One layout per group index the pass uses; empty layouts fill unused indices below the highest.
fn group_layouts(device: &wgpu::Device, pp: &PlanPass) -> Vec<wgpu::BindGroupLayout> {
    let max_group = pp.bind_groups.iter().map(|g| g.group + 1).max().unwrap_or(0);
    (0..max_group)
        .map(|i| {
            let entries: Vec<wgpu::BindGroupLayoutEntry> = pp
                .bind_groups
                .iter()
                .find(|g| g.group == i)
                .map(|g| {
                    g.entries
                        .iter()
                        .map(|e| wgpu::BindGroupLayoutEntry {
                            binding: e.binding,
                            visibility: convert::stages(&e.visibility),
                            ty: convert::binding_type(&e.ty),
                            count: None,
                        })
                        .collect()
                })
                .unwrap_or_default();
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(&pp.name),
                entries: &entries,
            })
        })
        .collect()
}

fn render_pipeline(
    device: &wgpu::Device,
    pp: &PlanPass,
    layout: &wgpu::PipelineLayout,
    (vm, ventry, vconstants): StageModule,
    fragment: Option<StageModule>,
) -> wgpu::RenderPipeline {
    let targets = pp.work.targets().cloned().unwrap_or_default();
    let color: Vec<Option<wgpu::ColorTargetState>> = targets
        .color
        .iter()
        .map(|c| {
            Some(wgpu::ColorTargetState {
                format: convert::format(c.format),
                blend: c.blend.map(convert::blend),
                write_mask: wgpu::ColorWrites::ALL,
            })
        })
        .collect();
    let depth = targets.depth.as_ref().map(|d| wgpu::DepthStencilState {
        format: convert::format(d.format),
        depth_write_enabled: Some(d.write),
        depth_compare: Some(convert::compare(d.compare)),
        stencil: Default::default(),
        bias: Default::default(),
    });
    let vertex_layout = [Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRIBUTES,
    })];
    let (cull, scene) = match &pp.work {
        Work::Raster { cull, draw, .. } => (convert::cull(*cull), draw.uses_scene()),
        _ => (None, false),
    };
    let buffers: &[Option<wgpu::VertexBufferLayout>] = if scene { &vertex_layout } else { &[] };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(&pp.name),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: &vm,
            entry_point: Some(&ventry),
            compilation_options: options(&vconstants),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology: wgpu::PrimitiveTopology::TriangleList,
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: cull,
            ..Default::default()
        },
        depth_stencil: depth,
        multisample: Default::default(),
        fragment: fragment.as_ref().map(|(m, e, c)| wgpu::FragmentState {
            module: m,
            entry_point: Some(e),
            compilation_options: options(c),
            targets: &color,
        }),
        multiview_mask: multiview_mask(pp.work.multiview()),
        cache: None,
    })
}

/// The view mask of a multiview pass: the low `n` bits.
pub fn multiview_mask(views: Option<u32>) -> Option<NonZeroU32> {
    views.and_then(|n| NonZeroU32::new(((1u64 << n.min(32)) - 1) as u32))
}
