//! Passes: raster (draws the scene or procedural vertices), fullscreen (one triangle),
//! compute (dispatch). Each kind carries only its own data.

use super::{Choice, Condition, LightKind, ParamValue, Stage};
use crate::span::{Span, Spanned};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
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
    pub fn name(self) -> &'static str {
        Self::NAMES[Self::ALL.iter().position(|c| *c == self).unwrap_or(0)]
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum CullMode {
    None,
    Front,
    Back,
}

impl CullMode {
    pub const NAMES: [&'static str; 3] = ["None", "Front", "Back"];
    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "None" => Some(CullMode::None),
            "Front" => Some(CullMode::Front),
            "Back" => Some(CullMode::Back),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            CullMode::None => "None",
            CullMode::Front => "Front",
            CullMode::Back => "Back",
        }
    }
}

/// Blend presets; enough for light accumulation and compositing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Blend {
    /// dst + src (light accumulation).
    Add,
    /// Standard "over" with source alpha.
    Alpha,
    /// dst * src (AO / shadow modulation).
    Multiply,
    /// src + dst * src1, per channel: dual-source blending, the second source being the
    /// shader's `@blend_src(1)` output (a coloured transmittance). Needs `DualSourceBlending`.
    DualSource,
}

impl Blend {
    pub const NAMES: [&'static str; 4] = ["Add", "Alpha", "Multiply", "DualSource"];
    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "Add" => Some(Blend::Add),
            "Alpha" => Some(Blend::Alpha),
            "Multiply" => Some(Blend::Multiply),
            "DualSource" => Some(Blend::DualSource),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Blend::Add => "Add",
            Blend::Alpha => "Alpha",
            Blend::Multiply => "Multiply",
            Blend::DualSource => "DualSource",
        }
    }
}

/// How an attachment starts: cleared to a value (RGBA for color, depth for depth) or loaded.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Load<T> {
    Clear(T),
    Load,
}

impl<T> Load<T> {
    pub fn is_load(&self) -> bool {
        matches!(self, Load::Load)
    }
}

/// Which layer(s) of an attachment a pass renders into.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum LayerSel {
    /// Layer 0 (or the current light's instance of a per-light resource).
    Base,
    /// The current cube face of a per-face pass.
    Face,
    /// A fixed layer.
    Index(u32),
    /// All layers at once, as a 2D-array view (multiview).
    All,
    /// The layer of the current repetition of a `repeat` pass, plus an offset (`Rep(-1)`:
    /// the layer the repetition before wrote). Read, an offset before the first layer wraps
    /// around to the last ones (the first repetition has no earlier layer to read).
    Rep(i32),
}

impl LayerSel {
    /// The layer at repetition `rep` of a texture with `layers` layers, for the kinds that
    /// name one (`Base`, `Index`, `Rep`).
    pub fn at(self, rep: u32, layers: u32) -> Option<u32> {
        match self {
            LayerSel::Base => Some(0),
            LayerSel::Index(n) => Some(n),
            LayerSel::Rep(d) => Some((rep as i64 + d as i64).rem_euclid(layers.max(1) as i64) as u32),
            LayerSel::Face | LayerSel::All => None,
        }
    }
}

/// How many times a `repeat` pass runs in a row: a number, or an Int parameter's value (fixed
/// when the Plan is made, like a size).
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Repeat {
    Times(u32),
    Param(String),
}

/// Which mip level of a resource a target or read means.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum MipSel {
    /// A fixed level.
    Level(u32),
    /// The level of the current repetition of a `per_mip` pass, plus an offset
    /// (`Rep(-1)`: the level above, the next larger one).
    Rep(i32),
}

impl MipSel {
    /// The level for repetition level `rep` (`None` when the offset leaves the chain).
    pub fn level(self, rep: u32) -> Option<u32> {
        match self {
            MipSel::Level(l) => Some(l),
            MipSel::Rep(d) => u32::try_from(rep as i64 + d as i64).ok(),
        }
    }
}

/// The mip levels a `per_mip` pass repeats over, from `from` to `to` inclusive (downwards
/// when `from > to`, as an up-sample chain runs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct MipRange {
    pub from: u32,
    pub to: u32,
}

impl MipRange {
    pub fn levels(self) -> Vec<u32> {
        if self.from <= self.to {
            (self.from..=self.to).collect()
        } else {
            (self.to..=self.from).rev().collect()
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColorTarget {
    pub resource: Spanned<String>,
    pub load: Load<[f64; 4]>,
    pub blend: Option<Spanned<Blend>>,
    pub layer: LayerSel,
    pub mip: Spanned<MipSel>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DepthTarget {
    pub resource: Spanned<String>,
    pub load: Load<f64>,
    pub compare: CompareFn,
    pub write: bool,
    pub layer: LayerSel,
    pub mip: Spanned<MipSel>,
    pub span: Span,
}

/// What a raster or fullscreen pass renders into.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Targets {
    pub color: Vec<ColorTarget>,
    pub depth: Option<DepthTarget>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Draw {
    /// Every opaque (and alpha-masked) mesh of the scene with its material.
    Scene,
    /// The scene's blended meshes (glTF alphaMode BLEND), from far to near the camera.
    Transparent,
    /// A fixed vertex count with no vertex buffers (procedural geometry).
    Vertices(u32),
    /// Vertex pulling over the scene: this many vertices for each triangle of the opaque and
    /// masked meshes, as one instance per triangle; the shader reads triangle
    /// `instance_index` from the standard `triangles` buffer (volumes a geometry shader
    /// would emit, e.g. ambient occlusion volumes).
    Triangles(u32),
    /// In a per-light pass: the bounding volume of the repetition's light, from the runtime's
    /// standard `light_volumes` buffer (a sphere for point lights, a cone for spot lights, one
    /// full-screen triangle for directional lights), for deferred lighting that shades only the
    /// pixels a light can reach (seed 003 §3.2.1). The vertex shader reads its vertex from
    /// `light_volumes` (see `shaders/lib/light_volume.wgsl`).
    LightVolume,
}

impl Draw {
    /// Draws scene meshes (vertex buffers, per-draw bindings).
    pub fn uses_scene(&self) -> bool {
        matches!(self, Draw::Scene | Draw::Transparent)
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Dispatch {
    /// One invocation per texel of a resource, divided by the shader's workgroup size.
    Size(Spanned<String>),
    /// Explicit workgroup counts.
    Groups(u32, u32, u32),
}

/// A shader module and an entry point in it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShaderRef {
    /// Path relative to the shader root (`shaders/`).
    pub file: Spanned<String>,
    pub entry: Spanned<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Raster {
    pub vertex: ShaderRef,
    /// `None`: depth-only.
    pub fragment: Option<ShaderRef>,
    pub targets: Targets,
    pub draw: Draw,
    pub cull: CullMode,
    /// Instances per draw (the instanced cube-shadow atlas draws each mesh 6 times).
    pub instances: Spanned<u32>,
    /// Render all views of a multiview attachment in one pass.
    pub multiview: Option<Spanned<u32>>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fullscreen {
    /// The vertex stage is built in (one triangle, `uv` at location 0).
    pub fragment: ShaderRef,
    pub targets: Targets,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Compute {
    pub entry: ShaderRef,
    pub dispatch: Spanned<Dispatch>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum PassKind {
    Raster(Raster),
    Fullscreen(Fullscreen),
    Compute(Compute),
}

impl PassKind {
    /// `raster`, `fullscreen` or `compute`.
    pub fn word(&self) -> &'static str {
        match self {
            PassKind::Raster(_) => "raster",
            PassKind::Fullscreen(_) => "fullscreen",
            PassKind::Compute(_) => "compute",
        }
    }
}

/// The vertex stage every fullscreen pass gets: one triangle covering the target, `uv` at location 0.
pub const FULLSCREEN_FILE: &str = "<builtin>/fullscreen.wgsl";
pub const FULLSCREEN_ENTRY: &str = "fullscreen_vs";

/// GLSL 450 shader files, by extension (one stage per file, entry point `main`).
pub fn is_glsl(path: &str) -> bool {
    [".vert", ".frag", ".comp", ".glsl"].iter().any(|e| path.ends_with(e))
}

/// The entry point a stage gets when the pipeline file names none: `main` for GLSL,
/// `vs_main` / `fs_main` / `cs_main` for WGSL.
pub fn default_entry(stage: Stage, file: &str) -> &'static str {
    if is_glsl(file) {
        return "main";
    }
    match stage {
        Stage::Vertex => "vs_main",
        Stage::Fragment => "fs_main",
        Stage::Compute => "cs_main",
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Read {
    /// The current frame's value.
    Current(Spanned<String>),
    /// The previous frame's value of a history resource.
    Prev(Spanned<String>),
    /// One mip level of the current frame's value.
    Mip(Spanned<String>, Spanned<MipSel>),
    /// One array layer of the current frame's value, bound as a 2D texture: `Index(n)` or
    /// the repetition's `Rep(offset)`.
    Layer(Spanned<String>, Spanned<LayerSel>),
}

impl Read {
    pub fn name(&self) -> &Spanned<String> {
        match self {
            Read::Current(n) | Read::Prev(n) | Read::Mip(n, _) | Read::Layer(n, _) => n,
        }
    }
    /// The one mip level read, if the read names one.
    pub fn mip(&self) -> Option<MipSel> {
        match self {
            Read::Mip(_, m) => Some(m.value),
            _ => None,
        }
    }
    /// The one array layer read, if the read names one.
    pub fn layer(&self) -> Option<LayerSel> {
        match self {
            Read::Layer(_, l) => Some(l.value),
            _ => None,
        }
    }
    pub fn is_prev(&self) -> bool {
        matches!(self, Read::Prev(_))
    }
}

/// A value for a shader `override` (a specialisation constant), fixed when the Plan is made.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Constant {
    Number(f64),
    Bool(bool),
    /// A parameter's value (Int, Float or Bool): a new value means a new Plan.
    Param(String),
    /// `true` while the variant's option is chosen.
    Variant(String, String),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pass {
    pub name: Spanned<String>,
    pub kind: PassKind,
    /// Sampled textures and read-only buffers.
    pub reads: Vec<Read>,
    /// Storage textures and buffers written (compute, or fragment with storage).
    pub writes: Vec<Spanned<String>>,
    /// Parameters in this pass's uniform block.
    pub params: Vec<Spanned<String>>,
    /// Fields of the parameter block fixed to literal values for this pass (a blur's
    /// direction, a sample count): no user-facing parameter, so one shader serves many passes.
    pub values: Vec<(Spanned<String>, Spanned<ParamValue>)>,
    /// Name of the shader global holding the parameter block.
    pub param_block: Spanned<String>,
    /// Explicit shader global -> declared name map, overriding the naming rule.
    pub bind: Vec<(Spanned<String>, Spanned<String>)>,
    /// Values of the shaders' `override` declarations, by name.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub constants: Vec<(Spanned<String>, Spanned<Constant>)>,
    pub when: Option<Spanned<Condition>>,
    /// Run once per light of these kinds.
    pub per_light: Option<Spanned<Vec<LightKind>>>,
    /// Run once per cube face (6 times; per light when `per_light` is set too).
    pub per_face: bool,
    /// With `per_light`: run only for the lights that cast shadows (a light's `shadows:
    /// false` removes its repetition; its shader reads it as unshadowed).
    pub shadow_casters: bool,
    /// Run once per mip level of this range (targets and reads select levels with `Rep`).
    pub per_mip: Option<Spanned<MipRange>>,
    /// Run this many times in a row (targets and reads select array layers with `Rep`;
    /// the shader reads the repetition as `instance.repetition`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub repeat: Option<Spanned<Repeat>>,
    /// Run every frame even when nothing it depends on changed (hidden inputs).
    pub always: bool,
    /// For a pass of a used pipeline: that pipeline's file (`plan --explain` says so).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<String>,
    /// Where it was written, when that says more than the pass: the groups around it, the
    /// templates it is like, the pass a choice by light kind made it from (`plan --explain`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub origin: Option<String>,
    /// For one copy of a pass written with choices: which arms it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub choice: Option<Choice>,
    pub span: Span,
}

impl Pass {
    /// The pass's stages in pipeline order; a fullscreen pass's vertex stage is the built-in one.
    pub fn stages(&self) -> Vec<(Stage, ShaderRef)> {
        match &self.kind {
            PassKind::Raster(r) => {
                let mut v = vec![(Stage::Vertex, r.vertex.clone())];
                v.extend(r.fragment.clone().map(|f| (Stage::Fragment, f)));
                v
            }
            PassKind::Fullscreen(f) => vec![
                (
                    Stage::Vertex,
                    ShaderRef {
                        file: Spanned::new(FULLSCREEN_FILE.to_string(), self.span),
                        entry: Spanned::new(FULLSCREEN_ENTRY.to_string(), self.span),
                    },
                ),
                (Stage::Fragment, f.fragment.clone()),
            ],
            PassKind::Compute(c) => vec![(Stage::Compute, c.entry.clone())],
        }
    }

    /// The stage whose file the pass's `shader` names: vertex for raster, fragment for
    /// fullscreen, compute for compute.
    pub fn main_stage(&self) -> &ShaderRef {
        match &self.kind {
            PassKind::Raster(r) => &r.vertex,
            PassKind::Fullscreen(f) => &f.fragment,
            PassKind::Compute(c) => &c.entry,
        }
    }

    /// Color and depth targets (none for compute passes).
    pub fn targets(&self) -> Option<&Targets> {
        match &self.kind {
            PassKind::Raster(r) => Some(&r.targets),
            PassKind::Fullscreen(f) => Some(&f.targets),
            PassKind::Compute(_) => None,
        }
    }

    pub fn color(&self) -> &[ColorTarget] {
        self.targets().map(|t| t.color.as_slice()).unwrap_or(&[])
    }

    pub fn depth(&self) -> Option<&DepthTarget> {
        self.targets().and_then(|t| t.depth.as_ref())
    }

    /// Every resource this pass writes: attachments and storage writes.
    /// Resources this pass changes: color targets, a depth target it writes or clears, storage
    /// writes. (A depth target with `write: false` and `load: Load` is only tested against.)
    pub fn written(&self) -> impl Iterator<Item = &Spanned<String>> {
        let depth = self.depth().filter(|d| d.write || !d.load.is_load());
        self.color()
            .iter()
            .map(|c| &c.resource)
            .chain(depth.map(|d| &d.resource))
            .chain(self.writes.iter())
    }

    /// A depth target only tested against (`write: false`, `load: Load`): read, not written,
    /// so the pass runs after its writers (e.g. transparent surfaces over the G-buffer depth).
    pub fn depth_tested(&self) -> Option<&Spanned<String>> {
        self.depth().filter(|d| !d.write && d.load.is_load()).map(|d| &d.resource)
    }

    /// Every resource the pass reads (declared reads and a tested depth) or changes.
    pub fn touched(&self) -> impl Iterator<Item = &Spanned<String>> {
        self.reads.iter().map(|r| r.name()).chain(self.depth_tested()).chain(self.written())
    }

    /// Does this pass's write of `res` build on the earlier content (`load: Load`)?
    pub fn accumulates(&self, res: &str) -> bool {
        self.color().iter().any(|c| c.resource.value == res && c.load.is_load())
            || self.depth().is_some_and(|d| d.resource.value == res && d.load.is_load())
    }
}
