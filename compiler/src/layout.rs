//! Binding and parameter-block layouts: derived by the `bindings` check from shader
//! reflection plus declared formats, carried by the Plan, consumed by the runtime.
//! Shared leaf types: nothing here is a string the runtime would have to re-parse.

use crate::format::TextureFormat;
use crate::ir::{SamplerKind, Stage};
use serde::{Deserialize, Serialize};

/// A texture view dimension as the shader declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ShaderDim {
    D1,
    D2,
    D2Array,
    Cube,
    CubeArray,
    D3,
}

impl ShaderDim {
    pub fn wgsl_word(self) -> &'static str {
        match self {
            ShaderDim::D1 => "1d",
            ShaderDim::D2 => "2d",
            ShaderDim::D2Array => "2d_array",
            ShaderDim::Cube => "cube",
            ShaderDim::CubeArray => "cube_array",
            ShaderDim::D3 => "3d",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SampleType {
    Float { filterable: bool },
    Depth,
    Uint,
    Sint,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum StorageAccess {
    ReadOnly,
    WriteOnly,
    ReadWrite,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum BindingType {
    Texture {
        sample_type: SampleType,
        view_dimension: ShaderDim,
        multisampled: bool,
    },
    StorageTexture {
        format: TextureFormat,
        access: StorageAccess,
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
    /// The scene's top-level acceleration structure (WGSL `acceleration_structure`).
    AccelerationStructure,
}

/// Global names of the standard blocks the runtime provides (see `shaders/lib/frame.wgsl`).
pub const FRAME: &str = "frame";
pub const INSTANCE: &str = "instance";
pub const LIGHTS: &str = "lights";
pub const TRIANGLES: &str = "triangles";
pub const LIGHT_VOLUMES: &str = "light_volumes";
pub const AREA_LIGHTS: &str = "area_lights";
pub const HIT_TRIANGLES: &str = "hit_triangles";
pub const HIT_MATERIALS: &str = "hit_materials";
pub const HIT_EMITTERS: &str = "hit_emitters";
pub const HIT_CORNERS: &str = "hit_corners";
pub const HIT_MAPS: &str = "hit_maps";

macro_rules! draw_slots {
    ($( $variant:ident = $name:literal ),* $(,)?) => {
        /// Per-draw slots bound for each mesh in `draw: Scene` passes (see `shaders/lib/mesh.wgsl`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
        pub enum DrawSlot { $($variant),* }
        impl DrawSlot {
            pub const ALL: &'static [DrawSlot] = &[$(DrawSlot::$variant),*];
            /// The shader global's name.
            pub fn name(self) -> &'static str { match self { $(DrawSlot::$variant => $name),* } }
            pub fn from_name(s: &str) -> Option<DrawSlot> { match s { $($name => Some(DrawSlot::$variant),)* _ => None } }
        }
    };
}

draw_slots! {
    Mesh = "mesh",
    Material = "material",
    BaseColorMap = "base_color_map",
    NormalMap = "normal_map",
    MetallicRoughnessMap = "metallic_roughness_map",
    EmissiveMap = "emissive_map",
    MaterialSampler = "material_sampler",
    OcclusionMap = "occlusion_map",
}

/// What the runtime binds at a slot. `R` and `S` name resources and samplers: declared
/// names while checking, Plan indices once planned.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum BindSource<R, S> {
    /// A declared resource (the current light's instance for per-light resources).
    Resource(R),
    /// The previous frame's value of a history resource.
    Prev(R),
    Sampler(S),
    /// This pass's parameter block (see the pass's uniform blocks).
    Params,
    /// The standard per-frame block (camera, resolution, time, light count).
    Frame,
    /// The standard per-repetition block (light index, face, view count).
    Instance,
    /// The scene's light array (storage, read-only).
    Lights,
    /// The scene's opaque and masked triangles in world space, 3 `vec4` (w: 1) each, as a
    /// table of texels (`texture_2d_array<u32>`, `shaders/lib/table.wgsl`), for vertex pulling.
    Triangles,
    /// The runtime's light-volume meshes, non-indexed triangle lists of `vec4` corners (w: the
    /// shape, see `shaders/lib/light_volume.wgsl`), drawn by `draw: LightVolume` passes.
    LightVolumes,
    /// The scene's emissive triangles as area lights, `AreaLight` structs of 4 `vec4` each
    /// (storage, read-only; see `shaders/lib/area_light.wgsl`).
    AreaLights,
    /// What a ray query's hit needs to shade it: per traced triangle its corners' shading
    /// normals, front normal and material, indexed by the hit's instance custom data plus its
    /// primitive index (a table of texels, see `shaders/lib/hit.wgsl`); built with the
    /// acceleration structure.
    HitTriangles,
    /// The traced meshes' materials (`HitMaterial`, `shaders/lib/hit.wgsl`).
    HitMaterials,
    /// The traced emissive triangles as lights, each with its probability of being chosen
    /// (in proportion to its power; `HitEmitter`, a table of texels after one holding the
    /// count, `shaders/lib/hit_emitters.wgsl`).
    HitEmitters,
    /// Per traced triangle its corners' texture coordinates, both sets, and tangents
    /// (`HitCorners`, a table of texels, `shaders/lib/hit_maps.wgsl`): where a hit's maps are
    /// looked up.
    HitCorners,
    /// The scene's texture maps at full resolution as one table of texels (the count, an
    /// entry of offset, size and row pitch per map, then RGBA8 texels), for lookups at ray hits.
    HitMaps,
    /// A per-draw slot of the mesh being drawn.
    Draw(DrawSlot),
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Binding<R, S> {
    pub binding: u32,
    /// The shader global's name.
    pub name: String,
    pub source: BindSource<R, S>,
    pub ty: BindingType,
    /// Stages whose entry points use it.
    pub visibility: Vec<Stage>,
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct BindGroupLayout<R, S> {
    pub group: u32,
    pub entries: Vec<Binding<R, S>>,
}

impl<R, S> BindGroupLayout<R, S> {
    /// A group holding per-draw slots holds nothing else (checked), so one entry decides.
    pub fn is_per_draw(&self) -> bool {
        self.entries.iter().any(|e| matches!(e.source, BindSource::Draw(_)))
    }
}

/// Index of a parameter in the pipeline's (and the Plan's) parameter list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ParamId(pub u32);

/// Host-shareable types a parameter block field can have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum FieldType {
    F32,
    I32,
    U32,
    Vec2F32,
    Vec3F32,
    Vec4F32,
}

impl FieldType {
    /// From the WGSL spelling naga prints (`f32`, `vec3<f32>`); `None` for any other type.
    pub fn from_wgsl(s: &str) -> Option<Self> {
        Some(match s {
            "f32" => FieldType::F32,
            "i32" => FieldType::I32,
            "u32" => FieldType::U32,
            "vec2<f32>" => FieldType::Vec2F32,
            "vec3<f32>" => FieldType::Vec3F32,
            "vec4<f32>" => FieldType::Vec4F32,
            _ => return None,
        })
    }
    pub fn wgsl(self) -> &'static str {
        match self {
            FieldType::F32 => "f32",
            FieldType::I32 => "i32",
            FieldType::U32 => "u32",
            FieldType::Vec2F32 => "vec2<f32>",
            FieldType::Vec3F32 => "vec3<f32>",
            FieldType::Vec4F32 => "vec4<f32>",
        }
    }
    /// 32-bit components.
    pub fn components(self) -> usize {
        match self {
            FieldType::F32 | FieldType::I32 | FieldType::U32 => 1,
            FieldType::Vec2F32 => 2,
            FieldType::Vec3F32 => 3,
            FieldType::Vec4F32 => 4,
        }
    }
}

/// What a parameter-block field holds.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum FieldSource {
    /// A pipeline parameter (its override or default).
    Param(ParamId),
    /// A per-pass value, already as the field's 32-bit words.
    Fixed(Vec<u32>),
}

#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct UniformField {
    /// Field name in the shader struct.
    pub name: String,
    /// The parameter or per-pass value written there.
    pub source: FieldSource,
    pub offset: u32,
    pub size: u32,
    pub ty: FieldType,
}

/// A pass's parameter block: offsets from naga's layout of the shader struct.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct UniformBlock {
    pub global: String,
    pub group: u32,
    pub binding: u32,
    pub size: u32,
    pub align: u32,
    pub fields: Vec<UniformField>,
}
