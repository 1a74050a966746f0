//! The generic executor: runs any Plan. Everything it creates (textures, layouts, pipelines,
//! bind groups) and every decision it makes (repetitions, attachments, dispatch sizes) comes
//! from the Plan; there is no code here for any particular pass or effect.

use super::blocks::{FrameBlock, InstanceBlock, LightBlock, Vertex, VERTEX_ATTRIBUTES};
use super::pool::{Entry, Pool};
use super::scene_gpu::SceneGpu;
use super::{convert, Gpu};
use crate::io::Image;
use crate::scene::{Light, Scene};
use lightbench_compiler::ir::{CompareFn, LayerSel, LightKind, ParamValue};
use lightbench_compiler::plan::{BindSource, BindingType, Plan, PlanAttachment, PlanBinding, PlanPass, Work};
use lightbench_compiler::shader::ShaderModule;
use lightbench_compiler::Executable;
use std::collections::{BTreeMap, HashMap};
use std::num::NonZeroU32;
use std::sync::Arc;
use std::time::Instant;

/// Instance slots are 256 bytes apart (the uniform offset alignment).
const SLOT: u64 = 256;

enum PipelineKind {
    Render(wgpu::RenderPipeline),
    Compute(wgpu::ComputePipeline),
}

/// One repetition of a pass: which light and face, and what it binds and renders into.
struct Rep {
    /// Per frame parity (history resources swap every frame).
    groups: [Vec<(u32, wgpu::BindGroup)>; 2],
    color: [Vec<wgpu::TextureView>; 2],
    depth: [Option<wgpu::TextureView>; 2],
}

struct PassGpu {
    plan: PlanPass,
    pipeline: PipelineKind,
    reps: Vec<Rep>,
    /// (group index, one bind group per mesh) for `draw: Scene` passes with per-draw bindings.
    draw_groups: Option<(u32, Vec<wgpu::BindGroup>)>,
    dispatch: [u32; 3],
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct PassTiming {
    pub pass: String,
    pub repetitions: u32,
    /// GPU time from timestamp queries (None where the adapter has none).
    pub gpu_ms: Option<f64>,
    pub cpu_encode_us: f64,
}

struct Timer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    period_ns: f32,
}

pub struct Executor {
    pub plan: Plan,
    pub pool: Pool,
    samplers: HashMap<String, wgpu::Sampler>,
    passes: Vec<PassGpu>,
    param_buffers: HashMap<(String, String), wgpu::Buffer>,
    frame_buf: wgpu::Buffer,
    lights_buf: wgpu::Buffer,
    instance_buf: wgpu::Buffer,
    scene_gpu: SceneGpu,
    lights: Vec<Light>,
    bounds: (glam::Vec3, glam::Vec3),
    scene: Scene,
    pub frame_index: u64,
    timer: Option<Timer>,
    pub last_timings: Vec<PassTiming>,
}

/// Run `f` inside error scopes for every error kind and report the first error with `what`.
fn err_scope<T>(gpu: &Gpu, what: &str, f: impl FnOnce() -> T) -> Result<T, String> {
    let oom = gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let internal = gpu.device.push_error_scope(wgpu::ErrorFilter::Internal);
    let validation = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let out = f();
    let errors: Vec<wgpu::Error> = [validation.pop(), internal.pop(), oom.pop()]
        .into_iter()
        .filter_map(pollster::block_on)
        .collect();
    match errors.first() {
        Some(e) => Err(format!("{what}: {e}")),
        None => Ok(out),
    }
}

/// Light indices (into the active light array) a per-light list of kinds iterates, in order.
fn lights_of(lights: &[Light], kinds: &[LightKind]) -> Vec<u32> {
    lights
        .iter()
        .enumerate()
        .filter(|(_, l)| kinds.contains(&l.kind))
        .map(|(i, _)| i as u32)
        .collect()
}

impl Executor {
    pub fn new(gpu: &Gpu, exe: &Executable, scene: &Scene) -> Result<Executor, String> {
        Self::build(gpu, exe, scene, Pool::default())
    }

    /// Replace the running Plan at a frame boundary, keeping resources whose descriptors
    /// did not change (hot reload and variant switching rely on this).
    pub fn replace(self, gpu: &Gpu, exe: &Executable) -> Result<Executor, String> {
        let scene = self.scene.clone();
        let frame_index = self.frame_index;
        let mut next = Self::build(gpu, exe, &scene, self.pool)?;
        next.frame_index = frame_index;
        Ok(next)
    }

    fn build(gpu: &Gpu, exe: &Executable, scene: &Scene, old_pool: Pool) -> Result<Executor, String> {
        let device = &gpu.device;
        let plan = exe.plan.clone();
        let lights: Vec<Light> = scene.active_lights().into_iter().cloned().collect();
        let pool = err_scope(gpu, "creating resources", || Pool::build(device, &plan, old_pool))??;
        let scene_gpu = err_scope(gpu, "uploading the scene", || SceneGpu::new(device, &gpu.queue, scene))??;
        let mut samplers = HashMap::new();
        for s in &plan.samplers {
            let address = convert::address(s.address);
            samplers.insert(
                s.name.clone(),
                device.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some(&s.name),
                    address_mode_u: address,
                    address_mode_v: address,
                    address_mode_w: address,
                    mag_filter: convert::filter(s.filter),
                    min_filter: convert::filter(s.filter),
                    mipmap_filter: convert::mipmap_filter(s.mipmap),
                    compare: s.compare.map(convert::compare),
                    ..Default::default()
                }),
            );
        }
        let reps_total: u64 = plan.passes.iter().map(|p| p.repetitions.max(1) as u64).sum();
        let frame_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame"),
            size: std::mem::size_of::<FrameBlock>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let lights_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lights"),
            size: (std::mem::size_of::<LightBlock>() * lights.len().max(1)) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let instance_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("instances"),
            size: SLOT * reps_total.max(1),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut exec = Executor {
            plan: plan.clone(),
            pool,
            samplers,
            passes: vec![],
            param_buffers: HashMap::new(),
            frame_buf,
            lights_buf,
            instance_buf,
            scene_gpu,
            bounds: scene.bounds(),
            lights,
            scene: scene.clone(),
            frame_index: 0,
            timer: None,
            last_timings: vec![],
        };
        exec.write_params(gpu, &BTreeMap::new());
        let mut modules: HashMap<usize, wgpu::ShaderModule> = HashMap::new();
        let mut slot = 0u64;
        for pp in &plan.passes {
            let pass = err_scope(gpu, &format!("pass `{}`", pp.name), || {
                exec.build_pass(gpu, exe, pp, &mut modules, &mut slot)
            })??;
            exec.passes.push(pass);
        }
        if gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY) && !plan.passes.is_empty() {
            let n = (plan.passes.len() * 2) as u32;
            exec.timer = Some(Timer {
                set: device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("pass timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count: n,
                }),
                resolve: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamps"),
                    size: n as u64 * 8,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
                readback: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamps readback"),
                    size: n as u64 * 8,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                period_ns: gpu.queue.get_timestamp_period(),
            });
        }
        Ok(exec)
    }

    /// Parameter blocks at the offsets the Plan gives, from the defaults or `overrides`.
    pub fn write_params(&mut self, gpu: &Gpu, overrides: &BTreeMap<String, ParamValue>) {
        for pp in &self.plan.passes {
            for b in &pp.uniform_blocks {
                let mut bytes = vec![0u8; b.size as usize];
                for f in &b.fields {
                    let Some(param) = self.plan.params.iter().find(|p| p.name == f.param) else {
                        continue;
                    };
                    let value = overrides.get(&f.param).unwrap_or(&param.default);
                    let o = f.offset as usize;
                    let mut put = |i: usize, v: [u8; 4]| {
                        if o + i * 4 + 4 <= bytes.len() {
                            bytes[o + i * 4..o + i * 4 + 4].copy_from_slice(&v);
                        }
                    };
                    match value {
                        ParamValue::Float(x) => put(0, (*x as f32).to_le_bytes()),
                        ParamValue::Int(x) if f.ty == "u32" => put(0, (*x as u32).to_le_bytes()),
                        ParamValue::Int(x) => put(0, (*x as i32).to_le_bytes()),
                        ParamValue::Bool(x) => put(0, (*x as u32).to_le_bytes()),
                        ParamValue::Vec(v) => {
                            let n = if f.ty.starts_with("vec4") { 4 } else { v.len().min(4) };
                            for i in 0..n {
                                put(i, (*v.get(i).unwrap_or(&1.0) as f32).to_le_bytes());
                            }
                        }
                        ParamValue::Enum(s) => {
                            let idx = match &param.ty {
                                lightbench_compiler::ir::ParamType::Enum(opts) => opts.iter().position(|o| o == s).unwrap_or(0),
                                _ => 0,
                            };
                            put(0, (idx as u32).to_le_bytes())
                        }
                    }
                }
                let key = (pp.name.clone(), b.global.clone());
                let buf = self.param_buffers.entry(key).or_insert_with(|| {
                    gpu.device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&format!("{}.{}", pp.name, b.global)),
                        size: (b.size as u64).max(16),
                        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    })
                });
                gpu.queue.write_buffer(buf, 0, &bytes);
            }
        }
    }

    fn shader(&self, gpu: &Gpu, m: &Arc<ShaderModule>, cache: &mut HashMap<usize, wgpu::ShaderModule>) -> wgpu::ShaderModule {
        let key = Arc::as_ptr(m) as usize;
        cache
            .entry(key)
            .or_insert_with(|| {
                gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(&m.path),
                    source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(m.module.clone())),
                })
            })
            .clone()
    }

    /// Index of a per-light resource's instance for light `light` (its rank among the lights
    /// the resource has instances for).
    fn instance_of(&self, res: &str, light: Option<u32>) -> u32 {
        let Some(r) = self.plan.resource(res) else { return 0 };
        match (r.per_light.is_empty(), light) {
            (false, Some(l)) => lights_of(&self.lights, &r.per_light).iter().position(|&i| i == l).unwrap_or(0) as u32,
            _ => 0,
        }
    }

    fn view(
        entry: &Entry,
        instance: u32,
        prev: bool,
        parity: u32,
        dim: Option<wgpu::TextureViewDimension>,
        layers: Option<(u32, u32)>,
    ) -> Result<wgpu::TextureView, String> {
        let tex = entry.texture(instance, prev, parity).ok_or("not a texture")?;
        let is_depth = tex.format().is_depth_stencil_format();
        Ok(tex.create_view(&wgpu::TextureViewDescriptor {
            dimension: dim,
            aspect: if is_depth {
                wgpu::TextureAspect::DepthOnly
            } else {
                wgpu::TextureAspect::All
            },
            base_array_layer: layers.map(|l| l.0).unwrap_or(0),
            array_layer_count: layers.map(|l| l.1),
            mip_level_count: if dim.is_some() { None } else { Some(1) },
            ..Default::default()
        }))
    }

    fn attachment_view(&self, a: &PlanAttachment, light: Option<u32>, face: u32, parity: u32) -> Result<wgpu::TextureView, String> {
        let e = self.pool.get(&a.resource)?;
        let inst = self.instance_of(&a.resource, light);
        let layers = e.key.layers;
        let (dim, range) = match a.layer {
            LayerSel::All => (wgpu::TextureViewDimension::D2Array, (0, layers)),
            LayerSel::Face => (wgpu::TextureViewDimension::D2, (face, 1)),
            LayerSel::Base => (wgpu::TextureViewDimension::D2, (0, 1)),
            LayerSel::Index(n) => (wgpu::TextureViewDimension::D2, (n, 1)),
        };
        let tex = e
            .texture(inst, false, parity)
            .ok_or_else(|| format!("`{}` is not a texture", a.resource))?;
        let is_depth = tex.format().is_depth_stencil_format();
        Ok(tex.create_view(&wgpu::TextureViewDescriptor {
            label: Some(&a.resource),
            dimension: Some(dim),
            usage: Some(wgpu::TextureUsages::RENDER_ATTACHMENT),
            aspect: if is_depth {
                wgpu::TextureAspect::DepthOnly
            } else {
                wgpu::TextureAspect::All
            },
            base_mip_level: 0,
            mip_level_count: Some(1),
            base_array_layer: range.0,
            array_layer_count: Some(range.1),
            ..Default::default()
        }))
    }

    fn build_pass(
        &self,
        gpu: &Gpu,
        exe: &Executable,
        pp: &PlanPass,
        modules: &mut HashMap<usize, wgpu::ShaderModule>,
        slot: &mut u64,
    ) -> Result<PassGpu, String> {
        let device = &gpu.device;
        // Bind group layouts, one per group index the pass uses.
        let max_group = pp.bind_groups.iter().map(|g| g.group + 1).max().unwrap_or(0);
        let mut layouts: Vec<Option<wgpu::BindGroupLayout>> = (0..max_group).map(|_| None).collect();
        let mut draw_group = None;
        for g in &pp.bind_groups {
            let entries = g
                .entries
                .iter()
                .map(|e| {
                    Ok(wgpu::BindGroupLayoutEntry {
                        binding: e.binding,
                        visibility: convert::stages(&e.visibility),
                        ty: convert::binding_type(&e.ty)?,
                        count: None,
                    })
                })
                .collect::<Result<Vec<_>, String>>()?;
            let per_draw = g.entries.iter().filter(|e| matches!(e.source, BindSource::Draw(_))).count();
            if per_draw > 0 {
                if per_draw != g.entries.len() {
                    return Err(format!(
                        "group {} mixes per-draw bindings with others; keep per-draw slots in a group of their own",
                        g.group
                    ));
                }
                draw_group = Some(g.group);
            }
            layouts[g.group as usize] = Some(device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(&pp.name),
                entries: &entries,
            }));
        }
        // Empty layouts fill unused group indices below the highest one.
        let empty = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("empty"),
            entries: &[],
        });
        let layout_refs: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(l.as_ref().unwrap_or(&empty))).collect();
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&pp.name),
            bind_group_layouts: &layout_refs,
            immediate_size: 0,
        });

        let mut module_of = |stage: &str| -> Result<(wgpu::ShaderModule, String), String> {
            let m = exe
                .modules
                .get(&(pp.name.clone(), stage.to_string()))
                .ok_or_else(|| format!("no {stage} module"))?;
            let entry = pp
                .stages
                .iter()
                .find(|s| s.stage == stage)
                .map(|s| s.entry.clone())
                .ok_or_else(|| format!("no {stage} stage"))?;
            Ok((self.shader(gpu, m, modules), entry))
        };
        let multiview = pp.multiview.and_then(|n| NonZeroU32::new((1u32 << n) - 1));
        let (pipeline, dispatch) = if let Work::Dispatch { groups, .. } = &pp.work {
            let (m, entry) = module_of("compute")?;
            let p = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&pp.name),
                layout: Some(&pipeline_layout),
                module: &m,
                entry_point: Some(&entry),
                compilation_options: Default::default(),
                cache: None,
            });
            (PipelineKind::Compute(p), *groups)
        } else {
            let (vm, ventry) = module_of("vertex")?;
            let frag = if pp.stages.iter().any(|s| s.stage == "fragment") {
                Some(module_of("fragment")?)
            } else {
                None
            };
            let targets = pp
                .color
                .iter()
                .map(|c| {
                    Ok(Some(wgpu::ColorTargetState {
                        format: convert::format(&c.format)?,
                        blend: c.blend.map(convert::blend),
                        write_mask: wgpu::ColorWrites::ALL,
                    }))
                })
                .collect::<Result<Vec<_>, String>>()?;
            let depth = pp
                .depth
                .as_ref()
                .map(|d| {
                    Ok::<_, String>(wgpu::DepthStencilState {
                        format: convert::format(&d.format)?,
                        depth_write_enabled: Some(d.depth_write.unwrap_or(true)),
                        depth_compare: Some(convert::compare(d.depth_compare.unwrap_or(CompareFn::Less))),
                        stencil: Default::default(),
                        bias: Default::default(),
                    })
                })
                .transpose()?;
            let vertex_layout = [Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &VERTEX_ATTRIBUTES,
            })];
            let buffers: &[Option<wgpu::VertexBufferLayout>] = if pp.work == Work::Scene { &vertex_layout } else { &[] };
            let p = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&pp.name),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &vm,
                    entry_point: Some(&ventry),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: pp.cull.and_then(convert::cull),
                    ..Default::default()
                },
                depth_stencil: depth,
                multisample: Default::default(),
                fragment: frag.as_ref().map(|(m, e)| wgpu::FragmentState {
                    module: m,
                    entry_point: Some(e),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: multiview,
                cache: None,
            });
            (PipelineKind::Render(p), [0, 0, 0])
        };

        // Repetitions: lights of the pass's kinds × faces.
        let light_list: Vec<Option<u32>> = if pp.per_light.is_empty() {
            vec![None]
        } else {
            lights_of(&self.lights, &pp.per_light).into_iter().map(Some).collect()
        };
        let faces: Vec<u32> = if pp.per_face { (0..6).collect() } else { vec![0] };
        let mut reps = vec![];
        for &light in &light_list {
            for &face in &faces {
                let inst = InstanceBlock {
                    light: light.unwrap_or(0),
                    face,
                    view_count: pp.multiview.unwrap_or(1),
                    _pad: 0,
                };
                gpu.queue.write_buffer(&self.instance_buf, *slot * SLOT, bytemuck::bytes_of(&inst));
                let mut groups: [Vec<(u32, wgpu::BindGroup)>; 2] = [vec![], vec![]];
                let mut color: [Vec<wgpu::TextureView>; 2] = [vec![], vec![]];
                let mut depth: [Option<wgpu::TextureView>; 2] = [None, None];
                // History resources swap every frame; without them both parities are the same.
                let parities = if self.pool.entries.values().any(|e| e.key.copies == 2) {
                    2
                } else {
                    1
                };
                for parity in 0..parities {
                    for g in &pp.bind_groups {
                        if Some(g.group) == draw_group {
                            continue;
                        }
                        let layout = layouts[g.group as usize].as_ref().ok_or("missing layout")?;
                        let bg = self.bind_group(gpu, pp, &g.entries, layout, light, *slot, parity)?;
                        groups[parity as usize].push((g.group, bg));
                    }
                    for c in &pp.color {
                        color[parity as usize].push(self.attachment_view(c, light, face, parity)?);
                    }
                    if let Some(d) = &pp.depth {
                        depth[parity as usize] = Some(self.attachment_view(d, light, face, parity)?);
                    }
                }
                if parities == 1 {
                    groups[1] = groups[0].clone();
                    color[1] = color[0].clone();
                    depth[1] = depth[0].clone();
                }
                reps.push(Rep { groups, color, depth });
                *slot += 1;
            }
        }
        let draw_groups = match draw_group {
            Some(gi) => {
                let g = pp.bind_groups.iter().find(|g| g.group == gi).ok_or("missing draw group")?;
                let layout = layouts[gi as usize].as_ref().ok_or("missing layout")?;
                let mut list = vec![];
                for mesh in &self.scene_gpu.meshes {
                    let mat = &self.scene_gpu.materials[mesh.material];
                    let entries = g
                        .entries
                        .iter()
                        .map(|e| {
                            let BindSource::Draw(slot) = &e.source else {
                                return Err("not a draw slot".to_string());
                            };
                            let resource = match slot.as_str() {
                                "mesh" => mesh.block.as_entire_binding(),
                                "material" => mat.block.as_entire_binding(),
                                "base_color_map" => wgpu::BindingResource::TextureView(&mat.textures[0]),
                                "normal_map" => wgpu::BindingResource::TextureView(&mat.textures[1]),
                                "metallic_roughness_map" => wgpu::BindingResource::TextureView(&mat.textures[2]),
                                "emissive_map" => wgpu::BindingResource::TextureView(&mat.textures[3]),
                                "material_sampler" => wgpu::BindingResource::Sampler(&self.scene_gpu.sampler),
                                other => return Err(format!("unknown per-draw slot `{other}`")),
                            };
                            Ok(wgpu::BindGroupEntry {
                                binding: e.binding,
                                resource,
                            })
                        })
                        .collect::<Result<Vec<_>, String>>()?;
                    list.push(device.create_bind_group(&wgpu::BindGroupDescriptor {
                        label: Some(&pp.name),
                        layout,
                        entries: &entries,
                    }));
                }
                Some((gi, list))
            }
            None => None,
        };
        Ok(PassGpu {
            plan: pp.clone(),
            pipeline,
            reps,
            draw_groups,
            dispatch,
        })
    }

    #[allow(clippy::too_many_arguments)]
    fn bind_group(
        &self,
        gpu: &Gpu,
        pp: &PlanPass,
        entries: &[PlanBinding],
        layout: &wgpu::BindGroupLayout,
        light: Option<u32>,
        slot: u64,
        parity: u32,
    ) -> Result<wgpu::BindGroup, String> {
        enum Res<'a> {
            Buf(wgpu::BufferBinding<'a>),
            View(wgpu::TextureView),
            Sampler(&'a wgpu::Sampler),
        }
        let mut held = vec![];
        for e in entries {
            let r = match &e.source {
                BindSource::Frame => Res::Buf(self.frame_buf.as_entire_buffer_binding()),
                BindSource::Lights => Res::Buf(self.lights_buf.as_entire_buffer_binding()),
                BindSource::Instance => Res::Buf(wgpu::BufferBinding {
                    buffer: &self.instance_buf,
                    offset: slot * SLOT,
                    size: std::num::NonZeroU64::new(16),
                }),
                BindSource::Params => {
                    let block = pp
                        .uniform_blocks
                        .iter()
                        .find(|b| b.global == e.name)
                        .ok_or_else(|| format!("no block for `{}`", e.name))?;
                    let buf = self
                        .param_buffers
                        .get(&(pp.name.clone(), block.global.clone()))
                        .ok_or("parameter buffer missing")?;
                    Res::Buf(buf.as_entire_buffer_binding())
                }
                BindSource::Sampler(name) => Res::Sampler(self.samplers.get(name).ok_or_else(|| format!("sampler `{name}` missing"))?),
                BindSource::Resource(name) | BindSource::Prev(name) => {
                    let prev = matches!(e.source, BindSource::Prev(_));
                    let entry = self.pool.get(name)?;
                    let inst = self.instance_of(name, light);
                    match &e.ty {
                        BindingType::Texture { view_dimension, .. } | BindingType::StorageTexture { view_dimension, .. } => Res::View(
                            Self::view(entry, inst, prev, parity, Some(convert::view_dim(*view_dimension)), None)?,
                        ),
                        _ => Res::Buf(
                            entry
                                .buffer(inst, prev, parity)
                                .ok_or_else(|| format!("`{name}` is not a buffer"))?
                                .as_entire_buffer_binding(),
                        ),
                    }
                }
                BindSource::Draw(_) => return Err("per-draw binding outside the per-draw group".into()),
            };
            held.push((e.binding, r));
        }
        let entries: Vec<wgpu::BindGroupEntry> = held
            .iter()
            .map(|(b, r)| wgpu::BindGroupEntry {
                binding: *b,
                resource: match r {
                    Res::Buf(bb) => wgpu::BindingResource::Buffer(bb.clone()),
                    Res::View(v) => wgpu::BindingResource::TextureView(v),
                    Res::Sampler(s) => wgpu::BindingResource::Sampler(s),
                },
            })
            .collect();
        Ok(gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&pp.name),
            layout,
            entries: &entries,
        }))
    }

    /// Render one frame at time `t` seconds. GPU errors come back as values naming the pass.
    pub fn render_frame(&mut self, gpu: &Gpu, t: f32) -> Result<(), String> {
        let (w, h) = self.plan.resolution;
        let cam = &self.scene.camera;
        let view = cam.view();
        let proj = cam.proj(w as f32 / h.max(1) as f32);
        let vp = proj * view;
        let frame = FrameBlock {
            view: view.to_cols_array_2d(),
            proj: proj.to_cols_array_2d(),
            view_proj: vp.to_cols_array_2d(),
            inv_view_proj: vp.inverse().to_cols_array_2d(),
            camera_pos: [cam.position.x, cam.position.y, cam.position.z, 1.0],
            resolution: [w as f32, h as f32, 1.0 / w as f32, 1.0 / h as f32],
            time: t,
            frame_index: self.frame_index as u32,
            light_count: self.lights.len() as u32,
            _pad: 0,
        };
        gpu.queue.write_buffer(&self.frame_buf, 0, bytemuck::bytes_of(&frame));
        let blocks: Vec<LightBlock> = self.lights.iter().map(|l| l.at(t).block(self.bounds)).collect();
        if !blocks.is_empty() {
            gpu.queue.write_buffer(&self.lights_buf, 0, bytemuck::cast_slice(&blocks));
        }
        let parity = (self.frame_index & 1) as usize;
        let mut buffers = vec![];
        let mut cpu_us = vec![];
        for (pi, pass) in self.passes.iter().enumerate() {
            let start = Instant::now();
            let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let mut enc = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some(&pass.plan.name),
            });
            let n = pass.reps.len();
            for (ri, rep) in pass.reps.iter().enumerate() {
                // The first repetition writes the pass's start time, the last its end.
                let ts = self
                    .timer
                    .as_ref()
                    .map(|t| (t, (ri == 0).then_some(2 * pi as u32), (ri + 1 == n).then_some(2 * pi as u32 + 1)))
                    .filter(|(_, b, e)| b.is_some() || e.is_some());
                match &pass.pipeline {
                    PipelineKind::Compute(p) => {
                        let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                            label: Some(&pass.plan.name),
                            timestamp_writes: ts.map(|(t, b, e)| wgpu::ComputePassTimestampWrites {
                                query_set: &t.set,
                                beginning_of_pass_write_index: b,
                                end_of_pass_write_index: e,
                            }),
                        });
                        cp.set_pipeline(p);
                        for (g, bg) in &rep.groups[parity] {
                            cp.set_bind_group(*g, bg, &[]);
                        }
                        cp.dispatch_workgroups(pass.dispatch[0], pass.dispatch[1], pass.dispatch[2]);
                    }
                    PipelineKind::Render(p) => {
                        let colors: Vec<Option<wgpu::RenderPassColorAttachment>> = pass
                            .plan
                            .color
                            .iter()
                            .zip(&rep.color[parity])
                            .map(|(a, v)| {
                                Some(wgpu::RenderPassColorAttachment {
                                    view: v,
                                    depth_slice: None,
                                    resolve_target: None,
                                    ops: wgpu::Operations {
                                        load: match &a.clear {
                                            Some(c) => wgpu::LoadOp::Clear(wgpu::Color {
                                                r: c.first().copied().unwrap_or(0.0),
                                                g: c.get(1).copied().unwrap_or(0.0),
                                                b: c.get(2).copied().unwrap_or(0.0),
                                                a: c.get(3).copied().unwrap_or(0.0),
                                            }),
                                            None => wgpu::LoadOp::Load,
                                        },
                                        store: wgpu::StoreOp::Store,
                                    },
                                })
                            })
                            .collect();
                        let depth =
                            pass.plan
                                .depth
                                .as_ref()
                                .zip(rep.depth[parity].as_ref())
                                .map(|(a, v)| wgpu::RenderPassDepthStencilAttachment {
                                    view: v,
                                    depth_ops: Some(wgpu::Operations {
                                        load: match &a.clear {
                                            Some(c) => wgpu::LoadOp::Clear(c.first().copied().unwrap_or(1.0) as f32),
                                            None => wgpu::LoadOp::Load,
                                        },
                                        store: wgpu::StoreOp::Store,
                                    }),
                                    stencil_ops: None,
                                });
                        let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                            label: Some(&pass.plan.name),
                            color_attachments: &colors,
                            depth_stencil_attachment: depth,
                            timestamp_writes: ts.map(|(t, b, e)| wgpu::RenderPassTimestampWrites {
                                query_set: &t.set,
                                beginning_of_pass_write_index: b,
                                end_of_pass_write_index: e,
                            }),
                            occlusion_query_set: None,
                            multiview_mask: pass.plan.multiview.and_then(|n| NonZeroU32::new((1u32 << n) - 1)),
                        });
                        rp.set_pipeline(p);
                        for (g, bg) in &rep.groups[parity] {
                            rp.set_bind_group(*g, bg, &[]);
                        }
                        match &pass.plan.work {
                            Work::Scene => {
                                for (mi, mesh) in self.scene_gpu.meshes.iter().enumerate() {
                                    if let Some((g, list)) = &pass.draw_groups {
                                        rp.set_bind_group(*g, &list[mi], &[]);
                                    }
                                    rp.set_vertex_buffer(0, mesh.vertices.slice(..));
                                    rp.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                                    rp.draw_indexed(0..mesh.index_count, 0, 0..pass.plan.instances.max(1));
                                }
                            }
                            Work::Vertices(n) => rp.draw(0..*n, 0..pass.plan.instances.max(1)),
                            Work::Fullscreen | Work::Dispatch { .. } => rp.draw(0..3, 0..1),
                        }
                    }
                }
            }
            let cb = enc.finish();
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(format!("pass `{}`: {e}", pass.plan.name));
            }
            buffers.push(cb);
            cpu_us.push(start.elapsed().as_secs_f64() * 1e6);
        }
        if let Some(t) = &self.timer {
            let mut enc = gpu
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("timestamps") });
            enc.resolve_query_set(&t.set, 0..(self.passes.len() * 2) as u32, &t.resolve, 0);
            enc.copy_buffer_to_buffer(&t.resolve, 0, &t.readback, 0, t.resolve.size());
            buffers.push(enc.finish());
        }
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        gpu.queue.submit(buffers);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(format!("submitting the frame: {e}"));
        }
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| format!("waiting for the GPU: {e}"))?;
        let gpu_ms = self.read_timestamps(gpu)?;
        self.last_timings = self
            .passes
            .iter()
            .enumerate()
            .map(|(i, p)| PassTiming {
                pass: p.plan.name.clone(),
                repetitions: p.reps.len() as u32,
                gpu_ms: gpu_ms.as_ref().map(|v| v[i]),
                cpu_encode_us: cpu_us[i],
            })
            .collect();
        let errors = gpu.take_uncaptured();
        if !errors.is_empty() {
            return Err(errors.join("; "));
        }
        self.frame_index += 1;
        Ok(())
    }

    fn read_timestamps(&self, gpu: &Gpu) -> Result<Option<Vec<f64>>, String> {
        let Some(t) = &self.timer else { return Ok(None) };
        let slice = t.readback.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        gpu.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| e.to_string())?;
        let ms = {
            let data = slice.get_mapped_range().map_err(|e| e.to_string())?;
            let ticks: &[u64] = bytemuck::cast_slice(&data);
            (0..self.passes.len())
                .map(|i| ticks[2 * i + 1].saturating_sub(ticks[2 * i]) as f64 * t.period_ns as f64 / 1e6)
                .collect()
        };
        t.readback.unmap();
        Ok(Some(ms))
    }

    /// Every (instance, layer) of a resource, for dumps: per light and per face.
    pub fn slices(&self, name: &str) -> Result<Vec<(u32, u32)>, String> {
        let e = self.pool.get(name)?;
        Ok((0..e.key.instances).flat_map(|i| (0..e.key.layers).map(move |l| (i, l))).collect())
    }

    /// The current (last rendered) value of a texture slice.
    pub fn read_texture(&self, gpu: &Gpu, name: &str, instance: u32, layer: u32) -> Result<Image, String> {
        let e = self.pool.get(name)?;
        // The frame that was just rendered used parity (frame_index - 1).
        let parity = (self.frame_index.wrapping_sub(1) & 1) as u32;
        let tex = e
            .texture(instance, false, parity)
            .ok_or_else(|| format!("`{name}` is a buffer; use read_buffer"))?;
        super::readback::read_texture(gpu, tex, layer)
    }

    /// The current value of a buffer resource as f32 words.
    pub fn read_buffer(&self, gpu: &Gpu, name: &str, instance: u32) -> Result<Vec<f32>, String> {
        let e = self.pool.get(name)?;
        let parity = (self.frame_index.wrapping_sub(1) & 1) as u32;
        let buf = e.buffer(instance, false, parity).ok_or_else(|| format!("`{name}` is a texture"))?;
        super::readback::read_buffer(gpu, buf)
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }
}
