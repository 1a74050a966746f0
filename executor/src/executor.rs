//! The generic executor: runs any Plan. Everything it creates (textures, layouts, pipelines,
//! bind groups) and every decision it makes (repetitions, attachments, dispatch sizes) comes
//! from the Plan; there is no code here for any particular pass or effect.
//!
//! Stages of building a Plan's GPU state: `pool` (resources, shared with the previous Plan
//! where unchanged), samplers and parameter blocks, `pipelines` (cached across Plans),
//! `bind_groups` (per repetition). A frame, in steps: `begin` (inputs checked and written,
//! repetitions decided), `frame` (every pass recorded into an encoder — the executor's own
//! in `render_frame`, the host's in `embed` — and submitted), `timings` (per-pass CPU and GPU
//! time); `read` reads any resource back.

mod begin;
mod embed;
mod frame;
mod read;
mod relight;
mod timings;

use super::accel::{Accel, BlasKey, HitData, HitMaps};
use super::bind_groups::{Binder, SLOT};
use super::encode::PassGpu;
use super::pipelines::{Built, PipelineCache, PipelineKey};
use super::pool::Pool;
use super::reuse::{Graph, Reuse};
use super::scene_gpu::SceneGpu;
use super::timing::{PassTiming, Timer};
use super::{convert, err_scope, Gpu};
use crate::error::{Error, Result};
use lightbench_compiler::abi::{FrameBlock, LightBlock};
use lightbench_compiler::ir::ParamValue;
use lightbench_compiler::plan::{ParamValues, Plan, PlanSampler};
use lightbench_compiler::Executable;
use lightbench_scene::{Camera, Light, Scene};
use std::sync::Arc;

/// One part of a resource: a light instance, array layer, mip level and history copy.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Part {
    pub instance: u32,
    pub layer: u32,
    pub mip: u32,
    /// The history copy that holds the previous frame (after a frame: the one it read).
    pub previous: bool,
}

/// What changes from frame to frame, passed to every `render_frame` (or `encode`).
/// [`Executor::inputs`] gives the last frame's, to change what differs.
#[derive(Clone, Debug)]
pub struct FrameInputs {
    /// Seconds since the start (lights animate with it).
    pub time: f32,
    /// The camera, unless `matrices` replaces it.
    pub camera: Camera,
    /// Parameter overrides; the rest keep their defaults.
    pub params: ParamValues,
    /// A host renderer's own view and projection, in place of `camera`.
    pub matrices: Option<CameraMatrices>,
    /// This frame's lights in place of the scene's (animated) ones: as many, of the same kinds
    /// and shadow casting, in the same order, since the Plan repeats passes per light; where
    /// they are and how bright is free. The scene's emitter lights (`Area`, one per emissive
    /// mesh) follow them in the light array as they are.
    pub lights: Option<Vec<Light>>,
}

/// A camera as a host renderer keeps it: world → view and view → clip matrices, in wgpu's
/// conventions (right-handed view looking down -Z, clip depth 0..1). The executor adds its
/// sub-pixel jitter to `proj` where the Plan asks for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraMatrices {
    pub view: glam::Mat4,
    pub proj: glam::Mat4,
}

impl FrameInputs {
    /// Where the camera is in the world (from `matrices` when given).
    pub fn eye(&self) -> glam::Vec3 {
        match &self.matrices {
            Some(m) => m.view.inverse().transform_point3(glam::Vec3::ZERO),
            None => self.camera.position,
        }
    }

    /// View and projection for an output of aspect ratio `aspect`, before jitter.
    fn view_proj(&self, aspect: f32) -> (glam::Mat4, glam::Mat4) {
        match &self.matrices {
            Some(m) => (m.view, m.proj),
            None => (self.camera.view(), self.camera.proj(aspect)),
        }
    }
}

/// What `replace` did: pipelines and resources built anew or kept, overrides dropped.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ReloadReport {
    /// Passes whose pipeline was built (a shader, layout or state changed).
    pub pipelines_built: Vec<String>,
    /// Passes whose pipeline was taken from the cache.
    pub pipelines_reused: Vec<String>,
    pub resources_created: Vec<String>,
    pub resources_reused: Vec<String>,
    /// Parameter overrides that no longer apply to the new Plan, with why.
    pub params_dropped: Vec<(String, String)>,
    /// A new scene (`replace_scene`): what of the old one's stayed resident, unchanged.
    pub scene_kept: Option<crate::scene_gpu::Kept>,
}

/// What one Plan needs on the GPU: built on the side, swapped in whole. (Samplers and the
/// instance-block buffer live as long as the bind groups that hold them.)
struct State {
    plan: Plan,
    /// The Plan's reuse graph (who feeds whom), worked out once.
    graph: Graph,
    pool: Pool,
    /// Per pass, one buffer per parameter block with the bytes last written to it.
    params: Vec<Vec<(wgpu::Buffer, Vec<u8>)>>,
    passes: Vec<PassGpu>,
    timer: Option<Timer>,
}

/// What stays when Plans are replaced: the scene on the GPU and the standard blocks.
struct Shared {
    frame_buf: wgpu::Buffer,
    lights_buf: wgpu::Buffer,
    scene_gpu: SceneGpu,
    /// The scene's acceleration structure, built the first time a Plan traces rays.
    accel: std::sync::OnceLock<Accel>,
    /// The bottom levels of the scene's before this one (`replace_scene`), which the first
    /// build takes over where they are unchanged.
    previous_blas: std::sync::Mutex<Vec<(BlasKey, wgpu::Blas)>>,
    /// What ray hits are shaded with, built the first time a Plan binds it.
    hits: std::sync::OnceLock<HitData>,
    /// What maps are looked up at hits with, built the first time a Plan binds it.
    hit_maps: std::sync::OnceLock<HitMaps>,
    /// The standard `triangles` binding, built the first time a Plan binds it.
    triangles: std::sync::OnceLock<wgpu::TextureView>,
    scene: Scene,
    lights: Vec<Light>,
    bounds: (glam::Vec3, glam::Vec3),
    /// How many times a scene was uploaded to this executor (`scene_uploads`).
    uploads: u32,
}

/// A compiled Plan running on a device for one scene: its resources, pipelines and bind
/// groups, rendering frames (`render_frame`, or `encode` into a host's encoder), taking a new
/// Plan or scene at a frame boundary (`replace`, `replace_scene`) and reading back any
/// resource.
pub struct Executor {
    state: State,
    shared: Shared,
    cache: PipelineCache,
    /// The inputs of the last frame (or the scene's camera and no overrides before the first).
    inputs: FrameInputs,
    pub frame_index: u64,
    pub last_timings: Vec<PassTiming>,
    /// Every frame's timings, when `log_timings` is set (a long-running viewer leaves it off).
    pub timing_log: Vec<Vec<PassTiming>>,
    pub log_timings: bool,
    /// GPU timestamps per pass (`PassTiming::gpu_ms`); on by default where the adapter has them.
    timing: bool,
    /// Repetitions that render into the same loaded attachments share a render pass (the
    /// default); off, each has its own (the baseline `bench lighting -- merge` measures).
    merge: bool,
    /// External resources whose contents were supplied (`load_input`) to their current storage.
    pub(super) supplied: std::collections::BTreeSet<String>,
    /// The last frame's view-projection and jitter (the frame block's `prev_*`).
    previous: Option<(glam::Mat4, [f32; 2])>,
    /// Which passes ran with what (reuse of unchanged work).
    pub(super) reuse: Reuse,
    /// Whether reuse was asked for (`set_reuse`); aliasing turns it off while on.
    reuse_on: bool,
    /// Frames submitted and maybe still running on the GPU, oldest first.
    in_flight: std::collections::VecDeque<wgpu::SubmissionIndex>,
    /// How many frames may be in flight (`set_frames_in_flight`).
    frames_in_flight: usize,
    /// Transient resources share memory where the Plan allows (`set_aliasing`).
    alias: bool,
    /// The frame `encode` recorded into a host's encoder, until it is known to be submitted.
    recorded: Option<frame::Recorded>,
    /// Frames whose timings were taken: `last_timings` (and the log's last entry) is frame
    /// `logged - 1`.
    logged: u64,
    /// GPU timestamps read late (`set_late_timestamps`): the frames whose read is on its way
    /// with which passes ran in them, and the latest figure per pass.
    late_timestamps: bool,
    late_runs: std::collections::VecDeque<(u64, Vec<bool>)>,
    late_ms: Vec<Option<f64>>,
    /// Where parameter blocks are packed each frame before being compared with the last.
    pack_scratch: Vec<u8>,
}

fn sampler(device: &wgpu::Device, s: &PlanSampler) -> wgpu::Sampler {
    device.create_sampler(&convert::sampler(s))
}

/// The standard `lights` binding, room for `n` lights (at least one).
fn lights_buffer(device: &wgpu::Device, n: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("lights"),
        size: (std::mem::size_of::<LightBlock>() * n.max(1)) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn uniform_buffer(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl Shared {
    /// The scene is taken: its textures go to the GPU and are dropped on the CPU. What
    /// `previous` (the scene on the GPU before it) holds unchanged stays resident.
    fn new(gpu: &Gpu, mut scene: Scene, previous: Option<&Shared>) -> Result<Shared> {
        let device = &gpu.device;
        let lights = scene.light_array();
        let upload = || SceneGpu::reusing(device, &gpu.queue, &mut scene, previous.map(|p| &p.scene_gpu));
        Ok(Shared {
            frame_buf: uniform_buffer(device, "frame", std::mem::size_of::<FrameBlock>() as u64),
            lights_buf: lights_buffer(device, lights.len()),
            scene_gpu: err_scope(gpu, "uploading the scene", upload)??,
            bounds: scene.bounds(),
            accel: Default::default(),
            previous_blas: std::sync::Mutex::new(previous.map(Shared::blas).unwrap_or_default()),
            hits: Default::default(),
            hit_maps: Default::default(),
            triangles: Default::default(),
            lights,
            scene,
            uploads: 1,
        })
    }

    /// The scene's punctual lights that are on: the light array's first part (shaders loop
    /// over `frame.light_count` of them; emitter lights follow).
    fn punctual(&self) -> &[Light] {
        let n = self.lights.iter().take_while(|l| l.kind.punctual()).count();
        &self.lights[..n]
    }

    /// The scene's acceleration structure, built on first use (ray-query devices only).
    fn accel(&self, gpu: &Gpu) -> Result<&Accel> {
        if let Some(a) = self.accel.get() {
            return Ok(a);
        }
        let previous = self.previous_blas.lock().map(|mut p| std::mem::take(&mut *p)).unwrap_or_default();
        let built = Accel::build(&gpu.device, &gpu.queue, &self.scene_gpu.meshes, &self.scene, &previous)?;
        Ok(self.accel.get_or_init(|| built))
    }

    /// The bottom levels a next scene may take over: this scene's, or those it was handed
    /// and has not built with yet.
    fn blas(&self) -> Vec<(BlasKey, wgpu::Blas)> {
        match self.accel.get() {
            Some(a) => a.blas.clone(),
            None => self.previous_blas.lock().map(|p| p.clone()).unwrap_or_default(),
        }
    }

    /// What ray hits are shaded with, built on first use.
    fn hits(&self, gpu: &Gpu) -> Result<&HitData> {
        if let Some(h) = self.hits.get() {
            return Ok(h);
        }
        let built = HitData::build((&gpu.device, &gpu.queue), &self.scene_gpu, &self.scene)?;
        Ok(self.hits.get_or_init(|| built))
    }

    /// What maps are looked up at hits with, built on first use.
    fn hit_maps(&self, gpu: &Gpu) -> Result<&HitMaps> {
        if let Some(m) = self.hit_maps.get() {
            return Ok(m);
        }
        let built = HitMaps::build((&gpu.device, &gpu.queue), &self.scene_gpu, &self.scene)?;
        Ok(self.hit_maps.get_or_init(|| built))
    }

    /// The scene's drawn triangles in world space, built on first use.
    fn triangles(&self, gpu: &Gpu) -> Result<&wgpu::TextureView> {
        if let Some(t) = self.triangles.get() {
            return Ok(t);
        }
        let built = super::scene_gpu::triangles((&gpu.device, &gpu.queue), &self.scene)?;
        Ok(self.triangles.get_or_init(|| built))
    }
}

impl Executor {
    /// An executor for a copy of `scene` (see `with_scene` to hand the scene over).
    pub fn new(gpu: &Gpu, exe: &Executable, scene: &Scene) -> Result<Executor> {
        Self::with_scene(gpu, exe, scene.clone())
    }

    /// An executor that takes the scene: its decoded textures are dropped once uploaded, so a
    /// large model is not held twice in memory. `scene()` then has no texture data.
    pub fn with_scene(gpu: &Gpu, exe: &Executable, scene: Scene) -> Result<Executor> {
        Self::with_cache(gpu, exe, scene, PipelineCache::default())
    }

    /// `with_scene`, starting from the pipelines another executor built on this device
    /// (`take_cache`): a run over many configurations compiles each pass pipeline once.
    pub fn with_cache(gpu: &Gpu, exe: &Executable, scene: Scene, mut cache: PipelineCache) -> Result<Executor> {
        let camera = scene.camera.clone();
        let shared = Shared::new(gpu, scene, None)?;
        let inputs = FrameInputs {
            time: 0.0,
            camera,
            params: ParamValues::new(),
            matrices: None,
            lights: None,
        };
        let (state, fresh, _) = build_state(gpu, exe, &shared, (&Pool::default(), false), &mut cache, &inputs.params)?;
        cache.insert(fresh, state.passes.len());
        let ex = Executor {
            state,
            shared,
            cache,
            inputs,
            frame_index: 0,
            last_timings: vec![],
            timing_log: vec![],
            log_timings: false,
            timing: true,
            merge: true,
            supplied: Default::default(),
            previous: None,
            reuse: Reuse::new(true),
            reuse_on: true,
            alias: false,
            in_flight: Default::default(),
            frames_in_flight: 2,
            recorded: None,
            logged: 0,
            late_timestamps: false,
            late_runs: Default::default(),
            late_ms: vec![],
            pack_scratch: vec![],
        };
        ex.upload_data(gpu)?;
        Ok(ex)
    }

    /// The compiled pipelines, for the next executor on this device (`with_cache`).
    pub fn take_cache(self) -> PipelineCache {
        self.cache
    }

    /// Replace the running Plan at a frame boundary. The new state is built on the side and
    /// swapped in only on success (on failure the old Plan keeps rendering, untouched);
    /// textures, buffers and pipelines whose descriptors did not change are reused, and
    /// parameter overrides that still apply are kept.
    pub fn replace(&mut self, gpu: &Gpu, exe: &Executable) -> Result<ReloadReport> {
        self.finish_pending(gpu)?;
        let mut params = self.inputs.params.clone();
        let dropped = params.retain_applicable(&exe.plan.params);
        let old = (&self.state.pool, self.alias);
        let (state, fresh, mut report) = build_state(gpu, exe, &self.shared, old, &mut self.cache, &params)?;
        report.params_dropped = dropped;
        self.cache.insert(fresh, state.passes.len());
        self.state = state;
        // Late timestamps on their way belong to the old Plan's passes.
        (self.late_runs, self.late_ms) = Default::default();
        self.inputs.params = params;
        // A recreated external resource lost what was supplied: it must be supplied again.
        self.supplied.retain(|n| !report.resources_created.contains(n));
        self.upload_data(gpu)?;
        self.reuse.reset();
        Ok(report)
    }

    /// Replace the scene, with the Plan compiled for it, at a frame boundary: pipelines and
    /// unchanged resources are kept, the camera becomes the new scene's; on failure the old
    /// scene and Plan keep rendering.
    pub fn replace_scene(&mut self, gpu: &Gpu, exe: &Executable, scene: &Scene) -> Result<ReloadReport> {
        self.finish_pending(gpu)?;
        let mut shared = Shared::new(gpu, scene.clone(), Some(&self.shared))?;
        shared.uploads += self.shared.uploads;
        let mut params = self.inputs.params.clone();
        let dropped = params.retain_applicable(&exe.plan.params);
        let old = (&self.state.pool, self.alias);
        let (state, fresh, mut report) = build_state(gpu, exe, &shared, old, &mut self.cache, &params)?;
        report.params_dropped = dropped;
        let mut kept = shared.scene_gpu.kept;
        kept.blas = shared.accel.get().map(|a| (a.kept, a.blas.len()));
        // A Plan that traces no rays keeps no old bottom levels alive on the GPU (a later
        // one that traces builds them all).
        if shared.accel.get().is_none() {
            shared.previous_blas = Default::default();
        }
        report.scene_kept = Some(kept);
        self.cache.insert(fresh, state.passes.len());
        self.state = state;
        // Late timestamps on their way belong to the old Plan's passes.
        (self.late_runs, self.late_ms) = Default::default();
        self.shared = shared;
        self.supplied.retain(|n| !report.resources_created.contains(n));
        self.inputs.params = params;
        self.inputs.camera = scene.camera.clone();
        // Frame lights were checked against the old scene's.
        self.inputs.lights = None;
        self.upload_data(gpu)?;
        self.reuse.reset();
        Ok(report)
    }

    pub fn plan(&self) -> &Plan {
        &self.state.plan
    }

    /// Pipelines and shader modules kept across Plans (bounded: a hot reload does not grow them).
    pub fn cached(&self) -> (usize, usize) {
        self.cache.len()
    }

    pub fn pool(&self) -> &Pool {
        &self.state.pool
    }

    pub fn scene(&self) -> &Scene {
        &self.shared.scene
    }

    /// How many times a scene's geometry and textures were uploaded to this executor: 1 when
    /// made, one more per `replace_scene` (`replace` and `replace_lights` keep them).
    pub fn scene_uploads(&self) -> u32 {
        self.shared.uploads
    }

    /// Inputs for a frame at `time`: the last camera (or the scene's animated camera at
    /// `time`) and parameter overrides.
    pub fn inputs(&self, time: f32) -> FrameInputs {
        let scene_camera = &self.shared.scene.camera;
        let camera = match scene_camera.animation {
            Some(_) => scene_camera.at(time),
            None => self.inputs.camera.clone(),
        };
        FrameInputs {
            time,
            camera,
            ..self.inputs.clone()
        }
    }

    /// The value the running Plan was made with for a parameter it fixes (a size, a repeat
    /// count, a shader constant); `None` for a parameter that is a frame input (or none).
    pub fn fixed_param(&self, name: &str) -> Option<&ParamValue> {
        self.state
            .plan
            .params
            .iter()
            .find(|p| p.name == name)
            .and_then(|p| p.sizes.as_ref())
    }

    /// Override a parameter for the following frames (checked against the running Plan).
    pub fn set_param(&mut self, name: &str, value: ParamValue) -> Result<()> {
        // A parameter the Plan fixes needs a new Plan.
        if let Some(sized) = self.fixed_param(name) {
            if *sized != value {
                return Err(Error::Request(format!(
                    "parameter `{name}` is fixed by the Plan (it sizes resources, repeats a pass or sets a shader constant; this Plan uses {}): plan again with the new value (Executor::replace with an Executable compiled for it)",
                    sized.describe()
                )));
            }
        }
        self.inputs.params.set(&self.state.plan.params, name, value)?;
        Ok(())
    }

    /// Write parameter blocks whose bytes changed; every override must apply to the Plan.
    fn apply_params(&mut self, gpu: &Gpu, params: &ParamValues) -> Result<()> {
        let plan = &self.state.plan;
        for (name, value) in params.iter() {
            ParamValues::check(&plan.params, name, value)?;
        }
        // Packed into a scratch buffer and swapped with the last bytes when they differ: no
        // allocation per block per frame.
        let scratch = &mut self.pack_scratch;
        for (pp, bufs) in plan.passes.iter().zip(&mut self.state.params) {
            for (block, (buf, last)) in pp.uniform_blocks.iter().zip(bufs.iter_mut()) {
                block.pack_into(&plan.params, params, scratch);
                if scratch != last {
                    gpu.queue.write_buffer(buf, 0, scratch);
                    std::mem::swap(scratch, last);
                }
            }
        }
        Ok(())
    }

    /// Time passes on the GPU with timestamp queries (the default, where the adapter has them)
    /// or not: then `gpu_ms` is `None`, and a frame spends nothing on writing and reading them.
    pub fn set_timing(&mut self, on: bool) {
        self.timing = on;
    }

    /// Let repetitions of a pass that render into the same loaded attachments share one
    /// render pass (`true`, the default), or give each its own. Images are the same. Untimed
    /// (`set_timing(false)`; `render_frame` and `encode` alike), a pass the Plan lets continue the one before
    /// (`PlanPass::continues`: ambient, then the lights) is recorded inside its render pass
    /// too; timed, each pass keeps its own for its timestamps.
    pub fn set_merge(&mut self, on: bool) {
        self.merge = on;
    }

    /// Run every pass every frame (`false`), or only those whose inputs changed (the default;
    /// not while aliasing).
    pub fn set_reuse(&mut self, on: bool) {
        self.reuse_on = on;
        self.reuse = Reuse::new(on && !self.alias);
    }

    /// Let transient resources share memory where the Plan allows (`PlanResource::shares`),
    /// or give each its own (the default). The resources are made again, as
    /// `replace` with `exe` (the executable running) does. While on, every pass runs every
    /// frame (a skipped pass's result could be overwritten by another resource), and a
    /// transient resource read after the frame holds whatever last lived in its memory: read
    /// back only outputs, history and external resources.
    pub fn set_aliasing(&mut self, gpu: &Gpu, exe: &Executable, on: bool) -> Result<ReloadReport> {
        let was = self.alias;
        self.alias = on;
        match self.replace(gpu, exe) {
            Ok(report) => {
                self.reuse = Reuse::new(self.reuse_on && !on);
                Ok(report)
            }
            Err(e) => {
                self.alias = was;
                Err(e)
            }
        }
    }

    /// Memory of the resources as created: each texture or buffer once (with aliasing, what
    /// several resources share counts once).
    pub fn resource_bytes(&self) -> u64 {
        let plan = &self.state.plan;
        plan.resources
            .iter()
            .zip(&self.state.pool.entries)
            .filter(|(_, e)| e.alias_of.is_none())
            .map(|(r, _)| r.bytes)
            .sum()
    }
}

type Fresh = Vec<(PipelineKey, Arc<Built>)>;

/// One uniform buffer per parameter block of each pass, written with the packed values.
fn param_blocks(gpu: &Gpu, plan: &Plan, params: &ParamValues) -> Vec<Vec<(wgpu::Buffer, Vec<u8>)>> {
    plan.passes
        .iter()
        .map(|pp| {
            pp.uniform_blocks
                .iter()
                .map(|b| {
                    let buf = uniform_buffer(&gpu.device, &format!("{}.{}", pp.name, b.global), b.size as u64);
                    let bytes = b.pack(&plan.params, params);
                    gpu.queue.write_buffer(&buf, 0, &bytes);
                    (buf, bytes)
                })
                .collect()
        })
        .collect()
}

/// The pipeline of a pass: from the cache, from this build, or built now (and recorded).
fn pipeline(
    gpu: &Gpu,
    exe: &Executable,
    i: usize,
    cache: &mut PipelineCache,
    fresh: &mut Fresh,
    report: &mut ReloadReport,
) -> Result<Arc<Built>> {
    let pp = &exe.plan.passes[i];
    let modules = &exe.modules[i];
    let key = PipelineKey::of(pp, modules);
    if let Some(b) = cache
        .get(&key)
        .or_else(|| fresh.iter().find(|(k, _)| *k == key).map(|(_, b)| b.clone()))
    {
        report.pipelines_reused.push(pp.name.clone());
        return Ok(b);
    }
    let b = Arc::new(err_scope(gpu, &format!("pass `{}`", pp.name), || {
        cache.build(&gpu.device, pp, modules)
    })??);
    report.pipelines_built.push(pp.name.clone());
    fresh.push((key, b.clone()));
    Ok(b)
}

/// Sub-pixel jitter of frame `n` in pixels: the Halton (2, 3) sequence over 16 frames,
/// centred (each component within ±0.5).
pub fn halton_jitter(n: u64) -> [f32; 2] {
    fn halton(mut i: u64, base: u64) -> f32 {
        let (mut f, mut r) = (1.0f32, 0.0f32);
        while i > 0 {
            f /= base as f32;
            r += f * (i % base) as f32;
            i /= base;
        }
        r
    }
    let i = n % 16 + 1;
    [halton(i, 2) - 0.5, halton(i, 3) - 0.5]
}

/// What of the scene's data built on demand a Plan binds.
struct SceneNeeds {
    /// The acceleration structure.
    accel: bool,
    /// The hit data.
    hits: bool,
    /// The maps looked up at hits.
    maps: bool,
    /// The standard `triangles` binding.
    triangles: bool,
}

fn scene_needs(plan: &Plan) -> SceneNeeds {
    use lightbench_compiler::layout::BindSource;
    let hit_data = |s: &BindSource<_, _>| matches!(s, BindSource::HitTriangles | BindSource::HitMaterials | BindSource::HitEmitters);
    let hit_maps = |s: &BindSource<_, _>| matches!(s, BindSource::HitCorners | BindSource::HitMaps);
    let entries = || plan.passes.iter().flat_map(|p| &p.bind_groups).flat_map(|g| &g.entries);
    SceneNeeds {
        accel: plan.resources.iter().any(|r| r.is_accel()),
        hits: entries().any(|e| hit_data(&e.source)),
        maps: entries().any(|e| hit_maps(&e.source)),
        triangles: entries().any(|e| matches!(e.source, BindSource::Triangles)),
    }
}

/// The GPU state of an executable: resources (sharing `old`'s where unchanged; transient ones
/// sharing memory with `alias`), samplers,
/// parameter blocks, pipelines (from `cache`, or built: returned as `Fresh` to be cached once
/// the whole state is known to be good) and bind groups.
fn build_state(
    gpu: &Gpu,
    exe: &Executable,
    shared: &Shared,
    (old, alias): (&Pool, bool),
    cache: &mut PipelineCache,
    params: &ParamValues,
) -> Result<(State, Fresh, ReloadReport)> {
    let device = &gpu.device;
    let plan = &exe.plan;
    if exe.modules.len() != plan.passes.len() {
        return Err(Error::Plan("the executable has no shader modules for some passes".into()));
    }
    let pool = err_scope(gpu, "creating resources", || Pool::build(device, plan, old, alias))?;
    let samplers: Vec<wgpu::Sampler> = plan.samplers.iter().map(|s| sampler(device, s)).collect();
    let reps_total: u64 = plan.passes.iter().map(|p| p.repetitions.max(1) as u64).sum();
    let instance_buf = uniform_buffer(device, "instances", SLOT * reps_total.max(1));
    let blocks = param_blocks(gpu, plan, params);
    let mut report = ReloadReport {
        resources_created: pool.created.clone(),
        resources_reused: pool.reused.clone(),
        ..Default::default()
    };
    // What only some Plans read (rays need the scene's acceleration structure): built the
    // first time a Plan binds it.
    let needs = scene_needs(plan);
    let accel = match needs.accel {
        true => Some(err_scope(gpu, "building the acceleration structure", || shared.accel(gpu))??),
        false => None,
    };
    let hits = match needs.hits {
        true => Some(err_scope(gpu, "building the ray-hit data", || shared.hits(gpu))??),
        false => None,
    };
    let maps = match needs.maps {
        true => Some(err_scope(gpu, "copying the maps looked up at ray hits", || shared.hit_maps(gpu))??),
        false => None,
    };
    let triangles = match needs.triangles {
        true => Some(err_scope(gpu, "building the scene's triangles", || shared.triangles(gpu))??),
        false => None,
    };
    let binder = Binder {
        accel,
        hits,
        maps,
        gpu,
        plan,
        pool: &pool,
        samplers: &samplers,
        frame: &shared.frame_buf,
        lights_buf: &shared.lights_buf,
        triangles,
        area_lights: &shared.scene_gpu.area_lights,
        volumes: (&shared.scene_gpu.light_volumes, &shared.scene_gpu.volumes),
        instance: &instance_buf,
        lights: &shared.lights,
    };
    let (mut fresh, mut passes, mut slot) = (Fresh::new(), vec![], 0u64);
    for (i, pp) in plan.passes.iter().enumerate() {
        let built = pipeline(gpu, exe, i, cache, &mut fresh, &mut report)?;
        let what = format!("pass `{}`", pp.name);
        let param_bufs: Vec<wgpu::Buffer> = blocks[i].iter().map(|(b, _)| b.clone()).collect();
        let reps = err_scope(gpu, &what, || binder.reps(pp, &built.layouts, &param_bufs, &mut slot))??;
        let draw_groups = err_scope(gpu, &what, || binder.draw_groups(pp, &built.layouts, &shared.scene_gpu))??;
        passes.push(PassGpu {
            plan: pp.clone(),
            built,
            reps,
            draw_groups,
        });
    }
    let state = State {
        graph: Graph::of(plan),
        plan: plan.clone(),
        pool,
        params: blocks,
        passes,
        timer: Timer::new(gpu, plan.passes.len()),
    };
    Ok((state, fresh, report))
}
