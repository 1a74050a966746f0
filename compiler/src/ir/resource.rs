//! Declared resources (textures, buffers) and samplers.

use super::LightKind;
use crate::format::TextureFormat;
use crate::span::{Span, Spanned};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ViewDim {
    D2,
    D2Array,
    Cube,
}

impl ViewDim {
    pub fn name(self) -> &'static str {
        match self {
            ViewDim::D2 => "D2",
            ViewDim::D2Array => "D2Array",
            ViewDim::Cube => "Cube",
        }
    }
    pub const NAMES: [&'static str; 3] = ["D2", "D2Array", "Cube"];
    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "D2" => Some(ViewDim::D2),
            "D2Array" => Some(ViewDim::D2Array),
            "Cube" => Some(ViewDim::Cube),
            _ => None,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum SizeSpec {
    /// A fraction of the output resolution (1.0 = full size).
    Viewport {
        scale: f64,
    },
    Fixed {
        width: u32,
        height: u32,
    },
    /// Square, as many texels each way as the Int parameter says (e.g. an RSM's size).
    Param(String),
    /// The output resolution scaled by a Float parameter (an occlusion buffer at w/2 × h/2).
    ViewportParam(String),
}

impl SizeSpec {
    /// The size at this viewport, with `param` giving parameters' values.
    pub fn resolve(&self, viewport: (u32, u32), param: &dyn Fn(&str) -> Option<f64>) -> (u32, u32) {
        let scaled = |scale: f64| {
            (
                ((viewport.0 as f64 * scale).round() as u32).max(1),
                ((viewport.1 as f64 * scale).round() as u32).max(1),
            )
        };
        match self {
            SizeSpec::Viewport { scale } => scaled(*scale),
            SizeSpec::Fixed { width, height } => (*width, *height),
            SizeSpec::Param(name) => {
                let n = (param(name).unwrap_or(1.0).max(1.0)) as u32;
                (n, n)
            }
            SizeSpec::ViewportParam(name) => scaled(param(name).unwrap_or(1.0)),
        }
    }

    /// The parameter the size depends on, if any.
    pub fn param(&self) -> Option<&str> {
        match self {
            SizeSpec::Param(n) | SizeSpec::ViewportParam(n) => Some(n),
            _ => None,
        }
    }
    pub fn describe(&self) -> String {
        match self {
            SizeSpec::Viewport { scale } if *scale == 1.0 => "viewport".into(),
            SizeSpec::Viewport { scale } => format!("viewport × {scale}"),
            SizeSpec::Fixed { width, height } => format!("{width}×{height}"),
            SizeSpec::Param(name) => format!("{name}²"),
            SizeSpec::ViewportParam(name) => format!("viewport × {name}"),
        }
    }
}

/// Where a resource's initial content comes from: a file next to the pipeline (PNG, EXR,
/// raw little-endian bytes; a JSON array of numbers for buffers) or numbers written inline.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum DataSource {
    File(String),
    /// 32-bit floats, little-endian.
    F32(Vec<f64>),
    /// 32-bit unsigned integers, little-endian.
    U32(Vec<u64>),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TextureDesc {
    pub format: Spanned<TextureFormat>,
    pub size: Spanned<SizeSpec>,
    pub layers: Spanned<u32>,
    pub view: Spanned<ViewDim>,
    pub mips: Spanned<u32>,
    /// One instance per light of these kinds.
    pub per_light: Option<Spanned<Vec<LightKind>>>,
    /// Keeps the previous frame's value, readable as `Prev("name")`.
    pub history: bool,
    /// Supplied from outside the graph (by the runtime); no pass needs to write it.
    pub external: bool,
    /// Initial content, uploaded once.
    pub data: Option<Spanned<DataSource>>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BufferDesc {
    /// Size in bytes (per pixel of the viewport with `per_pixel`).
    pub size: Spanned<u64>,
    /// `size` bytes for each pixel of the viewport (per-pixel lists, heads of linked lists).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub per_pixel: bool,
    pub per_light: Option<Spanned<Vec<LightKind>>>,
    pub history: bool,
    pub external: bool,
    /// Initial content, uploaded once.
    pub data: Option<Spanned<DataSource>>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ResourceKind {
    Texture(TextureDesc),
    Buffer(BufferDesc),
    /// The scene's ray-tracing acceleration structure: the executor builds one bottom level
    /// per mesh and the top level from the instances; no pass writes it, passes that trace
    /// rays read it (a WGSL `acceleration_structure` global).
    AccelerationStructure,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Resource {
    pub name: Spanned<String>,
    pub kind: ResourceKind,
    /// The range every value must lie in (`lightbench verify` checks it), e.g. `(0, 65504)`
    /// for radiance: non-negative and within f16.
    pub valid: Option<Spanned<(f64, f64)>>,
    pub span: Span,
}

impl Resource {
    pub fn texture(&self) -> Option<&TextureDesc> {
        match &self.kind {
            ResourceKind::Texture(t) => Some(t),
            ResourceKind::Buffer(_) | ResourceKind::AccelerationStructure => None,
        }
    }
    pub fn is_accel(&self) -> bool {
        matches!(self.kind, ResourceKind::AccelerationStructure)
    }
    pub fn per_light(&self) -> Option<&Spanned<Vec<LightKind>>> {
        match &self.kind {
            ResourceKind::Texture(t) => t.per_light.as_ref(),
            ResourceKind::Buffer(b) => b.per_light.as_ref(),
            ResourceKind::AccelerationStructure => None,
        }
    }
    pub fn history(&self) -> bool {
        match &self.kind {
            ResourceKind::Texture(t) => t.history,
            ResourceKind::Buffer(b) => b.history,
            ResourceKind::AccelerationStructure => false,
        }
    }
    pub fn external(&self) -> bool {
        match &self.kind {
            ResourceKind::Texture(t) => t.external,
            ResourceKind::Buffer(b) => b.external,
            ResourceKind::AccelerationStructure => false,
        }
    }
    /// Content comes from outside the passes (the caller, `data`, or the scene for an
    /// acceleration structure): no writer needed.
    pub fn supplied(&self) -> bool {
        self.external() || self.data().is_some() || self.is_accel()
    }
    pub fn data(&self) -> Option<&Spanned<DataSource>> {
        match &self.kind {
            ResourceKind::Texture(t) => t.data.as_ref(),
            ResourceKind::Buffer(b) => b.data.as_ref(),
            ResourceKind::AccelerationStructure => None,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum FilterMode {
    Nearest,
    Linear,
}

impl FilterMode {
    pub const NAMES: [&'static str; 2] = ["Nearest", "Linear"];
    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "Nearest" => Some(FilterMode::Nearest),
            "Linear" => Some(FilterMode::Linear),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            FilterMode::Nearest => "Nearest",
            FilterMode::Linear => "Linear",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum AddressMode {
    ClampToEdge,
    Repeat,
    MirrorRepeat,
}

impl AddressMode {
    pub const NAMES: [&'static str; 3] = ["ClampToEdge", "Repeat", "MirrorRepeat"];
    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "ClampToEdge" => Some(AddressMode::ClampToEdge),
            "Repeat" => Some(AddressMode::Repeat),
            "MirrorRepeat" => Some(AddressMode::MirrorRepeat),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            AddressMode::ClampToEdge => "ClampToEdge",
            AddressMode::Repeat => "Repeat",
            AddressMode::MirrorRepeat => "MirrorRepeat",
        }
    }
}

/// The sampler binding kind wgpu needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum SamplerKind {
    Filtering,
    NonFiltering,
    Comparison,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SamplerDecl {
    pub name: Spanned<String>,
    pub filter: FilterMode,
    pub mipmap: FilterMode,
    pub address: AddressMode,
    /// A comparison sampler (shadow maps) when set.
    pub compare: Option<super::CompareFn>,
    pub span: Span,
}

impl SamplerDecl {
    /// The binding kind wgpu needs: comparison, filtering (any linear filter) or non-filtering.
    pub fn binding_kind(&self) -> SamplerKind {
        if self.compare.is_some() {
            SamplerKind::Comparison
        } else if self.filter == FilterMode::Linear || self.mipmap == FilterMode::Linear {
            SamplerKind::Filtering
        } else {
            SamplerKind::NonFiltering
        }
    }
}
