//! The Plan: everything the runtime needs to execute one configuration of a pipeline,
//! and nothing it would have to decide itself. Serializable and stable for snapshots.

pub mod build;
mod explain;

pub use build::{build_plan, Config, Selection};
pub use explain::work_word;
pub use explain::{to_dot, to_text};

use crate::ir::{AddressMode, Blend, CompareFn, CullMode, FilterMode, LayerSel, LightKind, ParamType, ParamValue};
use crate::shader::reflect::ShaderDim;
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum SamplerKind {
    Filtering,
    NonFiltering,
    Comparison,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum SampleType {
    Float { filterable: bool },
    Depth,
    Uint,
    Sint,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum BindingType {
    Texture {
        sample_type: SampleType,
        view_dimension: ShaderDim,
        multisampled: bool,
    },
    StorageTexture {
        format: String,
        access: String,
        view_dimension: ShaderDim,
    },
    Sampler(SamplerKind),
    Uniform {
        min_binding_size: u32,
    },
    Storage {
        read_only: bool,
        min_binding_size: u32,
    },
}

/// What the runtime binds at a slot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum BindSource {
    /// A declared resource (the current light's instance for per-light resources).
    Resource(String),
    /// The previous frame's value of a history resource.
    Prev(String),
    Sampler(String),
    /// This pass's parameter block (see `uniform_blocks`).
    Params,
    /// The standard per-frame block (camera, resolution, time, light count).
    Frame,
    /// The standard per-repetition block (light index, face, view count).
    Instance,
    /// The scene's light array (storage, read-only).
    Lights,
    /// A per-draw slot of the mesh being drawn (`mesh`, `material`, `base_color_map`, ...).
    Draw(String),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanBinding {
    pub binding: u32,
    /// The shader global's name.
    pub name: String,
    pub source: BindSource,
    pub ty: BindingType,
    /// Stages whose entry points use it: "vertex", "fragment", "compute".
    pub visibility: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanBindGroup {
    pub group: u32,
    pub entries: Vec<PlanBinding>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UniformField {
    /// Field name in the shader struct.
    pub name: String,
    /// Pipeline parameter written there.
    pub param: String,
    pub offset: u32,
    pub size: u32,
    /// WGSL type, e.g. `vec3<f32>`; bools and enums are `u32`.
    pub ty: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UniformBlock {
    pub global: String,
    pub group: u32,
    pub binding: u32,
    pub size: u32,
    pub align: u32,
    pub fields: Vec<UniformField>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanStage {
    pub stage: String,
    pub file: String,
    pub entry: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanAttachment {
    pub resource: String,
    pub format: String,
    /// `None` = load; `Some(values)` = clear to these values.
    pub clear: Option<Vec<f64>>,
    pub blend: Option<Blend>,
    pub layer: LayerSel,
    /// Depth attachments only.
    pub depth_compare: Option<CompareFn>,
    pub depth_write: Option<bool>,
}

/// What a pass does once its bindings are set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Work {
    /// Draw every scene mesh (indexed, with the standard vertex layout).
    Scene,
    /// Draw this many vertices with no vertex buffers.
    Vertices(u32),
    /// One triangle covering the targets.
    Fullscreen,
    /// Compute workgroups; `sized_from` names the resource the count was derived from.
    Dispatch { groups: [u32; 3], sized_from: Option<String> },
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanPass {
    pub name: String,
    pub kind: String,
    pub stages: Vec<PlanStage>,
    pub work: Work,
    pub workgroup_size: Option<[u32; 3]>,
    pub cull: Option<CullMode>,
    pub instances: u32,
    pub multiview: Option<u32>,
    pub per_light: Vec<LightKind>,
    pub per_face: bool,
    /// How many times the pass runs for this scene (lights × faces).
    pub repetitions: u32,
    pub color: Vec<PlanAttachment>,
    pub depth: Option<PlanAttachment>,
    pub reads: Vec<String>,
    pub writes: Vec<String>,
    pub bind_groups: Vec<PlanBindGroup>,
    pub uniform_blocks: Vec<UniformBlock>,
    /// Passes whose results this one needs (after culling).
    pub after: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CulledPass {
    pub name: String,
    pub reason: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanResource {
    pub name: String,
    /// `texture` or `buffer`.
    pub kind: String,
    pub format: Option<String>,
    /// The size rule: `viewport`, `viewport × 0.5`, `512×512` or `N bytes`.
    pub size: String,
    /// The size at the plan's resolution.
    pub extent: (u32, u32),
    pub layers: u32,
    pub view: Option<String>,
    pub mips: u32,
    pub per_light: Vec<LightKind>,
    /// Instances for this scene: one per matching light, else one.
    pub instances: u32,
    pub history: bool,
    pub external: bool,
    /// wgpu usage flags derived from how passes use it.
    pub usage: Vec<String>,
    pub bytes: u64,
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

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    pub pipeline: String,
    pub profile: String,
    pub scene: String,
    pub resolution: (u32, u32),
    pub lights: Vec<(LightKind, u32)>,
    pub variants: Vec<ChosenVariant>,
    pub params: Vec<PlanParam>,
    pub samplers: Vec<PlanSampler>,
    /// Passes in execution order.
    pub passes: Vec<PlanPass>,
    pub culled: Vec<CulledPass>,
    pub resources: Vec<PlanResource>,
    pub output: String,
    pub memory_bytes: u64,
}

impl Plan {
    pub fn pass(&self, name: &str) -> Option<&PlanPass> {
        self.passes.iter().find(|p| p.name == name)
    }
    pub fn resource(&self, name: &str) -> Option<&PlanResource> {
        self.resources.iter().find(|r| r.name == name)
    }
}
