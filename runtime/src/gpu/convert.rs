//! Plan values (names and enums from the compiler) to wgpu types.

use lightbench_compiler::ir::{AddressMode, Blend, CompareFn, CullMode, FilterMode};
use lightbench_compiler::plan::{BindingType, SampleType, SamplerKind};
use lightbench_compiler::shader::reflect::ShaderDim;

pub fn format(name: &str) -> Result<wgpu::TextureFormat, String> {
    use wgpu::TextureFormat as F;
    Ok(match name {
        "R8Unorm" => F::R8Unorm,
        "Rg8Unorm" => F::Rg8Unorm,
        "Rgba8Unorm" => F::Rgba8Unorm,
        "Rgba8UnormSrgb" => F::Rgba8UnormSrgb,
        "Bgra8Unorm" => F::Bgra8Unorm,
        "Bgra8UnormSrgb" => F::Bgra8UnormSrgb,
        "Rgb10a2Unorm" => F::Rgb10a2Unorm,
        "Rg11b10Ufloat" => F::Rg11b10Ufloat,
        "R16Float" => F::R16Float,
        "Rg16Float" => F::Rg16Float,
        "Rgba16Float" => F::Rgba16Float,
        "R32Float" => F::R32Float,
        "Rg32Float" => F::Rg32Float,
        "Rgba32Float" => F::Rgba32Float,
        "R32Uint" => F::R32Uint,
        "Rg32Uint" => F::Rg32Uint,
        "Rgba32Uint" => F::Rgba32Uint,
        "R32Sint" => F::R32Sint,
        "Rgba16Uint" => F::Rgba16Uint,
        "Depth16Unorm" => F::Depth16Unorm,
        "Depth24Plus" => F::Depth24Plus,
        "Depth32Float" => F::Depth32Float,
        "Depth24PlusStencil8" => F::Depth24PlusStencil8,
        other => return Err(format!("texture format `{other}` has no wgpu equivalent")),
    })
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

pub fn stages(vis: &[String]) -> wgpu::ShaderStages {
    let mut s = wgpu::ShaderStages::empty();
    for v in vis {
        s |= match v.as_str() {
            "vertex" => wgpu::ShaderStages::VERTEX,
            "fragment" => wgpu::ShaderStages::FRAGMENT,
            "compute" => wgpu::ShaderStages::COMPUTE,
            _ => wgpu::ShaderStages::empty(),
        };
    }
    s
}

pub fn binding_type(t: &BindingType) -> Result<wgpu::BindingType, String> {
    Ok(match t {
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
            access: match access.as_str() {
                "ReadOnly" => wgpu::StorageTextureAccess::ReadOnly,
                "ReadWrite" => wgpu::StorageTextureAccess::ReadWrite,
                _ => wgpu::StorageTextureAccess::WriteOnly,
            },
            format: format(f)?,
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
    })
}

pub fn usage(names: &[String]) -> wgpu::TextureUsages {
    let mut u = wgpu::TextureUsages::empty();
    for n in names {
        u |= match n.as_str() {
            "RENDER_ATTACHMENT" => wgpu::TextureUsages::RENDER_ATTACHMENT,
            "TEXTURE_BINDING" => wgpu::TextureUsages::TEXTURE_BINDING,
            "STORAGE_BINDING" => wgpu::TextureUsages::STORAGE_BINDING,
            "COPY_SRC" => wgpu::TextureUsages::COPY_SRC,
            "COPY_DST" => wgpu::TextureUsages::COPY_DST,
            _ => wgpu::TextureUsages::empty(),
        };
    }
    u
}
