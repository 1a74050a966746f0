//! Passes: raster (draws the scene), fullscreen (one triangle), compute (dispatch).

use super::{Condition, LightKind};
use crate::span::{Span, Spanned};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum CompareFn {
    Never,
    Less,
    LessEqual,
    Equal,
    Greater,
    GreaterEqual,
    NotEqual,
    Always,
}

impl CompareFn {
    pub const NAMES: [&'static str; 8] = [
        "Never",
        "Less",
        "LessEqual",
        "Equal",
        "Greater",
        "GreaterEqual",
        "NotEqual",
        "Always",
    ];
    pub const ALL: [CompareFn; 8] = [
        CompareFn::Never,
        CompareFn::Less,
        CompareFn::LessEqual,
        CompareFn::Equal,
        CompareFn::Greater,
        CompareFn::GreaterEqual,
        CompareFn::NotEqual,
        CompareFn::Always,
    ];
    pub fn from_name(s: &str) -> Option<Self> {
        Self::NAMES.iter().position(|n| *n == s).map(|i| Self::ALL[i])
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum CullMode {
    None,
    Front,
    Back,
}

/// Blend presets; enough for light accumulation and compositing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Blend {
    /// dst + src (light accumulation).
    Add,
    /// Standard "over" with source alpha.
    Alpha,
    /// dst * src (AO / shadow modulation).
    Multiply,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum LoadOp {
    Clear(Vec<f64>),
    Load,
}

/// Which layer(s) of an attachment a pass renders into.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LayerSel {
    /// Layer 0 (or the current light's instance of a per-light resource).
    Base,
    /// The current cube face of a per-face pass.
    Face,
    /// A fixed layer.
    Index(u32),
    /// All layers at once, as a 2D-array view (multiview).
    All,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColorTarget {
    pub resource: Spanned<String>,
    pub load: LoadOp,
    pub blend: Option<Spanned<Blend>>,
    pub layer: LayerSel,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DepthTarget {
    pub resource: Spanned<String>,
    pub load: LoadOp,
    pub compare: CompareFn,
    pub write: bool,
    pub layer: LayerSel,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Draw {
    /// Every mesh of the scene with its material.
    Scene,
    /// A fixed vertex count with no vertex buffers (procedural geometry).
    Vertices(u32),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Dispatch {
    /// One invocation per texel of a resource, divided by the shader's workgroup size.
    Size(Spanned<String>),
    /// Explicit workgroup counts.
    Groups(u32, u32, u32),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum PassKind {
    Raster {
        draw: Draw,
        cull: CullMode,
        /// Instances per draw (the instanced cube-shadow atlas draws each mesh 6 times).
        instances: u32,
        /// Render all views of a multiview attachment in one pass.
        multiview: Option<Spanned<u32>>,
    },
    Fullscreen,
    Compute {
        dispatch: Dispatch,
    },
}

impl PassKind {
    pub fn word(&self) -> &'static str {
        match self {
            PassKind::Raster { .. } => "raster",
            PassKind::Fullscreen => "fullscreen",
            PassKind::Compute { .. } => "compute",
        }
    }
}

/// The entry point a stage gets when the pipeline file names none: `main` for GLSL,
/// `vs_main` / `fs_main` / `cs_main` for WGSL.
pub fn default_entry(stage: naga::ShaderStage, file: &str) -> &'static str {
    if crate::shader::is_glsl(file) {
        return "main";
    }
    match stage {
        naga::ShaderStage::Vertex => "vs_main",
        naga::ShaderStage::Fragment => "fs_main",
        _ => "cs_main",
    }
}

/// How a pipeline file writes a stage whose pass names `pass_file` as its shader: `None` when
/// the default entry applies, `file#entry` for another file, else the entry name. Both printers
/// use it, so RON and LBP agree on what is implied.
pub fn written_entry(r: &ShaderRef, pass_file: Option<&str>, stage: naga::ShaderStage, default_applies: bool) -> Option<String> {
    if Some(r.file.value.as_str()) != pass_file {
        return Some(format!("{}#{}", r.file.value, r.entry.value));
    }
    if default_applies && r.entry.value == default_entry(stage, &r.file.value) {
        return None;
    }
    Some(r.entry.value.clone())
}

/// A shader module and an entry point in it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShaderRef {
    /// Path relative to the shader root (`shaders/`).
    pub file: Spanned<String>,
    pub entry: Spanned<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Read {
    /// The current frame's value.
    Current(Spanned<String>),
    /// The previous frame's value of a history resource.
    Prev(Spanned<String>),
}

impl Read {
    pub fn name(&self) -> &Spanned<String> {
        match self {
            Read::Current(n) | Read::Prev(n) => n,
        }
    }
    pub fn is_prev(&self) -> bool {
        matches!(self, Read::Prev(_))
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pass {
    pub name: Spanned<String>,
    pub kind: PassKind,
    pub vertex: Option<ShaderRef>,
    pub fragment: Option<ShaderRef>,
    pub compute: Option<ShaderRef>,
    /// Sampled textures and read-only buffers.
    pub reads: Vec<Read>,
    /// Storage textures and buffers written (compute, or fragment with storage).
    pub writes: Vec<Spanned<String>>,
    pub color: Vec<ColorTarget>,
    pub depth: Option<DepthTarget>,
    /// Parameters in this pass's uniform block.
    pub params: Vec<Spanned<String>>,
    /// Name of the shader global holding the parameter block.
    pub param_block: Spanned<String>,
    /// Explicit shader global -> declared name map, overriding the naming rule.
    pub bind: Vec<(Spanned<String>, Spanned<String>)>,
    pub when: Option<Spanned<Condition>>,
    /// Run once per light of these kinds.
    pub per_light: Option<Spanned<Vec<LightKind>>>,
    /// Run once per cube face (6 times; per light when `per_light` is set too).
    pub per_face: bool,
    pub span: Span,
}

impl Pass {
    pub fn stages(&self) -> impl Iterator<Item = (naga::ShaderStage, &ShaderRef)> {
        [
            (naga::ShaderStage::Vertex, self.vertex.as_ref()),
            (naga::ShaderStage::Fragment, self.fragment.as_ref()),
            (naga::ShaderStage::Compute, self.compute.as_ref()),
        ]
        .into_iter()
        .filter_map(|(s, r)| r.map(|r| (s, r)))
    }

    /// Every resource this pass writes: attachments and storage writes.
    pub fn written(&self) -> impl Iterator<Item = &Spanned<String>> {
        self.color
            .iter()
            .map(|c| &c.resource)
            .chain(self.depth.as_ref().map(|d| &d.resource))
            .chain(self.writes.iter())
    }

    /// Does this pass's write of `res` build on the earlier content (`load: Load`)?
    pub fn accumulates(&self, res: &str) -> bool {
        self.color.iter().any(|c| c.resource.value == res && c.load == LoadOp::Load)
            || self
                .depth
                .as_ref()
                .is_some_and(|d| d.resource.value == res && d.load == LoadOp::Load)
    }
}
