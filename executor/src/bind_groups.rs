//! Bind groups and attachment views of each repetition of a pass (per light, per face and
//! per frame parity for history resources), and per-mesh groups for per-draw slots. Every
//! slot is filled from what the Plan says it binds.

use super::pool::Pool;
use super::scene_gpu::SceneGpu;
use super::{convert, Gpu};
use crate::error::{Error, Result};
use lightbench_compiler::abi::InstanceBlock;
use lightbench_compiler::ir::{LayerSel, MipSel};
use lightbench_compiler::layout::{BindSource, BindingType, DrawSlot};
use lightbench_compiler::plan::{Plan, PlanBindGroup, PlanPass, PlanRep, ResourceId};
use lightbench_scene::Light;

/// Instance slots are 256 bytes apart (the uniform offset alignment).
pub const SLOT: u64 = 256;

/// One repetition of a pass: what it binds and renders into, per frame parity.
pub struct Rep {
    /// The light this repetition is for (per-light passes).
    pub light: Option<u32>,
    /// Workgroups of a per-mip compute repetition sized from a texture (at its level).
    pub dispatch: Option<[u32; 3]>,
    pub groups: [Vec<(u32, wgpu::BindGroup)>; 2],
    pub color: [Vec<wgpu::TextureView>; 2],
    pub depth: [Option<wgpu::TextureView>; 2],
    /// The vertices of its light's volume (`draw: LightVolume` passes).
    pub volume: std::ops::Range<u32>,
    /// What its attachments render into (resource, instance, first layer, layers, level):
    /// repetitions with the same can share one render pass.
    pub targets: Vec<TargetKey>,
}

/// One attachment's subresource: resource, instance, first layer, layer count, mip level.
pub type TargetKey = (ResourceId, u32, u32, u32, u32);

/// The part of a texture a read binds: one mip level and/or one layer (else all).
#[derive(Clone, Copy, Default)]
struct Sub {
    level: Option<u32>,
    layer: Option<u32>,
}

/// What bind groups are made from.
pub struct Binder<'a> {
    pub gpu: &'a Gpu,
    pub plan: &'a Plan,
    pub pool: &'a Pool,
    pub samplers: &'a [wgpu::Sampler],
    pub frame: &'a wgpu::Buffer,
    pub lights_buf: &'a wgpu::Buffer,
    /// The scene's triangles (standard binding `triangles`), where the Plan binds them.
    pub triangles: Option<&'a wgpu::TextureView>,
    /// The scene's emissive triangles (standard binding `area_lights`).
    pub area_lights: &'a wgpu::Buffer,
    /// The light-volume meshes (standard binding `light_volumes`) and their ranges.
    pub volumes: (&'a wgpu::Buffer, &'a super::light_volumes::LightVolumes),
    pub instance: &'a wgpu::Buffer,
    pub lights: &'a [Light],
    /// The scene's acceleration structure, when the Plan traces rays.
    pub accel: Option<&'a super::accel::Accel>,
    /// What ray hits are shaded with, when the Plan binds it.
    pub hits: Option<&'a super::accel::HitData>,
    /// What maps are looked up at hits with, when the Plan binds it.
    pub maps: Option<&'a super::accel::HitMaps>,
}

enum Held<'a> {
    Buf(wgpu::BufferBinding<'a>),
    View(wgpu::TextureView),
    Sampler(&'a wgpu::Sampler),
    Tlas(&'a wgpu::Tlas),
}

impl Binder<'_> {
    fn accel(&self) -> Result<&super::accel::Accel> {
        self.accel
            .ok_or_else(|| Error::Plan("the scene's acceleration structure was not built for this Plan".into()))
    }

    fn hits(&self) -> Result<&super::accel::HitData> {
        self.hits
            .ok_or_else(|| Error::Plan("the scene's ray-hit data was not built for this Plan".into()))
    }

    fn maps(&self) -> Result<&super::accel::HitMaps> {
        self.maps
            .ok_or_else(|| Error::Plan("the maps looked up at ray hits were not built for this Plan".into()))
    }

    fn triangles(&self) -> Result<&wgpu::TextureView> {
        self.triangles
            .ok_or_else(|| Error::Plan("the scene's triangles were not built for this Plan".into()))
    }

    fn entry(&self, res: ResourceId) -> Result<&super::pool::Entry> {
        self.pool
            .get(res)
            .ok_or_else(|| Error::Plan(format!("resource #{} is not in the pool", res.0)))
    }

    /// The size a pass renders at: its first colour (else depth) attachment at the mip level
    /// it renders, or the texture its dispatch is sized from (at the repetition's level), else
    /// the Plan's resolution.
    fn target_size(&self, pp: &PlanPass, rep_mip: Option<u32>) -> (u32, u32) {
        let t = pp.work.targets();
        let first = t.and_then(|t| {
            let c = t.color.first().map(|c| (c.resource, c.mip));
            c.or(t.depth.as_ref().map(|d| (d.resource, d.mip)))
        });
        let sized = match &pp.work {
            lightbench_compiler::plan::Work::Compute { sized_from, .. } => sized_from.map(|r| (r, MipSel::Rep(0))),
            _ => None,
        };
        let Some((r, sel)) = first.or(sized) else {
            return self.plan.resolution;
        };
        let level = sel.level(rep_mip.unwrap_or(0)).unwrap_or(0);
        match &self.plan.res(r).shape {
            lightbench_compiler::plan::ResourceShape::Texture { extent, .. } => ((extent.0 >> level).max(1), (extent.1 >> level).max(1)),
            _ => self.plan.resolution,
        }
    }

    /// Every repetition of a pass (lights of its kinds × faces), writing each one's instance
    /// block at its slot; `slot` advances past the pass's slots.
    pub fn reps(&self, pp: &PlanPass, layouts: &[wgpu::BindGroupLayout], params: &[wgpu::Buffer], slot: &mut u64) -> Result<Vec<Rep>> {
        let parities = if self.pool.has_history() { 2 } else { 1 };
        let mut reps = vec![];
        // The Plan's runs, made for this scene's lights (their order in the light array).
        let fits = |l: u32| {
            self.lights
                .get(l as usize)
                .is_some_and(|x| pp.per_light.contains(&x.kind) && (x.shadows || !pp.shadow_casters))
        };
        if let Some(l) = pp.reps.iter().filter_map(|r| r.light).find(|&l| !fits(l)) {
            return Err(Error::Plan(format!(
                "pass `{}` runs for light {l}, which is not one of its kinds among the scene's {} lights on: the Plan was made for another scene",
                pp.name,
                self.lights.len()
            )));
        }
        self.check_copies(pp)?;
        for r in &pp.reps {
            let (light, mip) = (r.light, r.mip);
            let (w, h) = self.target_size(pp, mip);
            let inst = InstanceBlock {
                light: light.unwrap_or(0),
                face: r.face,
                view_count: pp.work.multiview().unwrap_or(1),
                mip: mip.unwrap_or(0),
                target_size: [w as f32, h as f32, 1.0 / w.max(1) as f32, 1.0 / h.max(1) as f32],
                repetition: r.run,
                _pad: [0; 3],
            };
            self.gpu.queue.write_buffer(self.instance, *slot * SLOT, bytemuck::bytes_of(&inst));
            let mut rep = Rep {
                light,
                dispatch: mip.and_then(|_| per_mip_groups(pp, (w, h))),
                groups: [vec![], vec![]],
                color: [vec![], vec![]],
                depth: [None, None],
                volume: light.map(|l| self.volumes.1.range_for(&self.lights[l as usize])).unwrap_or(0..0),
                targets: vec![],
            };
            for parity in 0..parities {
                self.fill(&mut rep, pp, layouts, params, (r, *slot, parity))?;
            }
            if parities == 1 {
                rep.groups[1] = rep.groups[0].clone();
                rep.color[1] = rep.color[0].clone();
                rep.depth[1] = rep.depth[0].clone();
            }
            reps.push(rep);
            *slot += 1;
        }
        Ok(reps)
    }

    /// Every copy a run names is one its resource has (a Plan is read from JSON too).
    fn check_copies(&self, pp: &PlanPass) -> Result<()> {
        for c in pp.reps.iter().flat_map(|r| &r.copies) {
            let r = self.plan.resources.get(c.resource.0 as usize);
            if r.is_some_and(|r| c.instance < r.instances) {
                continue;
            }
            return Err(Error::Plan(format!(
                "pass `{}` binds copy {} of resource #{}{}: the Plan is inconsistent",
                pp.name,
                c.instance,
                c.resource.0,
                r.map_or(", which does not exist".into(), |r| format!(
                    " `{}`, which has {}",
                    r.name, r.instances
                ))
            )));
        }
        Ok(())
    }

    fn fill(
        &self,
        rep: &mut Rep,
        pp: &PlanPass,
        layouts: &[wgpu::BindGroupLayout],
        params: &[wgpu::Buffer],
        (r, slot, parity): (&PlanRep, u64, u32),
    ) -> Result<()> {
        let p = parity as usize;
        for g in pp.bind_groups.iter().filter(|g| !g.is_per_draw()) {
            let layout = layouts
                .get(g.group as usize)
                .ok_or_else(|| Error::Plan(format!("no layout for group {}", g.group)))?;
            rep.groups[p].push((g.group, self.group(pp, g, layout, params, r, slot, parity)?));
        }
        let level = |sel: MipSel| sel.level(r.mip.unwrap_or(0)).unwrap_or(0);
        if let Some(t) = pp.work.targets() {
            for c in &t.color {
                let (view, key) = self.attachment(c.resource, (c.layer, level(c.mip)), r, parity)?;
                rep.color[p].push(view);
                if p == 0 {
                    rep.targets.push(key);
                }
            }
            if let Some(d) = &t.depth {
                let (view, key) = self.attachment(d.resource, (d.layer, level(d.mip)), r, parity)?;
                rep.depth[p] = Some(view);
                if p == 0 {
                    rep.targets.push(key);
                }
            }
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn group(
        &self,
        pp: &PlanPass,
        g: &PlanBindGroup,
        layout: &wgpu::BindGroupLayout,
        params: &[wgpu::Buffer],
        rep: &PlanRep,
        slot: u64,
        parity: u32,
    ) -> Result<wgpu::BindGroup> {
        let mut held = vec![];
        for e in &g.entries {
            let r = match &e.source {
                BindSource::Frame => Held::Buf(self.frame.as_entire_buffer_binding()),
                BindSource::Lights => Held::Buf(self.lights_buf.as_entire_buffer_binding()),
                BindSource::Triangles => Held::View(self.triangles()?.clone()),
                BindSource::LightVolumes => Held::Buf(self.volumes.0.as_entire_buffer_binding()),
                BindSource::AreaLights => Held::Buf(self.area_lights.as_entire_buffer_binding()),
                BindSource::HitTriangles => Held::View(self.hits()?.triangles.clone()),
                BindSource::HitMaterials => Held::Buf(self.hits()?.materials.as_entire_buffer_binding()),
                BindSource::HitEmitters => Held::View(self.hits()?.emitters.clone()),
                BindSource::HitCorners => Held::View(self.maps()?.corners.clone()),
                BindSource::HitMaps => Held::View(self.maps()?.maps.clone()),
                BindSource::Instance => Held::Buf(wgpu::BufferBinding {
                    buffer: self.instance,
                    offset: slot * SLOT,
                    size: std::num::NonZeroU64::new(std::mem::size_of::<InstanceBlock>() as u64),
                }),
                BindSource::Params => {
                    let i = pp.uniform_blocks.iter().position(|b| b.global == e.name);
                    let buf = i
                        .and_then(|i| params.get(i))
                        .ok_or_else(|| Error::Plan(format!("no parameter block `{}`", e.name)))?;
                    Held::Buf(buf.as_entire_buffer_binding())
                }
                BindSource::Sampler(s) => Held::Sampler(
                    self.samplers
                        .get(s.0 as usize)
                        .ok_or_else(|| Error::Plan(format!("sampler #{} missing", s.0)))?,
                ),
                BindSource::Resource(id) | BindSource::Prev(id) => {
                    let prev = matches!(e.source, BindSource::Prev(_));
                    // A `Mip(..)` read binds one level: the one it selects at this repetition.
                    // A `Layer(..)` read binds one layer: a fixed one, or this repetition's.
                    let read = pp.reads.iter().find(|r| r.resource == *id && !r.prev);
                    let level = read.and_then(|r| r.mip).map(|sel| sel.level(rep.mip.unwrap_or(0)).unwrap_or(0));
                    let layers = self.entry(*id)?.key.layers();
                    let sub = Sub {
                        level,
                        layer: read.and_then(|r| r.layer).and_then(|l| l.at(rep.run, layers)),
                    };
                    self.resource(*id, &e.ty, (rep.copy_of(*id), sub), prev, parity)?
                }
                BindSource::Draw(_) => return Err(Error::Plan("per-draw binding outside the per-draw group".into())),
            };
            held.push((e.binding, r));
        }
        let entries: Vec<wgpu::BindGroupEntry> = held
            .iter()
            .map(|(b, r)| wgpu::BindGroupEntry {
                binding: *b,
                resource: match r {
                    Held::Buf(bb) => wgpu::BindingResource::Buffer(bb.clone()),
                    Held::View(v) => wgpu::BindingResource::TextureView(v),
                    Held::Sampler(s) => wgpu::BindingResource::Sampler(s),
                    Held::Tlas(t) => wgpu::BindingResource::AccelerationStructure(t),
                },
            })
            .collect();
        Ok(self.gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&pp.name),
            layout,
            entries: &entries,
        }))
    }

    /// Copy `inst` of resource `id` as binding type `ty` binds it (the part `sub` of a texture).
    fn resource(&self, id: ResourceId, ty: &BindingType, (inst, sub): (u32, Sub), prev: bool, parity: u32) -> Result<Held<'_>> {
        let entry = self.entry(id)?;
        let name = &self.plan.res(id).name;
        Ok(match ty {
            BindingType::AccelerationStructure => Held::Tlas(&self.accel()?.tlas),
            BindingType::Texture { view_dimension, .. } | BindingType::StorageTexture { view_dimension, .. } => {
                let tex = entry
                    .texture(inst, prev, parity)
                    .ok_or_else(|| Error::Plan(format!("`{name}` is not a texture")))?;
                Held::View(tex.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(convert::view_dim(*view_dimension)),
                    aspect: aspect(tex),
                    base_mip_level: sub.level.unwrap_or(0),
                    mip_level_count: sub.level.map(|_| 1),
                    base_array_layer: sub.layer.unwrap_or(0),
                    array_layer_count: sub.layer.map(|_| 1),
                    ..Default::default()
                }))
            }
            _ => Held::Buf(
                entry
                    .buffer(inst, prev, parity)
                    .ok_or_else(|| Error::Plan(format!("`{name}` is not a buffer")))?
                    .as_entire_buffer_binding(),
            ),
        })
    }

    /// The view a pass renders into: one layer (base, fixed or the current face), or all
    /// layers as a 2D array for multiview.
    fn attachment(
        &self,
        res: ResourceId,
        (layer, level): (LayerSel, u32),
        rep: &PlanRep,
        parity: u32,
    ) -> Result<(wgpu::TextureView, TargetKey)> {
        let e = self.entry(res)?;
        let (dim, range) = match layer {
            LayerSel::All => (wgpu::TextureViewDimension::D2Array, (0, e.key.layers())),
            LayerSel::Face => (wgpu::TextureViewDimension::D2, (rep.face, 1)),
            fixed => (wgpu::TextureViewDimension::D2, (fixed.at(rep.run, e.key.layers()).unwrap_or(0), 1)),
        };
        let name = &self.plan.res(res).name;
        let instance = rep.copy_of(res);
        let tex = e
            .texture(instance, false, parity)
            .ok_or_else(|| Error::Plan(format!("`{name}` is not a texture")))?;
        let key = (res, instance, range.0, range.1, level);
        let view = tex.create_view(&wgpu::TextureViewDescriptor {
            label: Some(name),
            dimension: Some(dim),
            usage: Some(wgpu::TextureUsages::RENDER_ATTACHMENT),
            // An attachment is all of the texture's aspects (a depth-stencil format's stencil
            // too); bindings read the depth alone.
            aspect: wgpu::TextureAspect::All,
            base_mip_level: level,
            mip_level_count: Some(1),
            base_array_layer: range.0,
            array_layer_count: Some(range.1),
            ..Default::default()
        });
        Ok((view, key))
    }

    /// One bind group per mesh for the pass's per-draw group, if it has one.
    pub fn draw_groups(
        &self,
        pp: &PlanPass,
        layouts: &[wgpu::BindGroupLayout],
        scene: &SceneGpu,
    ) -> Result<Option<(u32, Vec<wgpu::BindGroup>)>> {
        let Some(g) = pp.bind_groups.iter().find(|g| g.is_per_draw()) else {
            return Ok(None);
        };
        let layout = layouts
            .get(g.group as usize)
            .ok_or_else(|| Error::Plan(format!("no layout for group {}", g.group)))?;
        let mut list = vec![];
        for mesh in &scene.meshes {
            let mat = &scene.materials[mesh.material];
            let entries = g
                .entries
                .iter()
                .map(|e| {
                    let BindSource::Draw(slot) = &e.source else {
                        return Err(Error::Plan(format!("group {} mixes per-draw bindings with others", g.group)));
                    };
                    let resource = match slot {
                        DrawSlot::Mesh => mesh.block.as_entire_binding(),
                        DrawSlot::Material => mat.block.as_entire_binding(),
                        DrawSlot::BaseColorMap => wgpu::BindingResource::TextureView(&mat.textures[0]),
                        DrawSlot::NormalMap => wgpu::BindingResource::TextureView(&mat.textures[1]),
                        DrawSlot::MetallicRoughnessMap => wgpu::BindingResource::TextureView(&mat.textures[2]),
                        DrawSlot::EmissiveMap => wgpu::BindingResource::TextureView(&mat.textures[3]),
                        DrawSlot::OcclusionMap => wgpu::BindingResource::TextureView(&mat.textures[4]),
                        DrawSlot::MaterialSampler => wgpu::BindingResource::Sampler(&scene.samplers[mat.sampler]),
                    };
                    Ok(wgpu::BindGroupEntry {
                        binding: e.binding,
                        resource,
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            list.push(self.gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(&pp.name),
                layout,
                entries: &entries,
            }));
        }
        Ok(Some((g.group, list)))
    }
}

/// Workgroups covering `extent` for a per-mip compute pass sized from a texture.
fn per_mip_groups(pp: &PlanPass, (w, h): (u32, u32)) -> Option<[u32; 3]> {
    match &pp.work {
        lightbench_compiler::plan::Work::Compute {
            workgroup_size,
            sized_from: Some(_),
            ..
        } => Some([w.div_ceil(workgroup_size[0].max(1)), h.div_ceil(workgroup_size[1].max(1)), 1]),
        _ => None,
    }
}

fn aspect(tex: &wgpu::Texture) -> wgpu::TextureAspect {
    if tex.format().is_depth_stencil_format() {
        wgpu::TextureAspect::DepthOnly
    } else {
        wgpu::TextureAspect::All
    }
}
