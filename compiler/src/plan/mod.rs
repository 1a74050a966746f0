//! The Plan: everything the runtime needs to execute one configuration of a pipeline, and
//! nothing it would have to decide itself. Typed throughout: passes, resources and samplers
//! are addressed by index, names are kept for display. Serializable and stable for snapshots.

pub mod alias;
mod build;
mod bytes;
mod constants;
mod copies;
mod cull;
mod deps;
mod diff;
mod explain;
mod merge;
pub mod order;
mod params;
mod passes;
mod resources;
pub mod reuse;
mod select;

pub use build::{build_plan, check_configuration};
pub use cull::{schedule, Schedule};
pub use diff::{diff, Change, PassChange, PlanDiff};
pub use explain::{memory_text, mib_text, pass_facts, resource_fact, to_dot, to_text, work_word};
pub use params::{declared_param, pass_value_params, plan_param, ParamError, ParamValues};
pub use select::{select, unsupported_options, Selection};

use crate::check::PassVersion;
use crate::format::TextureFormat;
use crate::ir::scene::SceneFeatures;
use crate::ir::{
    AddressMode, Blend, CompareFn, CullMode, Draw, Effect, FilterMode, LayerSel, LightKind, Load, MipRange, MipSel, ParamType, ParamValue,
    SamplerKind, SizeSpec, Stage, ViewDim,
};
use crate::layout::{BindGroupLayout, BindSource, Binding, UniformBlock};
use crate::profile::Profile;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;

/// What a configuration is planned for.
pub struct Config<'a> {
    pub profile: &'a Profile,
    pub scene: &'a SceneFeatures,
    pub selection: Selection,
    /// Parameter overrides that size resources (`size: Param(..)`); the rest use defaults.
    pub params: &'a ParamValues,
    /// A real scene (`plan`, `render`, `check --scene`), not `check`'s stand-ins for every
    /// scene: only then does a kept pass that renders to a format the profile cannot render to
    /// fail the plan (without one, the declaration check warns).
    pub scene_known: bool,
    /// Orders the other configurations of one check worked out (`check_configurations`).
    pub orders: Option<&'a order::Orders>,
}

impl Config<'_> {
    /// A texture's extent in this configuration.
    pub fn extent(&self, p: &crate::ir::Pipeline, size: &SizeSpec) -> (u32, u32) {
        let param = |name: &str| {
            let prm = p.param(name)?;
            let v = self.params.get(name).cloned().unwrap_or_else(|| self.default_of(p, prm).0);
            match v {
                ParamValue::Int(i) => u32::try_from(i).ok().map(f64::from),
                ParamValue::Float(f) => Some(f),
                _ => None,
            }
        };
        size.resolve(self.scene.size, &param)
    }

    /// How many times a `repeat` pass runs in this configuration (1 without `repeat`; a
    /// parameter's value as overridden, at least 1: the check holds it to its range).
    pub fn repeat_count(&self, p: &crate::ir::Pipeline, r: Option<&crate::ir::Repeat>) -> u32 {
        let value = match r {
            None => return 1,
            Some(crate::ir::Repeat::Times(n)) => *n as i64,
            Some(crate::ir::Repeat::Param(name)) => match p.param(name) {
                Some(prm) => match self.params.get(name).cloned().unwrap_or_else(|| self.default_of(p, prm).0) {
                    ParamValue::Int(i) => i,
                    _ => 1,
                },
                None => 1,
            },
        };
        value.clamp(1, u32::MAX as i64) as u32
    }

    /// A parameter's value before overrides: the preset of a chosen option that sets it (with
    /// the option, as `variant=option`), else its declared default.
    pub fn default_of(&self, p: &crate::ir::Pipeline, prm: &crate::ir::Param) -> (ParamValue, Option<String>) {
        for v in &p.variants {
            let chosen = self.selection.chosen.get(&v.name.value).and_then(|o| v.option(o));
            let set = chosen.and_then(|o| o.params.iter().find(|(k, _)| k.value == prm.name.value).map(|(_, lit)| (o, lit)));
            if let Some((o, lit)) = set {
                if let Some(value) = crate::check::declarations::preset_value(p, &prm.name.value, &lit.value) {
                    return (value, Some(format!("{}={}", v.name.value, o.name.value)));
                }
            }
        }
        (prm.default.value.clone(), None)
    }
}

/// The kept passes in execution order: index into the pipeline's passes, and the version
/// the selection picks.
type Kept<'a> = Vec<(usize, &'a PassVersion)>;

/// Index of a pass in `Plan::passes` (execution order).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct PassId(pub u32);

/// Index of a resource in `Plan::resources`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ResourceId(pub u32);

/// Index of a sampler in `Plan::samplers`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct SamplerId(pub u32);

pub use crate::layout::ParamId;

pub type PlanBindGroup = BindGroupLayout<ResourceId, SamplerId>;
pub type PlanBinding = Binding<ResourceId, SamplerId>;
pub type PlanSource = BindSource<ResourceId, SamplerId>;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanStage {
    pub stage: Stage,
    pub file: String,
    pub entry: String,
    /// Values of the module's `override`s the pass sets (key: the name, or an `@id` as
    /// digits), as wgpu's pipeline constants take them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub constants: Vec<(String, f64)>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColorAttachment {
    pub resource: ResourceId,
    pub format: TextureFormat,
    pub load: Load<[f64; 4]>,
    pub blend: Option<Blend>,
    pub layer: LayerSel,
    pub mip: MipSel,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DepthAttachment {
    pub resource: ResourceId,
    pub format: TextureFormat,
    pub load: Load<f64>,
    pub compare: CompareFn,
    pub write: bool,
    pub layer: LayerSel,
    pub mip: MipSel,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PlanTargets {
    pub color: Vec<ColorAttachment>,
    pub depth: Option<DepthAttachment>,
}

/// What a pass does once its bindings are set; each kind carries only its own data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Work {
    /// Draw the scene's meshes (indexed, standard vertex layout) or a fixed vertex count.
    Raster {
        draw: Draw,
        cull: CullMode,
        instances: u32,
        /// Views rendered at once into the layers of the attachments.
        multiview: Option<u32>,
        targets: PlanTargets,
    },
    /// One triangle covering the targets.
    Fullscreen { targets: PlanTargets },
    /// Compute workgroups; `sized_from` is the resource the count was derived from.
    Compute {
        groups: [u32; 3],
        workgroup_size: [u32; 3],
        sized_from: Option<ResourceId>,
    },
}

impl Work {
    pub fn targets(&self) -> Option<&PlanTargets> {
        match self {
            Work::Raster { targets, .. } | Work::Fullscreen { targets } => Some(targets),
            Work::Compute { .. } => None,
        }
    }
    /// `raster`, `fullscreen` or `compute`.
    pub fn kind_word(&self) -> &'static str {
        match self {
            Work::Raster { .. } => "raster",
            Work::Fullscreen { .. } => "fullscreen",
            Work::Compute { .. } => "compute",
        }
    }
    pub fn multiview(&self) -> Option<u32> {
        match self {
            Work::Raster { multiview, .. } => *multiview,
            _ => None,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlanRead {
    pub resource: ResourceId,
    /// The previous frame's value of a history resource.
    pub prev: bool,
    /// One mip level (else the whole chain).
    pub mip: Option<MipSel>,
    /// One array layer, bound as a 2D texture (else every layer): a fixed one or the
    /// repetition's (`Rep`).
    pub layer: Option<LayerSel>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanPass {
    pub name: String,
    pub work: Work,
    pub stages: Vec<PlanStage>,
    pub per_light: Vec<LightKind>,
    /// Only the lights of `per_light` that cast shadows.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub shadow_casters: bool,
    pub per_face: bool,
    /// The mip levels it repeats over, in order.
    pub per_mip: Option<MipRange>,
    /// Times in a row a `repeat` pass runs (1 otherwise).
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub repeat: u32,
    /// How many times the pass runs for this scene (lights × faces × mip levels × repeat).
    pub repetitions: u32,
    /// Each run, in order: lights outermost, then faces, mip levels, runs of a `repeat`.
    pub reps: Vec<PlanRep>,
    pub reads: Vec<PlanRead>,
    /// Storage writes (attachments are in the work's targets).
    pub writes: Vec<ResourceId>,
    pub bind_groups: Vec<PlanBindGroup>,
    pub uniform_blocks: Vec<UniformBlock>,
    /// Passes whose results this one needs (after culling).
    pub after: Vec<PassId>,
    /// What its result depends on besides the resources it reads (reuse of unchanged work).
    pub depends: Depends,
    /// For a pass written with choices: the arms this configuration takes, per variant the
    /// options the arm serves (`plan --explain` shows them).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub arms: Vec<(String, Vec<String>)>,
    /// For a pass of a used pipeline: that pipeline's file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<String>,
    /// Where it was written: groups, templates, a choice by light kind (`plan --explain`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub origin: Option<String>,
    /// It may be recorded inside the previous pass's render pass (stage `merge`): it renders
    /// into the same attachments and loads them, and neither writes storage.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub continues: bool,
}

/// One run of a pass: for which light (its index in the light array the frame binds, the
/// scene's lights that are on, in order), cube face, mip level and run of a `repeat`; what
/// the per-repetition block (`instance`) tells the shader.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlanRep {
    pub light: Option<u32>,
    pub face: u32,
    pub mip: Option<u32>,
    pub run: u32,
    /// Which copy of each per-light resource the pass uses this run binds or renders into
    /// (stage `copies`); empty for a run with no light. A resource not listed: copy 0.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub copies: Vec<PlanCopy>,
}

impl PlanRep {
    /// The copy (instance) of `resource` this run uses: 0 unless `copies` says otherwise.
    pub fn copy_of(&self, resource: ResourceId) -> u32 {
        self.copies.iter().find(|c| c.resource == resource).map_or(0, |c| c.instance)
    }
}

/// One per-light resource's copy a repetition uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlanCopy {
    pub resource: ResourceId,
    pub instance: u32,
}

/// What a pass's result depends on besides the resources it reads and its parameter block:
/// derived from which standard-block fields its shaders read (naga reflection). The
/// runtime runs a pass only when one of these, or a resource it reads, changed since it
/// last ran.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Depends {
    /// Frame-block fields its shaders read (found by the bytes they read).
    pub frame_fields: Vec<crate::abi::FrameField>,
    /// The camera: view and projection fields (and jitter), or a back-to-front draw order.
    pub camera: bool,
    pub time: bool,
    pub frame_index: bool,
    /// The whole light array (a per-light pass always depends on its own light).
    pub lights: bool,
    /// The scene's meshes and materials (it draws them).
    pub scene: bool,
    /// Runs every frame regardless, and why (`always`, history resources).
    pub always: Option<String>,
}

impl PlanPass {
    pub fn stage(&self, s: Stage) -> Option<&PlanStage> {
        self.stages.iter().find(|x| x.stage == s)
    }
    /// Every resource the pass uses: what it writes, reads, binds or is sized from, once each.
    pub fn used(&self) -> Vec<ResourceId> {
        let bound = self.bind_groups.iter().flat_map(|g| &g.entries).filter_map(|e| match e.source {
            PlanSource::Resource(r) | PlanSource::Prev(r) => Some(r),
            _ => None,
        });
        let sized = match &self.work {
            Work::Compute { sized_from, .. } => *sized_from,
            _ => None,
        };
        let mut used: Vec<ResourceId> = self.written();
        used.extend(self.reads.iter().map(|r| r.resource).chain(bound).chain(sized));
        let mut seen = std::collections::BTreeSet::new();
        used.retain(|r| seen.insert(r.0));
        used
    }

    /// Every resource the pass writes: color and depth attachments, then storage writes.
    pub fn written(&self) -> Vec<ResourceId> {
        let t = self.work.targets();
        t.into_iter()
            .flat_map(|t| t.color.iter().map(|c| c.resource).chain(t.depth.as_ref().map(|d| d.resource)))
            .chain(self.writes.iter().copied())
            .collect()
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CulledPass {
    pub name: String,
    pub reason: String,
}

/// An effect the scene calls for that no kept pass serves, and the first of its passes culled
/// for want of what the scene lacks, with why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UnservedEffect {
    pub effect: Effect,
    pub pass: String,
    pub reason: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ResourceShape {
    Texture {
        format: TextureFormat,
        /// The size rule, and the size at the plan's resolution.
        size: SizeSpec,
        extent: (u32, u32),
        layers: u32,
        view: ViewDim,
        mips: u32,
    },
    Buffer {
        /// Bytes of one instance.
        size: u64,
        /// What its 32-bit words hold, as the shaders binding it declare them.
        words: Words,
    },
    /// The scene's ray-tracing acceleration structure, which the executor builds from the
    /// scene (one bottom level per mesh, the top level from the instances).
    AccelerationStructure,
}

/// The scalar type of a buffer's words: `U32`/`I32` when every shader binding it declares
/// only such scalars (e.g. `array<u32>`), else `F32`. Read-backs print them so.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Words {
    #[default]
    F32,
    U32,
    I32,
}

/// How passes use a resource (the runtime maps these to wgpu usage flags).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Usage {
    RenderAttachment,
    TextureBinding,
    StorageBinding,
    Storage,
    Uniform,
    CopySrc,
    CopyDst,
    /// Bound as an acceleration structure that shaders trace rays against.
    RayQuery,
}

impl Usage {
    pub fn name(self) -> &'static str {
        match self {
            Usage::RenderAttachment => "RENDER_ATTACHMENT",
            Usage::TextureBinding => "TEXTURE_BINDING",
            Usage::StorageBinding => "STORAGE_BINDING",
            Usage::Storage => "STORAGE",
            Usage::Uniform => "UNIFORM",
            Usage::CopySrc => "COPY_SRC",
            Usage::CopyDst => "COPY_DST",
            Usage::RayQuery => "ACCELERATION_STRUCTURE",
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanResource {
    pub name: String,
    pub shape: ResourceShape,
    pub per_light: Vec<LightKind>,
    /// Written only by `shadow_casters` passes: one instance per casting light (at least one).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub casters_only: bool,
    /// Instances for this scene: one per matching light (casting light for `casters_only`),
    /// else one.
    pub instances: u32,
    pub history: bool,
    pub external: bool,
    /// Filled once from the pipeline's `data`: `contents`.
    pub data: bool,
    /// The bytes a `data` resource is filled with (mip 0 of each layer, rows tightly packed,
    /// in its format), so that a Plan runs without the pipeline's files; base64 in JSON.
    #[serde(default, skip_serializing_if = "Option::is_none", with = "bytes")]
    pub contents: Option<std::sync::Arc<Vec<u8>>>,
    /// The range every value must lie in (`lightbench verify`).
    pub valid: Option<(f64, f64)>,
    pub usage: BTreeSet<Usage>,
    /// Memory of every instance and history copy.
    pub bytes: u64,
    /// A transient resource whose passes all run after the last pass using this earlier one
    /// (stage `alias`): it may live in that one's memory, if the executor aliases.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shares: Option<ResourceId>,
}

impl PlanResource {
    pub fn is_buffer(&self) -> bool {
        matches!(self.shape, ResourceShape::Buffer { .. })
    }
    /// Array layers (1 for buffers).
    pub fn layers(&self) -> u32 {
        match self.shape {
            ResourceShape::Texture { layers, .. } => layers,
            ResourceShape::Buffer { .. } | ResourceShape::AccelerationStructure => 1,
        }
    }
    pub fn is_accel(&self) -> bool {
        matches!(self.shape, ResourceShape::AccelerationStructure)
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChosenVariant {
    pub variant: String,
    pub option: String,
    /// Set when the chosen option differs from the requested one, or to say why it was kept.
    pub reason: Option<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanParam {
    pub name: String,
    pub ty: ParamType,
    pub default: ParamValue,
    pub min: Option<ParamValue>,
    pub max: Option<ParamValue>,
    pub doc: Option<String>,
    /// The chosen variant option (`variant=option`) whose preset gave `default`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// For a parameter the Plan fixes — it sizes resources (`size: Param(..)`), repeats a
    /// pass (`repeat: Param(..)`) or sets a shader constant (`constants`) —: the value this
    /// Plan was made with. Another value needs another Plan.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sizes: Option<ParamValue>,
    /// For a per-pass value made addressable (`PASS.KEY`): the pass whose `values` set it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pass: Option<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanSampler {
    pub name: String,
    pub kind: SamplerKind,
    pub filter: FilterMode,
    pub mipmap: FilterMode,
    pub address: AddressMode,
    pub compare: Option<CompareFn>,
}

/// The version of the Plan's data format (`plan --json`, specified in `docs/plan.md`): raised
/// when a field changes meaning or goes; new optional fields keep it.
pub const FORMAT: u32 = 2;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// `FORMAT` when the Plan was made (0: a Plan from before formats were numbered).
    #[serde(default)]
    pub format: u32,
    pub pipeline: String,
    pub profile: String,
    pub scene: String,
    pub resolution: (u32, u32),
    pub lights: Vec<(LightKind, u32)>,
    pub variants: Vec<ChosenVariant>,
    /// Every declared parameter, in declaration order (`ParamId` indexes it).
    pub params: Vec<PlanParam>,
    pub samplers: Vec<PlanSampler>,
    /// Passes in execution order.
    pub passes: Vec<PlanPass>,
    pub culled: Vec<CulledPass>,
    /// Effects that passes of the pipeline serve, culled because the scene does not call for
    /// them (a model given on its own calls for shadows only): what `render` notes once.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub uncalled_effects: Vec<Effect>,
    /// Effects the scene calls for whose serving passes are all culled, one or more for want
    /// of a light kind or of blended meshes (an emitter-lit scene calling for indirect light
    /// that RSMs of directional and spot lights give): what `render` notes once, not a silent 0.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub unserved_effects: Vec<UnservedEffect>,
    pub resources: Vec<PlanResource>,
    pub output: ResourceId,
    /// The linear image before tone mapping, when the pipeline names one (`hdr_output`).
    pub hdr_output: Option<ResourceId>,
    pub memory_bytes: u64,
    /// Memory with transient resources aliased (`PlanResource::shares`).
    #[serde(default)]
    pub physical_bytes: u64,
    /// Sub-pixel camera jitter each frame (Halton 2, 3; `frame.jitter`).
    pub jitter: bool,
    /// The text of every shader file a kept pass's stage names (`PlanStage::file`), once per
    /// file, as its compiler read it: what an executor of its own compiles.
    #[serde(default)]
    pub shaders: Vec<PlanShader>,
}

/// A shader file as the compiler read it, `#include`s spliced in.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanShader {
    /// The path stages name it by (`PlanStage::file`).
    pub file: String,
    pub language: ShaderLanguage,
    pub text: String,
}

/// The language of a shader's text: WGSL, or GLSL 450 (its stage is the stage naming it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ShaderLanguage {
    Wgsl,
    Glsl,
}

impl Plan {
    pub fn pass(&self, name: &str) -> Option<&PlanPass> {
        self.passes.iter().find(|p| p.name == name)
    }
    pub fn resource_id(&self, name: &str) -> Option<ResourceId> {
        self.resources.iter().position(|r| r.name == name).map(|i| ResourceId(i as u32))
    }
    pub fn resource(&self, name: &str) -> Option<&PlanResource> {
        self.resources.iter().find(|r| r.name == name)
    }
    pub fn res(&self, id: ResourceId) -> &PlanResource {
        &self.resources[id.0 as usize]
    }
    pub fn sampler(&self, id: SamplerId) -> &PlanSampler {
        &self.samplers[id.0 as usize]
    }
    pub fn param(&self, id: ParamId) -> &PlanParam {
        &self.params[id.0 as usize]
    }
    pub fn output_resource(&self) -> &PlanResource {
        self.res(self.output)
    }
    /// The text of the shader file a stage names.
    pub fn shader(&self, file: &str) -> Option<&PlanShader> {
        self.shaders.iter().find(|s| s.file == file)
    }
}

fn one() -> u32 {
    1
}

fn is_one(n: &u32) -> bool {
    *n == 1
}
