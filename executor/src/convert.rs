//! Typed Plan values (the compiler's enums) to wgpu types: total mappings, no names parsed.

use lightbench_compiler::format::TextureFormat;
use lightbench_compiler::ir::{AddressMode, Blend, CompareFn, CullMode, FilterMode, SamplerKind, Stage};
use lightbench_compiler::layout::{BindingType, SampleType, ShaderDim, StorageAccess};
use lightbench_compiler::plan::{PlanSampler, Usage};

pub fn format(f: TextureFormat) -> wgpu::TextureFormat {
    use wgpu::TextureFormat as F;
    use TextureFormat as T;
    match f {
        T::R8Unorm => F::R8Unorm,
        T::Rg8Unorm => F::Rg8Unorm,
        T::Rgba8Unorm => F::Rgba8Unorm,
        T::Rgba8UnormSrgb => F::Rgba8UnormSrgb,
        T::Bgra8Unorm => F::Bgra8Unorm,
        T::Bgra8UnormSrgb => F::Bgra8UnormSrgb,
        T::Rgb10a2Unorm => F::Rgb10a2Unorm,
        T::Rg11b10Ufloat => F::Rg11b10Ufloat,
        T::R16Float => F::R16Float,
        T::Rg16Float => F::Rg16Float,
        T::Rgba16Float => F::Rgba16Float,
        T::R32Float => F::R32Float,
        T::Rg32Float => F::Rg32Float,
        T::Rgba32Float => F::Rgba32Float,
        T::R32Uint => F::R32Uint,
        T::Rg32Uint => F::Rg32Uint,
        T::Rgba32Uint => F::Rgba32Uint,
        T::R32Sint => F::R32Sint,
        T::Rgba16Uint => F::Rgba16Uint,
        T::Depth16Unorm => F::Depth16Unorm,
        T::Depth24Plus => F::Depth24Plus,
        T::Depth32Float => F::Depth32Float,
        T::Depth24PlusStencil8 => F::Depth24PlusStencil8,
    }
}

pub fn view_dim(d: ShaderDim) -> wgpu::TextureViewDimension {
    match d {
        ShaderDim::D1 => wgpu::TextureViewDimension::D1,
        ShaderDim::D2 => wgpu::TextureViewDimension::D2,
        ShaderDim::D2Array => wgpu::TextureViewDimension::D2Array,
        ShaderDim::Cube => wgpu::TextureViewDimension::Cube,
        ShaderDim::CubeArray => wgpu::TextureViewDimension::CubeArray,
        ShaderDim::D3 => wgpu::TextureViewDimension::D3,
    }
}

pub fn compare(c: CompareFn) -> wgpu::CompareFunction {
    use wgpu::CompareFunction as C;
    match c {
        CompareFn::Never => C::Never,
        CompareFn::Less => C::Less,
        CompareFn::LessEqual => C::LessEqual,
        CompareFn::Equal => C::Equal,
        CompareFn::Greater => C::Greater,
        CompareFn::GreaterEqual => C::GreaterEqual,
        CompareFn::NotEqual => C::NotEqual,
        CompareFn::Always => C::Always,
    }
}

pub fn blend(b: Blend) -> wgpu::BlendState {
    use wgpu::{BlendComponent as C, BlendFactor as F, BlendOperation as O};
    match b {
        Blend::Add => {
            let add = C {
                src_factor: F::One,
                dst_factor: F::One,
                operation: O::Add,
            };
            wgpu::BlendState { color: add, alpha: add }
        }
        Blend::Alpha => wgpu::BlendState::ALPHA_BLENDING,
        Blend::Multiply => {
            let m = C {
                src_factor: F::Dst,
                dst_factor: F::Zero,
                operation: O::Add,
            };
            wgpu::BlendState { color: m, alpha: m }
        }
        Blend::DualSource => wgpu::BlendState {
            color: C {
                src_factor: F::One,
                dst_factor: F::Src1,
                operation: O::Add,
            },
            alpha: C {
                src_factor: F::One,
                dst_factor: F::Src1Alpha,
                operation: O::Add,
            },
        },
    }
}

pub fn filter(f: FilterMode) -> wgpu::FilterMode {
    match f {
        FilterMode::Nearest => wgpu::FilterMode::Nearest,
        FilterMode::Linear => wgpu::FilterMode::Linear,
    }
}

pub fn mipmap_filter(f: FilterMode) -> wgpu::MipmapFilterMode {
    match f {
        FilterMode::Nearest => wgpu::MipmapFilterMode::Nearest,
        FilterMode::Linear => wgpu::MipmapFilterMode::Linear,
    }
}

/// A Plan's sampler: one filter both ways, one address mode on every axis.
pub fn sampler(s: &PlanSampler) -> wgpu::SamplerDescriptor<'_> {
    let address = address(s.address);
    wgpu::SamplerDescriptor {
        label: Some(&s.name),
        address_mode_u: address,
        address_mode_v: address,
        address_mode_w: address,
        mag_filter: filter(s.filter),
        min_filter: filter(s.filter),
        mipmap_filter: mipmap_filter(s.mipmap),
        compare: s.compare.map(compare),
        ..Default::default()
    }
}

pub fn address(a: AddressMode) -> wgpu::AddressMode {
    match a {
        AddressMode::ClampToEdge => wgpu::AddressMode::ClampToEdge,
        AddressMode::Repeat => wgpu::AddressMode::Repeat,
        AddressMode::MirrorRepeat => wgpu::AddressMode::MirrorRepeat,
    }
}

pub fn cull(c: CullMode) -> Option<wgpu::Face> {
    match c {
        CullMode::None => None,
        CullMode::Front => Some(wgpu::Face::Front),
        CullMode::Back => Some(wgpu::Face::Back),
    }
}

pub fn stages(vis: &[Stage]) -> wgpu::ShaderStages {
    let mut s = wgpu::ShaderStages::empty();
    for v in vis {
        s |= match v {
            Stage::Vertex => wgpu::ShaderStages::VERTEX,
            Stage::Fragment => wgpu::ShaderStages::FRAGMENT,
            Stage::Compute => wgpu::ShaderStages::COMPUTE,
        };
    }
    s
}

pub fn binding_type(t: &BindingType) -> wgpu::BindingType {
    match t {
        BindingType::Texture {
            sample_type,
            view_dimension,
            multisampled,
        } => wgpu::BindingType::Texture {
            sample_type: match sample_type {
                SampleType::Float { filterable } => wgpu::TextureSampleType::Float { filterable: *filterable },
                SampleType::Depth => wgpu::TextureSampleType::Depth,
                SampleType::Uint => wgpu::TextureSampleType::Uint,
                SampleType::Sint => wgpu::TextureSampleType::Sint,
            },
            view_dimension: view_dim(*view_dimension),
            multisampled: *multisampled,
        },
        BindingType::StorageTexture {
            format: f,
            access,
            view_dimension,
        } => wgpu::BindingType::StorageTexture {
            access: match access {
                StorageAccess::ReadOnly => wgpu::StorageTextureAccess::ReadOnly,
                StorageAccess::ReadWrite => wgpu::StorageTextureAccess::ReadWrite,
                StorageAccess::WriteOnly => wgpu::StorageTextureAccess::WriteOnly,
            },
            format: format(*f),
            view_dimension: view_dim(*view_dimension),
        },
        BindingType::Sampler(k) => wgpu::BindingType::Sampler(match k {
            SamplerKind::Filtering => wgpu::SamplerBindingType::Filtering,
            SamplerKind::NonFiltering => wgpu::SamplerBindingType::NonFiltering,
            SamplerKind::Comparison => wgpu::SamplerBindingType::Comparison,
        }),
        BindingType::Uniform { min_binding_size } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: std::num::NonZeroU64::new(*min_binding_size as u64),
        },
        BindingType::Storage {
            read_only,
            min_binding_size,
        } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: *read_only },
            has_dynamic_offset: false,
            min_binding_size: std::num::NonZeroU64::new(*min_binding_size as u64),
        },
        BindingType::AccelerationStructure => wgpu::BindingType::AccelerationStructure { vertex_return: false },
    }
}

/// Texture usages (buffer usages of a Plan resource have no texture equivalent).
pub fn usage(usages: &std::collections::BTreeSet<Usage>) -> wgpu::TextureUsages {
    let mut u = wgpu::TextureUsages::empty();
    for n in usages {
        u |= match n {
            Usage::RenderAttachment => wgpu::TextureUsages::RENDER_ATTACHMENT,
            Usage::TextureBinding => wgpu::TextureUsages::TEXTURE_BINDING,
            Usage::StorageBinding => wgpu::TextureUsages::STORAGE_BINDING,
            Usage::CopySrc => wgpu::TextureUsages::COPY_SRC,
            Usage::CopyDst => wgpu::TextureUsages::COPY_DST,
            Usage::Storage | Usage::Uniform | Usage::RayQuery => wgpu::TextureUsages::empty(),
        };
    }
    u
}
