//! A second executor, deliberately small: it runs `lightbench plan --json` output with the
//! scene's data and nothing else (no pipeline file, no shader file), and must render what the
//! real executor renders. It proves the Plan is enough to run (`docs/plan.md`). It renders a
//! first frame of every option of both bundled pipelines — scene,
//! full-screen, vertex-pulling and light-volume draws, compute, per-light, per-face and per-mip
//! repetitions with the copies the Plan names, multiview, parameter blocks, data resources from
//! the Plan's `contents`, history (the previous frame's copy still cleared), jitter, WGSL and
//! GLSL stages compiled from the Plan's text, ray queries — and refuses the rest by name
//! (textured scenes, external resources). From the executor crate it borrows only what reads
//! no Plan: the mapping of the Plan's enums to wgpu's (`convert`), texture read-back, the
//! scene's triangles (`scene_gpu::area_lights` for the emissive ones, `scene_gpu::triangles`
//! for all), the light-volume meshes (`light_volumes`) and the scene's acceleration structure
//! with its hit data (`accel`).

use crate::gpu_common::{gpu, render_with, root};
use lightbench::gpu::{accel, convert, light_volumes, readback, scene_gpu, Gpu};
use lightbench::io::Image;
use lightbench::scene::{AlphaMode, Scene};
use lightbench_compiler::abi::{FrameBlock, InstanceBlock, MaterialBlock, MeshBlock, Vertex};
use lightbench_compiler::ir::{Draw, LayerSel, Load, MipSel, ParamType, ParamValue};
use lightbench_compiler::layout::{BindSource, DrawSlot, FieldSource, FieldType, UniformBlock};
use lightbench_compiler::plan::{Plan, PlanPass, PlanRep, ResourceId, ResourceShape, ShaderLanguage, Work};
use wgpu::util::DeviceExt;

type Res<T> = Result<T, String>;

/// Refuse what this executor does not carry out.
fn unsupported<T>(what: impl std::fmt::Display) -> Res<T> {
    Err(format!("the small executor does not support {what}"))
}

/// A resource's GPU objects, one per instance.
enum Held {
    Textures(Vec<wgpu::Texture>),
    Buffers(Vec<wgpu::Buffer>),
    /// The scene's acceleration structure (`Traced`).
    Scene,
}

/// A scene mesh ready to draw with its per-draw bind-group contents.
struct MeshGpu {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    count: u32,
    mesh: wgpu::Buffer,
    material: wgpu::Buffer,
    /// Blended (`draw: Transparent` draws it), and how far its bounds' centre is from the eye.
    blend: bool,
    distance: f32,
}

struct Small<'a> {
    gpu: &'a Gpu,
    plan: &'a Plan,
    held: Vec<Held>,
    samplers: Vec<wgpu::Sampler>,
    frame: wgpu::Buffer,
    lights_buf: wgpu::Buffer,
    /// The scene's emissive triangles (`area_lights`), at least one entry.
    area_lights: wgpu::Buffer,
    /// The scene's drawn triangles in world space (`triangles`).
    triangles: wgpu::TextureView,
    /// How many triangles `triangles` holds (what `draw: Triangles(n)` instances).
    triangle_count: u32,
    /// The scene's light array (the lights that are on, in scene order, then the emitter
    /// lights: what the Plan's runs index), and
    /// the volumes a light-volume draw takes for them (`light_volumes`).
    lights: Vec<lightbench::scene::Light>,
    volumes: light_volumes::LightVolumes,
    volumes_buf: wgpu::Buffer,
    meshes: Vec<MeshGpu>,
    /// The per-draw textures of an untextured material (white, flat normal) and its sampler.
    white: [wgpu::TextureView; 3],
    material_sampler: wgpu::Sampler,
    /// What rays are traced against and hits shaded with, where the Plan traces rays.
    traced: Option<Traced>,
}

/// The scene's acceleration structure and hit data, built from the scene alone (the
/// executor crate's `accel`, which reads no Plan) for a Plan that binds them.
struct Traced {
    accel: accel::Accel,
    hits: accel::HitData,
    maps: accel::HitMaps,
}

impl Traced {
    fn build(gpu: &Gpu, plan: &Plan, scene: &Scene) -> Res<Option<Traced>> {
        let traces = plan
            .resources
            .iter()
            .any(|r| matches!(r.shape, ResourceShape::AccelerationStructure));
        if !traces {
            return Ok(None);
        }
        let (d, q) = (&gpu.device, &gpu.queue);
        let scene_gpu = scene_gpu::SceneGpu::new(d, q, &mut scene.clone()).map_err(|e| e.to_string())?;
        Ok(Some(Traced {
            accel: accel::Accel::build(d, q, &scene_gpu.meshes, scene, &[]).map_err(|e| e.to_string())?,
            hits: accel::HitData::build((d, q), &scene_gpu, scene).map_err(|e| e.to_string())?,
            maps: accel::HitMaps::build((d, q), &scene_gpu, scene).map_err(|e| e.to_string())?,
        }))
    }
}

impl<'a> Small<'a> {
    fn new(gpu: &'a Gpu, plan: &'a Plan, scene: &Scene) -> Res<Small<'a>> {
        if !scene.textures.is_empty() {
            return unsupported("textured scenes");
        }
        let d = &gpu.device;
        let held = plan.resources.iter().map(|r| resource(gpu, r)).collect::<Res<_>>()?;
        let samplers = plan.samplers.iter().map(|s| d.create_sampler(&convert::sampler(s)));
        // The light array: the lights that are on, then the emitter lights.
        let lights: Vec<_> = scene.light_array().iter().map(|l| l.at(0.0)).collect();
        let bounds = scene.bounds();
        let mut blocks: Vec<_> = lights.iter().map(|l| l.block(bounds)).collect();
        if blocks.is_empty() {
            blocks.push(bytemuck::Zeroable::zeroed());
        }
        let volumes = light_volumes::LightVolumes::new();
        let (mut area_lights, _) = scene_gpu::area_lights(scene);
        if area_lights.is_empty() {
            area_lights.push(bytemuck::Zeroable::zeroed());
        }
        let (w, h) = plan.resolution;
        let (view, proj) = (scene.camera.view(), scene.camera.proj(w as f32 / h as f32));
        // The first frame's sub-pixel jitter where the Plan asks for it, as a shift in NDC.
        let j = if plan.jitter { lightbench::gpu::halton_jitter(0) } else { [0.0; 2] };
        let proj = glam::Mat4::from_translation(glam::Vec3::new(2.0 * j[0] / w as f32, -2.0 * j[1] / h as f32, 0.0)) * proj;
        let vp = proj * view;
        let frame = FrameBlock {
            view: view.to_cols_array_2d(),
            proj: proj.to_cols_array_2d(),
            view_proj: vp.to_cols_array_2d(),
            inv_view_proj: vp.inverse().to_cols_array_2d(),
            prev_view_proj: vp.to_cols_array_2d(),
            prev_inv_view_proj: vp.inverse().to_cols_array_2d(),
            camera_pos: scene.camera.position.extend(1.0).to_array(),
            resolution: [w as f32, h as f32, 1.0 / w as f32, 1.0 / h as f32],
            jitter: [j[0], j[1], j[0], j[1]],
            time: 0.0,
            frame_index: 0,
            light_count: scene.active_lights().len() as u32,
            scene_radius: ((bounds.1 - bounds.0).length() * 0.5).max(1e-6),
        };
        let texel = |rgba: [u8; 4], format| {
            let desc = texture_desc((1, 1, 1, 1), format, wgpu::TextureUsages::TEXTURE_BINDING);
            let t = d.create_texture_with_data(&gpu.queue, &desc, wgpu::util::TextureDataOrder::LayerMajor, &rgba);
            t.create_view(&Default::default())
        };
        Ok(Small {
            gpu,
            plan,
            held,
            samplers: samplers.collect(),
            frame: init(d, bytemuck::bytes_of(&frame), wgpu::BufferUsages::UNIFORM),
            lights_buf: init(d, bytemuck::cast_slice(&blocks), wgpu::BufferUsages::STORAGE),
            area_lights: init(d, bytemuck::cast_slice(&area_lights), wgpu::BufferUsages::STORAGE),
            triangles: scene_gpu::triangles((d, &gpu.queue), scene).map_err(|e| e.to_string())?,
            triangle_count: scene_gpu::triangle_count(scene) as u32,
            volumes_buf: init(d, bytemuck::cast_slice(&volumes.corners), wgpu::BufferUsages::STORAGE),
            volumes,
            lights,
            meshes: meshes(d, scene),
            white: [
                texel([255; 4], wgpu::TextureFormat::Rgba8UnormSrgb),
                texel([255; 4], wgpu::TextureFormat::Rgba8Unorm),
                texel([128, 128, 255, 255], wgpu::TextureFormat::Rgba8Unorm),
            ],
            material_sampler: d.create_sampler(&Default::default()),
            traced: Traced::build(gpu, plan, scene)?,
        })
    }

    /// One frame: every pass, every repetition, each its own GPU pass.
    fn frame(&self) -> Res<()> {
        let scope = self.gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut enc = self.gpu.device.create_command_encoder(&Default::default());
        for pass in &self.plan.passes {
            let pipeline = self.pipeline(pass)?;
            let params: Vec<wgpu::Buffer> = pass.uniform_blocks.iter().map(|b| self.block(b)).collect();
            for rep in &pass.reps {
                self.record(&mut enc, pass, &pipeline, &params, rep)?;
            }
        }
        self.gpu.queue.submit([enc.finish()]);
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(format!("the small executor's frame: {e}")),
            None => Ok(()),
        }
    }

    fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        pass: &PlanPass,
        pipeline: &Pipeline,
        params: &[wgpu::Buffer],
        rep: &PlanRep,
    ) -> Res<()> {
        let instance = init(
            &self.gpu.device,
            bytemuck::bytes_of(&self.instance(pass, rep)),
            wgpu::BufferUsages::UNIFORM,
        );
        let groups = self.groups(pass, pipeline, (params, &instance), rep)?;
        match (&pass.work, &pipeline.kind) {
            (
                Work::Compute {
                    groups: n,
                    workgroup_size: size,
                    sized_from,
                },
                Kind::Compute(p),
            ) => {
                let mut cp = enc.begin_compute_pass(&Default::default());
                cp.set_pipeline(p);
                groups.iter().for_each(|(i, g)| cp.set_bind_group(*i, g, &[]));
                // A per-mip pass sized from a texture covers the repetition's level.
                let n = match (rep.mip, sized_from) {
                    (Some(_), Some(_)) => {
                        let [w, h, ..] = self.instance(pass, rep).target_size;
                        [(w as u32).div_ceil(size[0].max(1)), (h as u32).div_ceil(size[1].max(1)), 1]
                    }
                    _ => *n,
                };
                cp.dispatch_workgroups(n[0], n[1], n[2]);
            }
            (work, Kind::Render(p)) => {
                let targets = work.targets().ok_or("targets")?;
                let colors = targets
                    .color
                    .iter()
                    .map(|c| self.attachment(c.resource, (c.layer, c.mip), rep))
                    .collect::<Res<Vec<_>>>()?;
                let depth = targets
                    .depth
                    .as_ref()
                    .map(|d| self.attachment(d.resource, (d.layer, d.mip), rep))
                    .transpose()?;
                let color_attachments: Vec<_> = targets
                    .color
                    .iter()
                    .zip(&colors)
                    .map(|(c, view)| {
                        let load = match c.load {
                            Load::Clear([r, g, b, a]) => wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                            Load::Load => wgpu::LoadOp::Load,
                        };
                        let ops = wgpu::Operations {
                            load,
                            store: wgpu::StoreOp::Store,
                        };
                        Some(wgpu::RenderPassColorAttachment {
                            view,
                            depth_slice: None,
                            resolve_target: None,
                            ops,
                        })
                    })
                    .collect();
                let depth_stencil_attachment = targets.depth.as_ref().zip(depth.as_ref()).map(|(d, view)| {
                    let load = match d.load {
                        Load::Clear(v) => wgpu::LoadOp::Clear(v as f32),
                        Load::Load => wgpu::LoadOp::Load,
                    };
                    let depth_ops = Some(wgpu::Operations {
                        load,
                        store: wgpu::StoreOp::Store,
                    });
                    wgpu::RenderPassDepthStencilAttachment {
                        view,
                        depth_ops,
                        stencil_ops: None,
                    }
                });
                let desc = wgpu::RenderPassDescriptor {
                    color_attachments: &color_attachments,
                    depth_stencil_attachment,
                    multiview_mask: multiview_mask(work),
                    ..Default::default()
                };
                let mut rp = enc.begin_render_pass(&desc);
                rp.set_pipeline(p);
                groups.iter().for_each(|(i, g)| rp.set_bind_group(*i, g, &[]));
                self.draw(&mut rp, (pass, rep), work, pipeline)?;
            }
            _ => return unsupported(format!("the work of pass `{}`", pass.name)),
        }
        Ok(())
    }

    /// The repetition's bind groups, except the per-draw one.
    fn groups(
        &self,
        pass: &PlanPass,
        pipeline: &Pipeline,
        (params, instance): (&[wgpu::Buffer], &wgpu::Buffer),
        rep: &PlanRep,
    ) -> Res<Vec<(u32, wgpu::BindGroup)>> {
        let mut out = vec![];
        for g in pass.bind_groups.iter().filter(|g| !g.is_per_draw()) {
            let views: Vec<Option<wgpu::TextureView>> = g.entries.iter().map(|e| self.read_view(pass, e, rep)).collect();
            let mut entries = vec![];
            for (e, view) in g.entries.iter().zip(&views) {
                let resource = match (&e.source, view) {
                    (BindSource::Frame, _) => self.frame.as_entire_binding(),
                    (BindSource::Lights, _) => self.lights_buf.as_entire_binding(),
                    (BindSource::AreaLights, _) => self.area_lights.as_entire_binding(),
                    (BindSource::Triangles, _) => wgpu::BindingResource::TextureView(&self.triangles),
                    (BindSource::LightVolumes, _) => self.volumes_buf.as_entire_binding(),
                    (hit @ (BindSource::HitTriangles | BindSource::HitMaterials | BindSource::HitEmitters), _) => {
                        let h = &self.traced()?.hits;
                        match hit {
                            BindSource::HitTriangles => wgpu::BindingResource::TextureView(&h.triangles),
                            BindSource::HitMaterials => h.materials.as_entire_binding(),
                            _ => wgpu::BindingResource::TextureView(&h.emitters),
                        }
                    }
                    (BindSource::HitCorners, _) => wgpu::BindingResource::TextureView(&self.traced()?.maps.corners),
                    (BindSource::HitMaps, _) => wgpu::BindingResource::TextureView(&self.traced()?.maps.maps),
                    (BindSource::Instance, _) => instance.as_entire_binding(),
                    (BindSource::Params, _) => match pass.uniform_blocks.iter().position(|b| b.global == e.name) {
                        Some(i) => params[i].as_entire_binding(),
                        None => return Err(format!("pass `{}`: no parameter block `{}`", pass.name, e.name)),
                    },
                    (BindSource::Sampler(s), _) => wgpu::BindingResource::Sampler(&self.samplers[s.0 as usize]),
                    (BindSource::Resource(_) | BindSource::Prev(_), Some(v)) => wgpu::BindingResource::TextureView(v),
                    (BindSource::Resource(id) | BindSource::Prev(id), None) => match &self.held[id.0 as usize] {
                        Held::Buffers(b) => b[self.slot(*id, rep, matches!(e.source, BindSource::Prev(_)))].as_entire_binding(),
                        Held::Textures(_) => return Err(format!("`{}` bound as a buffer", e.name)),
                        Held::Scene => wgpu::BindingResource::AccelerationStructure(&self.traced()?.accel.tlas),
                    },
                    (other, _) => return unsupported(format!("binding {other:?} in pass `{}`", pass.name)),
                };
                entries.push(wgpu::BindGroupEntry {
                    binding: e.binding,
                    resource,
                });
            }
            let desc = wgpu::BindGroupDescriptor {
                label: None,
                layout: &pipeline.layouts[g.group as usize],
                entries: &entries,
            };
            out.push((g.group, self.gpu.device.create_bind_group(&desc)));
        }
        Ok(out)
    }

    fn traced(&self) -> Res<&Traced> {
        self.traced
            .as_ref()
            .ok_or_else(|| "hit data bound by a Plan without an acceleration structure".into())
    }

    /// The view a texture binding reads: the repetition's instance, the level and layer the
    /// pass's read selects (else all).
    fn read_view(&self, pass: &PlanPass, e: &lightbench_compiler::plan::PlanBinding, rep: &PlanRep) -> Option<wgpu::TextureView> {
        use lightbench_compiler::layout::BindingType as T;
        let (id, prev) = match e.source {
            BindSource::Resource(id) => (id, false),
            BindSource::Prev(id) => (id, true),
            _ => return None,
        };
        let (Held::Textures(t), T::Texture { view_dimension: dim, .. } | T::StorageTexture { view_dimension: dim, .. }) =
            (&self.held[id.0 as usize], &e.ty)
        else {
            return None;
        };
        let read = pass.reads.iter().find(|r| r.resource == id && !r.prev);
        let level = read.and_then(|r| r.mip).and_then(|m| m.level(rep.mip.unwrap_or(0)));
        let layer = read.and_then(|r| r.layer).and_then(|l| l.at(rep.run, self.plan.res(id).layers()));
        Some(view(&t[self.slot(id, rep, prev)], convert::view_dim(*dim), level, layer))
    }

    /// Where the repetition's copy of resource `id` is held: this frame's, or (`prev`) the
    /// previous frame's, which on this first frame is still cleared.
    fn slot(&self, id: ResourceId, rep: &PlanRep, prev: bool) -> usize {
        let copies = if self.plan.res(id).history { 2 } else { 1 };
        (rep.copy_of(id) * copies + prev as u32) as usize
    }

    /// The layer and level of a texture a repetition renders into.
    fn attachment(&self, r: ResourceId, (layer, mip): (LayerSel, MipSel), rep: &PlanRep) -> Res<wgpu::TextureView> {
        let Held::Textures(t) = &self.held[r.0 as usize] else {
            return unsupported("a buffer attachment");
        };
        let level = mip.level(rep.mip.unwrap_or(0));
        let t = &t[self.slot(r, rep, false)];
        let layer = match layer {
            LayerSel::Face => rep.face,
            // Multiview renders every layer at once.
            LayerSel::All => return Ok(view(t, wgpu::TextureViewDimension::D2Array, level, None)),
            other => other.at(rep.run, self.plan.res(r).layers()).unwrap_or(0),
        };
        Ok(view(t, wgpu::TextureViewDimension::D2, level, Some(layer)))
    }

    fn draw(&self, rp: &mut wgpu::RenderPass, (pass, rep): (&PlanPass, &PlanRep), work: &Work, pipeline: &Pipeline) -> Res<()> {
        match work {
            Work::Fullscreen { .. } => rp.draw(0..3, 0..1),
            Work::Raster {
                draw: draw @ (Draw::Scene | Draw::Transparent),
                instances,
                ..
            } => {
                let per_draw = pass.bind_groups.iter().find(|g| g.is_per_draw());
                let blend = *draw == Draw::Transparent;
                let mut meshes: Vec<&MeshGpu> = self.meshes.iter().filter(|m| m.blend == blend).collect();
                if blend {
                    meshes.sort_by(|a, b| b.distance.total_cmp(&a.distance));
                }
                for m in meshes {
                    if let Some(g) = per_draw {
                        let entries = g.entries.iter().map(|e| {
                            let resource = match e.source {
                                BindSource::Draw(DrawSlot::Mesh) => m.mesh.as_entire_binding(),
                                BindSource::Draw(DrawSlot::Material) => m.material.as_entire_binding(),
                                BindSource::Draw(DrawSlot::MaterialSampler) => wgpu::BindingResource::Sampler(&self.material_sampler),
                                BindSource::Draw(DrawSlot::NormalMap) => wgpu::BindingResource::TextureView(&self.white[2]),
                                BindSource::Draw(DrawSlot::BaseColorMap | DrawSlot::EmissiveMap) => {
                                    wgpu::BindingResource::TextureView(&self.white[0])
                                }
                                _ => wgpu::BindingResource::TextureView(&self.white[1]),
                            };
                            wgpu::BindGroupEntry {
                                binding: e.binding,
                                resource,
                            }
                        });
                        let entries: Vec<_> = entries.collect();
                        let layout = &pipeline.layouts[g.group as usize];
                        let group = self.gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                            label: None,
                            layout,
                            entries: &entries,
                        });
                        rp.set_bind_group(g.group, &group, &[]);
                    }
                    rp.set_vertex_buffer(0, m.vertices.slice(..));
                    rp.set_index_buffer(m.indices.slice(..), wgpu::IndexFormat::Uint32);
                    rp.draw_indexed(0..m.count, 0, 0..(*instances).max(1));
                }
            }
            // Vertex pulling: the vertices of a volume per triangle, one instance per triangle.
            Work::Raster {
                draw: Draw::Triangles(n), ..
            } => rp.draw(0..*n, 0..self.triangle_count),
            // The bounding volume of the repetition's light.
            Work::Raster {
                draw: Draw::LightVolume, ..
            } => {
                let light = rep
                    .light
                    .and_then(|l| self.lights.get(l as usize))
                    .ok_or("a light volume without its light")?;
                rp.draw(self.volumes.range_for(light), 0..1);
            }
            Work::Raster {
                draw: Draw::Vertices(n),
                instances,
                ..
            } => rp.draw(0..*n, 0..(*instances).max(1)),
            _ => return unsupported(format!("the draw of pass `{}`", pass.name)),
        }
        Ok(())
    }

    /// The per-repetition block: its light, face, level, run, and the size the pass renders at
    /// (its first target's, or the texture it is sized from, at the level it renders).
    fn instance(&self, pass: &PlanPass, rep: &PlanRep) -> InstanceBlock {
        let sized = match &pass.work {
            Work::Compute { sized_from, .. } => sized_from.map(|r| (r, MipSel::Rep(0))),
            w => w.targets().and_then(|t| {
                let color = t.color.first().map(|c| (c.resource, c.mip));
                color.or(t.depth.as_ref().map(|d| (d.resource, d.mip)))
            }),
        };
        let level = sized.and_then(|(_, m)| m.level(rep.mip.unwrap_or(0))).unwrap_or(0);
        let (w, h) = match sized.map(|(r, _)| &self.plan.res(r).shape) {
            Some(ResourceShape::Texture { extent, .. }) => ((extent.0 >> level).max(1), (extent.1 >> level).max(1)),
            _ => self.plan.resolution,
        };
        InstanceBlock {
            light: rep.light.unwrap_or(0),
            face: rep.face,
            view_count: pass.work.multiview().unwrap_or(1),
            mip: rep.mip.unwrap_or(0),
            target_size: [w as f32, h as f32, 1.0 / w as f32, 1.0 / h as f32],
            repetition: rep.run,
            _pad: [0; 3],
        }
    }

    /// A parameter block at its defaults: each field's value as 32-bit words at its offset.
    fn block(&self, b: &UniformBlock) -> wgpu::Buffer {
        let mut bytes = vec![0u8; (b.size as usize).max(16)];
        for f in &b.fields {
            let words: Vec<u32> = match &f.source {
                FieldSource::Fixed(w) => w.clone(),
                FieldSource::Param(id) => {
                    let p = &self.plan.params[id.0 as usize];
                    match (&p.default, &p.ty) {
                        (ParamValue::Float(x), _) => vec![(*x as f32).to_bits()],
                        (ParamValue::Int(x), _) if f.ty == FieldType::U32 => vec![*x as u32],
                        (ParamValue::Int(x), _) => vec![(*x as i32) as u32],
                        (ParamValue::Bool(x), _) => vec![*x as u32],
                        (ParamValue::Vec(c), _) => (0..f.size as usize / 4)
                            .map(|i| (*c.get(i).unwrap_or(&1.0) as f32).to_bits())
                            .collect(),
                        (ParamValue::Enum(s), ParamType::Enum(opts)) => vec![opts.iter().position(|o| o == s).unwrap_or(0) as u32],
                        (ParamValue::Enum(_), _) => vec![0],
                    }
                }
            };
            for (i, w) in words.iter().enumerate() {
                let at = f.offset as usize + 4 * i;
                bytes[at..at + 4].copy_from_slice(&w.to_le_bytes());
            }
        }
        init(&self.gpu.device, &bytes, wgpu::BufferUsages::UNIFORM)
    }

    fn pipeline(&self, pass: &PlanPass) -> Res<Pipeline> {
        let d = &self.gpu.device;
        let groups = pass.bind_groups.iter().map(|g| g.group + 1).max().unwrap_or(0);
        let layouts: Vec<wgpu::BindGroupLayout> = (0..groups)
            .map(|i| {
                let entries =
                    pass.bind_groups
                        .iter()
                        .filter(|g| g.group == i)
                        .flat_map(|g| &g.entries)
                        .map(|e| wgpu::BindGroupLayoutEntry {
                            binding: e.binding,
                            visibility: convert::stages(&e.visibility),
                            ty: convert::binding_type(&e.ty),
                            count: None,
                        });
                d.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: None,
                    entries: &entries.collect::<Vec<_>>(),
                })
            })
            .collect();
        let refs: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(Some).collect();
        let layout = d.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &refs,
            immediate_size: 0,
        });
        // Each stage's module from the Plan's own text of its file.
        let mut stages = vec![];
        for s in &pass.stages {
            let shader = self
                .plan
                .shader(&s.file)
                .ok_or_else(|| format!("the Plan has no text for `{}`", s.file))?;
            let source = match shader.language {
                ShaderLanguage::Wgsl => wgpu::ShaderSource::Wgsl(shader.text.as_str().into()),
                // GLSL 450, of the stage naming it.
                ShaderLanguage::Glsl => {
                    let stage = match s.stage {
                        lightbench_compiler::ir::Stage::Vertex => naga::ShaderStage::Vertex,
                        lightbench_compiler::ir::Stage::Fragment => naga::ShaderStage::Fragment,
                        lightbench_compiler::ir::Stage::Compute => naga::ShaderStage::Compute,
                    };
                    let module = naga::front::glsl::Frontend::default()
                        .parse(&naga::front::glsl::Options::from(stage), &shader.text)
                        .map_err(|e| format!("{}: {e:?}", s.file))?;
                    wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module))
                }
            };
            let module = d.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&s.file),
                source,
            });
            let constants: Vec<(&str, f64)> = s.constants.iter().map(|(k, v)| (k.as_str(), *v)).collect();
            stages.push((module, s.entry.as_str(), constants));
        }
        let kind = match &pass.work {
            Work::Compute { .. } => {
                let (m, entry, c) = &stages[0];
                Kind::Compute(d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: None,
                    layout: Some(&layout),
                    module: m,
                    entry_point: Some(entry),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: c,
                        ..Default::default()
                    },
                    cache: None,
                }))
            }
            work => Kind::Render(render_pipeline(d, work, &layout, &stages)),
        };
        Ok(Pipeline { kind, layouts })
    }

    /// Read a texture resource's first instance, layer 0.
    fn read(&self, name: &str) -> Image {
        let id = self.plan.resource_id(name).unwrap();
        let Held::Textures(t) = &self.held[id.0 as usize] else {
            panic!("`{name}` is a buffer")
        };
        readback::read_texture(self.gpu, &t[0], 0).unwrap()
    }
}

enum Kind {
    Render(wgpu::RenderPipeline),
    Compute(wgpu::ComputePipeline),
}

struct Pipeline {
    kind: Kind,
    layouts: Vec<wgpu::BindGroupLayout>,
}

type Stage<'s> = (wgpu::ShaderModule, &'s str, Vec<(&'s str, f64)>);

fn render_pipeline(d: &wgpu::Device, work: &Work, layout: &wgpu::PipelineLayout, stages: &[Stage]) -> wgpu::RenderPipeline {
    let targets = work.targets().cloned().unwrap_or_default();
    let color: Vec<_> = targets
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
    let (cull, scene) = match work {
        Work::Raster { cull, draw, .. } => (convert::cull(*cull), draw.uses_scene()),
        _ => (None, false),
    };
    // The standard vertex layout (`shaders/lib/mesh.wgsl`): locations 0..4 of `abi::Vertex`.
    let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4, 4 => Float32x2];
    let vertex = [Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &attributes,
    })];
    let (vm, ventry, vc) = &stages[0];
    let fragment = stages.get(1).map(|(m, e, c)| wgpu::FragmentState {
        module: m,
        entry_point: Some(e),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants: c,
            ..Default::default()
        },
        targets: &color,
    });
    d.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: None,
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: vm,
            entry_point: Some(ventry),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: vc,
                ..Default::default()
            },
            buffers: if scene { &vertex } else { &[] },
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: cull,
            ..Default::default()
        },
        depth_stencil: targets.depth.as_ref().map(|t| wgpu::DepthStencilState {
            format: convert::format(t.format),
            depth_write_enabled: Some(t.write),
            depth_compare: Some(convert::compare(t.compare)),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment,
        multiview_mask: multiview_mask(work),
        cache: None,
    })
}

/// The views a multiview pass renders, one bit each.
fn multiview_mask(work: &Work) -> Option<std::num::NonZeroU32> {
    work.multiview().and_then(|n| std::num::NonZeroU32::new((1u32 << n) - 1))
}

fn texture_desc(
    (w, h, layers, mips): (u32, u32, u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::TextureDescriptor<'static> {
    wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: layers,
        },
        mip_level_count: mips,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    }
}

/// A resource's instances as the Plan describes them; a data resource's filled with the
/// Plan's `contents`.
fn resource(gpu: &Gpu, r: &lightbench_compiler::plan::PlanResource) -> Res<Held> {
    if r.external {
        return unsupported(format!("external resource `{}`", r.name));
    }
    let d = &gpu.device;
    let contents = match (r.data, &r.contents) {
        (true, Some(bytes)) => Some(bytes.as_slice()),
        (true, None) => return Err(format!("data resource `{}` without contents", r.name)),
        (false, _) => None,
    };
    // Each instance, and its previous frame's copy after it where it keeps one (`slot`).
    let n = r.instances.max(1) as usize * if r.history { 2 } else { 1 };
    Ok(match &r.shape {
        ResourceShape::Texture {
            format,
            extent,
            layers,
            mips,
            ..
        } => {
            let usage = convert::usage(&r.usage) | wgpu::TextureUsages::COPY_SRC;
            let desc = texture_desc((extent.0, extent.1, *layers, *mips), convert::format(*format), usage);
            let textures: Vec<_> = (0..n).map(|_| d.create_texture(&desc)).collect();
            if let Some(bytes) = contents {
                let layout = wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(extent.0 * format.bytes()),
                    rows_per_image: Some(extent.1),
                };
                for t in &textures {
                    gpu.queue.write_texture(t.as_image_copy(), bytes, layout, desc.size);
                }
            }
            Held::Textures(textures)
        }
        ResourceShape::Buffer { size, .. } => Held::Buffers(
            (0..n)
                .map(|_| {
                    let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
                    let mut bytes = contents.map(<[u8]>::to_vec).unwrap_or_default();
                    bytes.resize((size.max(&4).div_ceil(4) * 4) as usize, 0);
                    init(d, &bytes, usage)
                })
                .collect(),
        ),
        ResourceShape::AccelerationStructure => Held::Scene,
    })
}

fn view(t: &wgpu::Texture, dimension: wgpu::TextureViewDimension, level: Option<u32>, layer: Option<u32>) -> wgpu::TextureView {
    let depth = t.format().is_depth_stencil_format();
    t.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(dimension),
        aspect: if depth {
            wgpu::TextureAspect::DepthOnly
        } else {
            wgpu::TextureAspect::All
        },
        base_mip_level: level.unwrap_or(0),
        mip_level_count: level.map(|_| 1),
        base_array_layer: layer.unwrap_or(0),
        array_layer_count: layer.map(|_| 1),
        ..Default::default()
    })
}

fn init(d: &wgpu::Device, contents: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents,
        usage,
    })
}

/// The meshes drawn, in scene order, with their blocks: `draw: Scene` draws the opaque and
/// masked ones, `draw: Transparent` the blended ones from far to near the eye.
fn meshes(d: &wgpu::Device, scene: &Scene) -> Vec<MeshGpu> {
    let drawn = scene.meshes.iter().filter(|m| !m.indices.is_empty());
    drawn
        .map(|m| {
            let mat = &scene.materials[m.material];
            let [r0, r1] = mat.uv_transform;
            let material = MaterialBlock {
                base_color: mat.base_color,
                emissive: [mat.emissive[0], mat.emissive[1], mat.emissive[2], 0.0],
                uv_row0: [r0[0], r0[1], r0[2], 0.0],
                uv_row1: [r1[0], r1[1], r1[2], 0.0],
                metallic: mat.metallic,
                roughness: mat.roughness,
                normal_scale: mat.normal_scale,
                has_normal_map: 0,
                alpha_cutoff: if let AlphaMode::Mask(c) = mat.alpha { c } else { 0.0 },
                occlusion_strength: 0.0,
                uv_sets: mat.uv_sets,
                double_sided: mat.double_sided as u32,
            };
            let mesh = MeshBlock {
                model: m.transform.to_cols_array_2d(),
                normal_matrix: m.transform.inverse().transpose().to_cols_array_2d(),
            };
            MeshGpu {
                vertices: init(d, bytemuck::cast_slice(&m.vertices), wgpu::BufferUsages::VERTEX),
                indices: init(d, bytemuck::cast_slice(&m.indices), wgpu::BufferUsages::INDEX),
                count: m.drawn_indices(),
                mesh: init(d, bytemuck::bytes_of(&mesh), wgpu::BufferUsages::UNIFORM),
                material: init(d, bytemuck::bytes_of(&material), wgpu::BufferUsages::UNIFORM),
                blend: mat.alpha == AlphaMode::Blend,
                distance: centre(m).distance(scene.camera.position),
            }
        })
        .collect()
}

/// The world-space centre of a mesh's bounding box.
fn centre(m: &lightbench::scene::Mesh) -> glam::Vec3 {
    let points = m.vertices.iter().map(|v| glam::Vec3::from(v.position));
    let (lo, hi) = points.fold((glam::Vec3::MAX, glam::Vec3::MIN), |(lo, hi), p| (lo.min(p), hi.max(p)));
    m.transform.transform_point3((lo + hi) * 0.5)
}

fn rmse(a: &Image, b: &Image) -> f64 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let sum: f64 = a.rgba.iter().zip(&b.rgba).map(|(x, y)| ((x - y) as f64).powi(2)).sum();
    (sum / a.rgba.len() as f64).sqrt()
}

/// `pipeline`'s Plan with `variants` for a built-in scene at 64², from `plan --json` only,
/// rendered by the small executor: its linear image and its output equal the real executor's.
fn renders_as_the_executor_does(pipeline: &str, scene_name: &str, variants: &[(&str, &str)]) -> Plan {
    let mut args = vec!["plan", pipeline, "--scene", scene_name, "--size", "64x64", "--json"];
    let chosen: Vec<String> = variants.iter().map(|(v, o)| format!("{v}={o}")).collect();
    chosen.iter().for_each(|c| args.extend(["--variant", c.as_str()]));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .args(&args)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let plan: Plan = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(plan.format, lightbench_compiler::plan::FORMAT);
    let scene = lightbench::scene::load::load_sized(scene_name, Some((64, 64)), &[]).unwrap();
    let gpu = gpu();
    let small = Small::new(&gpu, &plan, &scene).unwrap_or_else(|e| panic!("{e}"));
    small.frame().unwrap_or_else(|e| panic!("{e}"));
    let real = render_with(&gpu, &root().join(pipeline), &scene, variants, 1);
    let hdr = rmse(&small.read("hdr"), &real.read_texture(&gpu, "hdr", 0, 0).unwrap());
    let output = rmse(&small.read(&plan.output_resource().name), &crate::gpu_common::output(&gpu, &real));
    eprintln!(
        "{pipeline} {variants:?} on {scene_name}: {} passes, RMSE hdr {hdr:e}, output {output:e}",
        plan.passes.len()
    );
    assert!(hdr <= 1e-6 && output <= 1e-6, "{scene_name}: hdr {hdr}, output {output}");
    let lit = small.read("hdr").rgba.iter().filter(|v| **v > 0.01).count();
    assert!(
        lit > 1000,
        "{scene_name}: the image is lit ({lit} values), not two blank images agreeing"
    );
    plan
}

/// The names of the Plan's data resources that carry their bytes.
fn carried(plan: &Plan) -> Vec<&str> {
    plan.resources
        .iter()
        .filter(|r| r.data && r.contents.as_ref().is_some_and(|c| c.len() as u64 == r.bytes))
        .map(|r| r.name.as_str())
        .collect()
}

#[test]
fn a_plan_alone_renders_the_cornell_box_as_the_executor_does() {
    renders_as_the_executor_does("pipelines/deferred.ron", "cornell", &[]);
}

#[test]
fn a_plan_alone_renders_many_lights_as_the_executor_does() {
    renders_as_the_executor_does("pipelines/deferred.ron", "many_lights", &[]);
}

/// The LTC table (a `data` buffer) travels in the Plan: area lights render from the JSON.
#[test]
fn a_plan_alone_renders_area_lights_from_the_data_it_carries() {
    let plan = renders_as_the_executor_does("pipelines/deferred.ron", "cornell_lamp", &[("area_lights", "ltc")]);
    assert_eq!(carried(&plan), ["ltc"]);
}

/// SSAO's kernel and noise (`data` buffers) travel in the Plan.
#[test]
fn a_plan_alone_renders_ssao_from_the_data_it_carries() {
    let step = root().join("scenes/step.ron");
    let plan = renders_as_the_executor_does("pipelines/deferred_gi.ron", step.to_str().unwrap(), &[("ao", "ssao")]);
    assert!(plan.pass("ssao").is_some(), "the scene calls for AO");
    let carried = carried(&plan);
    assert!(carried.contains(&"ssao.kernel") && carried.contains(&"ssao.noise"), "{carried:?}");
}

/// The executor runs the copies and data the Plan names, so a Plan whose copies name one its
/// resource does not have, or whose data resource carries no bytes, is refused by name.
#[test]
fn a_plan_with_a_missing_copy_or_missing_data_is_refused_by_name() {
    let gpu = gpu();
    let compile = |scene: &lightbench::scene::Scene, variants: &[(String, String)]| {
        lightbench::render::compile(&gpu, &root().join("pipelines/deferred.lbp"), None, scene, variants)
            .unwrap_or_else(|e| panic!("{e}"))
            .0
    };
    let refusal = |exe, scene| lightbench::gpu::Executor::new(&gpu, exe, scene).err().expect("refused").to_string();

    // The Cornell box's light casts shadows: its lighting pass binds copy 0 of its cube map.
    let cornell = lightbench::scene::load::load_sized("cornell", Some((32, 32)), &[]).unwrap();
    let mut exe = compile(&cornell, &[]);
    let pass = exe.plan.passes.iter_mut().find(|p| p.name == "light_point").unwrap();
    let copy = &mut pass.reps[0].copies[0];
    copy.instance = 7;
    let resource = exe.plan.resources[copy.resource.0 as usize].name.clone();
    let err = refusal(&exe, &cornell);
    assert!(
        err.contains("pass `light_point` binds copy 7 of resource") && err.contains(&format!("`{resource}`, which has 1")),
        "{err}"
    );

    let lamp = lightbench::scene::load::load_sized("cornell_lamp", Some((32, 32)), &[]).unwrap();
    let mut exe = compile(&lamp, &[("area_lights".into(), "ltc".into())]);
    let ltc = exe.plan.resources.iter_mut().find(|r| r.name == "ltc").unwrap();
    assert!(ltc.contents.is_some());
    ltc.contents = None;
    let err = refusal(&exe, &lamp);
    assert!(
        err.contains("resource `ltc` is filled from data, but the Plan carries no `contents`"),
        "{err}"
    );
}

/// Every option of both bundled pipelines (each variant in turn, the others at their
/// defaults), planned for a scene calling for every pass (`every_light.ron`: point, spot and
/// sun shadows, emissive blended panes, every effect): the Plan, through its JSON, is rendered
/// by the small executor as the executor renders its first frame (RMSE 0), or the small
/// executor refuses it naming what it does not carry out — it never renders one differently.
/// With the two pairs of options that call for passes no single option does (`PAIRS`), every
/// pass of both pipelines runs in one of them; the configurations rendered are counted (all
/// 83 today, the ray-traced ones among them), so coverage cannot shrink unnoticed.
const MIN_RENDERED: usize = 81 + PAIRS.len();

/// The ray-traced shadows of forward and light-volume lighting (`deferred` only: `deferred_gi`
/// has no `lighting` variant).
const PAIRS: [[(&str, &str); 2]; 2] = [
    [("lighting", "forward_multi"), ("shadows", "rt")],
    [("lighting", "deferred_volumes"), ("shadows", "rt")],
];

#[test]
fn every_bundled_option_renders_from_the_plan_alone_or_is_refused_by_name() {
    let gpu = gpu();
    let spec = root().join("runtime/tests/executor/every_light.ron");
    let scene = lightbench::scene::load::load_sized(spec.to_str().unwrap(), None, &[]).unwrap();
    let (mut rendered, mut refused) = (vec![], std::collections::BTreeMap::<String, Vec<String>>::new());
    let mut never_run = std::collections::BTreeSet::new();
    for pipeline in ["pipelines/deferred.ron", "pipelines/deferred_gi.ron"] {
        let path = root().join(pipeline);
        let checked = lightbench_compiler::Workspace::disk()
            .session()
            .load_checked(&path, None, &gpu.profile)
            .expect("the bundled pipeline checks");
        let mut unseen: std::collections::BTreeSet<String> = checked.pipeline.passes.iter().map(|p| p.name.value.clone()).collect();
        let options = checked
            .pipeline
            .variants
            .iter()
            .flat_map(|v| v.options.iter().map(move |o| vec![(v.name.value.clone(), o.name.value.clone())]));
        // Passes only two options together call for (`when all(…)`), where the pipeline has both.
        let has = |v: &str| checked.pipeline.variants.iter().any(|x| x.name.value == v);
        let pairs = PAIRS
            .iter()
            .filter(|pair| pair.iter().all(|(v, _)| has(v)))
            .map(|pair| pair.iter().map(|(v, o)| (v.to_string(), o.to_string())).collect());
        for chosen in options.chain(pairs).collect::<Vec<Vec<_>>>() {
            let config = format!(
                "{pipeline} {}",
                chosen.iter().map(|(v, o)| format!("{v}={o}")).collect::<Vec<_>>().join(" ")
            );
            match renders_alone(&gpu, (&path, &scene), &chosen) {
                Ok(plan) => {
                    plan.passes.iter().for_each(|p| {
                        unseen.remove(&p.name);
                    });
                    rendered.push(config);
                }
                Err(e) => refused.entry(e).or_default().push(config),
            }
        }
        never_run.extend(unseen.into_iter().map(|p| format!("{pipeline}: {p}")));
    }
    eprintln!("rendered from the Plan alone: {}", rendered.join(", "));
    for (why, configs) in &refused {
        eprintln!("{why}: {}", configs.join(", "));
    }
    assert!(
        rendered.len() >= MIN_RENDERED,
        "{} configurations rendered, fewer than {MIN_RENDERED}",
        rendered.len()
    );
    assert!(never_run.is_empty(), "passes no rendered configuration ran: {never_run:?}");
}

/// One configuration's Plan through its JSON, rendered by the small executor and compared with the
/// executor's first frame; `Err` where the small executor refuses it by name.
fn renders_alone(gpu: &Gpu, (path, scene): (&std::path::Path, &Scene), chosen: &[(String, String)]) -> Result<Plan, String> {
    let config = format!("{} {chosen:?}", path.display());
    let (exe, _) = lightbench::render::compile(gpu, path, None, scene, chosen).unwrap_or_else(|e| panic!("{config}: {e}"));
    // Only what `plan --json` prints reaches the small executor.
    let plan: Plan = serde_json::from_str(&serde_json::to_string(&exe.plan).unwrap()).unwrap();
    let small = match Small::new(gpu, &plan, scene).and_then(|s| s.frame().map(|_| s)) {
        Ok(s) => s,
        Err(e) if e.starts_with("the small executor does not support") => return Err(e),
        Err(e) => panic!("{config}: {e}"),
    };
    let real = lightbench::render::render(gpu, &exe, scene, 1).unwrap_or_else(|e| panic!("{config}: {e}"));
    let output = plan.output_resource().name.clone();
    let e = rmse(&small.read(&output), &crate::gpu_common::output(gpu, &real));
    assert!(
        e == 0.0,
        "{config}: the small executor's output is {e} RMSE from the executor's; first texture apart: {:?}",
        first_apart(gpu, &small, &real)
    );
    Ok(plan)
}

/// The first texture, in the Plan's order, whose first copy's first layer differs between the
/// two executors (RMSE over 0): where to look when their outputs differ.
fn first_apart(gpu: &Gpu, small: &Small, real: &lightbench::gpu::Executor) -> Option<(String, f64)> {
    small.plan.resources.iter().find_map(|r| {
        let ResourceShape::Texture { format, .. } = r.shape else {
            return None;
        };
        if format.is_depth() {
            return None;
        }
        let theirs = real.read_texture(gpu, &r.name, 0, 0).ok()?;
        let e = rmse(&small.read(&r.name), &theirs);
        (e > 0.0).then(|| (r.name.clone(), e))
    })
}
