//! Capability profiles: the features and limits a pipeline is checked against.
//! Offline profiles stand for common targets; the runtime builds one from the live adapter.

use crate::diag::did_you_mean;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;

macro_rules! features {
    ($( $name:ident => $wgpu:literal ),* $(,)?) => {
        /// Optional device features a variant can require (names as in the pipeline file;
        /// `wgpu_name` is the `wgpu::Features` flag the runtime maps it to).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
        pub enum Feature { $($name),* }
        impl Feature {
            pub const ALL: &'static [Feature] = &[$(Feature::$name),*];
            pub const NAMES: &'static [&'static str] = &[$(stringify!($name)),*];
            pub fn name(self) -> &'static str { match self { $(Feature::$name => stringify!($name)),* } }
            pub fn wgpu_name(self) -> &'static str { match self { $(Feature::$name => $wgpu),* } }
        }
    };
}

features! {
    Multiview => "MULTIVIEW",
    ClipDistances => "CLIP_DISTANCES",
    TimestampQuery => "TIMESTAMP_QUERY",
    ShaderF16 => "SHADER_F16",
    Float32Filterable => "FLOAT32_FILTERABLE",
    DepthClipControl => "DEPTH_CLIP_CONTROL",
    DualSourceBlending => "DUAL_SOURCE_BLENDING",
    CubeArrayTextures => "CUBE_ARRAY_TEXTURES",
    Rg11b10UfloatRenderable => "RG11B10UFLOAT_RENDERABLE",
    // Shader capabilities: each lets naga accept what its WGSL uses.
    ShaderF64 => "SHADER_F64",
    ShaderI16 => "SHADER_I16",
    ShaderInt64 => "SHADER_INT64",
    ShaderInt64AtomicMinMax => "SHADER_INT64_ATOMIC_MIN_MAX",
    ShaderInt64AtomicAllOps => "SHADER_INT64_ATOMIC_ALL_OPS",
    ShaderFloat32Atomic => "SHADER_FLOAT32_ATOMIC",
    TextureAtomic => "TEXTURE_ATOMIC",
    Immediates => "IMMEDIATES",
    TextureBindingArray => "TEXTURE_BINDING_ARRAY",
    BufferBindingArray => "BUFFER_BINDING_ARRAY",
    StorageResourceBindingArray => "STORAGE_RESOURCE_BINDING_ARRAY",
    SampledTextureAndStorageBufferArrayNonUniformIndexing => "SAMPLED_TEXTURE_AND_STORAGE_BUFFER_ARRAY_NON_UNIFORM_INDEXING",
    StorageTextureArrayNonUniformIndexing => "STORAGE_TEXTURE_ARRAY_NON_UNIFORM_INDEXING",
    UniformBufferBindingArrays => "UNIFORM_BUFFER_BINDING_ARRAYS",
    ExperimentalRayQuery => "EXPERIMENTAL_RAY_QUERY",
    Subgroup => "SUBGROUP",
    SubgroupVertex => "SUBGROUP_VERTEX",
    SubgroupBarrier => "SUBGROUP_BARRIER",
    PrimitiveIndex => "PRIMITIVE_INDEX",
    ShaderEarlyDepthTest => "SHADER_EARLY_DEPTH_TEST",
    ShaderBarycentrics => "SHADER_BARYCENTRICS",
    Float32Renderable => "(format capability: R32Float, Rg32Float, Rgba32Float as render attachments; GL lacks it)",
    GeometryShader => "(none: WGSL, naga and wgpu have no geometry stage)",
}

impl Feature {
    pub fn from_name(s: &str) -> Option<Feature> {
        Self::NAMES.iter().position(|n| *n == s).map(|i| Self::ALL[i])
    }
}

macro_rules! limits {
    ($( $name:ident ),* $(,)?) => {
        /// Device limits that pipelines can exceed (names as in `wgpu::Limits`).
        #[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
        pub struct Limits { $(pub $name: u64),* }
        impl Limits {
            pub const NAMES: &'static [&'static str] = &[$(stringify!($name)),*];
            pub fn get(&self, name: &str) -> Option<u64> {
                match name { $(stringify!($name) => Some(self.$name),)* _ => None }
            }
            pub fn set(&mut self, name: &str, value: u64) -> bool {
                match name { $(stringify!($name) => { self.$name = value; true })* _ => false }
            }
        }
    };
}

limits! {
    max_texture_dimension_2d,
    max_texture_array_layers,
    max_bind_groups,
    max_bindings_per_bind_group,
    max_color_attachments,
    max_color_attachment_bytes_per_sample,
    max_uniform_buffer_binding_size,
    max_storage_buffer_binding_size,
    max_sampled_textures_per_shader_stage,
    max_samplers_per_shader_stage,
    max_storage_textures_per_shader_stage,
    max_uniform_buffers_per_shader_stage,
    max_storage_buffers_per_shader_stage,
    max_compute_workgroup_size_x,
    max_compute_workgroup_size_y,
    max_compute_workgroup_size_z,
    max_compute_invocations_per_workgroup,
    max_multiview_view_count,
    max_buffer_size,
    max_compute_workgroups_per_dimension,
}

impl Limits {
    /// The WebGPU baseline (wgpu `Limits::default()`).
    pub fn webgpu() -> Self {
        Limits {
            max_texture_dimension_2d: 8192,
            max_texture_array_layers: 256,
            max_bind_groups: 4,
            max_bindings_per_bind_group: 1000,
            max_color_attachments: 8,
            max_color_attachment_bytes_per_sample: 32,
            max_uniform_buffer_binding_size: 64 << 10,
            max_storage_buffer_binding_size: 128 << 20,
            max_sampled_textures_per_shader_stage: 16,
            max_samplers_per_shader_stage: 16,
            max_storage_textures_per_shader_stage: 4,
            max_uniform_buffers_per_shader_stage: 12,
            max_storage_buffers_per_shader_stage: 8,
            max_compute_workgroup_size_x: 256,
            max_compute_workgroup_size_y: 256,
            max_compute_workgroup_size_z: 64,
            max_compute_invocations_per_workgroup: 256,
            max_multiview_view_count: 0,
            max_buffer_size: 256 << 20,
            max_compute_workgroups_per_dimension: 65535,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Profile {
    pub name: String,
    pub features: BTreeSet<Feature>,
    pub limits: Limits,
}

impl Profile {
    pub const OFFLINE: [&'static str; 3] = ["webgpu", "vulkan", "gl"];

    pub fn has(&self, f: Feature) -> bool {
        self.features.contains(&f)
    }

    /// WebGPU baseline: no optional features, default limits.
    pub fn webgpu() -> Self {
        Profile {
            name: "webgpu".into(),
            // WebGPU core renders to 32-bit float formats.
            features: [Feature::Float32Renderable].into_iter().collect(),
            limits: Limits::webgpu(),
        }
    }

    /// A desktop Vulkan device as wgpu exposes it (what Mesa lavapipe offers in CI).
    pub fn vulkan() -> Self {
        let mut limits = Limits::webgpu();
        limits.max_texture_dimension_2d = 16384;
        limits.max_texture_array_layers = 2048;
        limits.max_bind_groups = 8;
        limits.max_sampled_textures_per_shader_stage = 128;
        limits.max_samplers_per_shader_stage = 32;
        limits.max_storage_textures_per_shader_stage = 16;
        limits.max_storage_buffers_per_shader_stage = 16;
        limits.max_compute_invocations_per_workgroup = 1024;
        limits.max_compute_workgroup_size_x = 1024;
        limits.max_compute_workgroup_size_y = 1024;
        limits.max_multiview_view_count = 6;
        let features = [
            Feature::Multiview,
            Feature::ClipDistances,
            Feature::TimestampQuery,
            Feature::ShaderF16,
            Feature::Float32Filterable,
            Feature::DepthClipControl,
            Feature::DualSourceBlending,
            Feature::CubeArrayTextures,
            Feature::Float32Renderable,
            // Shader capabilities Mesa 25 lavapipe exposes through wgpu 30.
            Feature::ShaderF64,
            Feature::ShaderI16,
            Feature::ShaderInt64,
            Feature::ShaderInt64AtomicMinMax,
            Feature::ShaderInt64AtomicAllOps,
            Feature::ShaderFloat32Atomic,
            Feature::TextureAtomic,
            Feature::Immediates,
            Feature::TextureBindingArray,
            Feature::BufferBindingArray,
            Feature::StorageResourceBindingArray,
            Feature::SampledTextureAndStorageBufferArrayNonUniformIndexing,
            Feature::StorageTextureArrayNonUniformIndexing,
            Feature::Subgroup,
            Feature::SubgroupBarrier,
            Feature::PrimitiveIndex,
            Feature::ShaderEarlyDepthTest,
            // Mesa 25 lavapipe's VK_KHR_ray_query, which wgpu 30 exposes as experimental.
            Feature::ExperimentalRayQuery,
        ]
        .into_iter()
        .collect();
        Profile {
            name: "vulkan".into(),
            features,
            limits,
        }
    }

    /// wgpu's GL backend (e.g. llvmpipe through EGL): no multiview, no timestamps.
    pub fn gl() -> Self {
        let mut limits = Limits::webgpu();
        limits.max_texture_dimension_2d = 8192;
        limits.max_storage_textures_per_shader_stage = 8;
        let features = [
            Feature::ClipDistances,
            Feature::Float32Filterable,
            Feature::CubeArrayTextures,
            Feature::Immediates,
            Feature::PrimitiveIndex,
            Feature::ShaderEarlyDepthTest,
        ]
        .into_iter()
        .collect();
        Profile {
            name: "gl".into(),
            features,
            limits,
        }
    }

    pub fn offline(name: &str) -> Result<Profile, String> {
        match name {
            "webgpu" => Ok(Self::webgpu()),
            "vulkan" => Ok(Self::vulkan()),
            "gl" => Ok(Self::gl()),
            other => Err(match did_you_mean(other, Self::OFFLINE) {
                Some(s) => format!("unknown profile `{other}`; did you mean `{s}`?"),
                None => format!("unknown profile `{other}`; expected one of: webgpu, vulkan, gl"),
            }),
        }
    }
}
