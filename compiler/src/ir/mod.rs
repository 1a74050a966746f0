//! The pipeline IR: the one data model every front end produces and every check reads.
//! Every node carries the span of the pipeline-file text it came from.

mod choice;
mod condition;
mod param;
mod pass;
mod resource;
pub mod scene;
mod stage;
mod variant;

pub use choice::{Choice, Source};
pub use condition::{Condition, Effect, LetDecl, LightKind};
pub use param::{out_of_range, Literal, Param, ParamType, ParamValue, ValueError};
pub use pass::{
    default_entry, is_glsl, Blend, ColorTarget, CompareFn, Compute, Constant, CullMode, DepthTarget, Dispatch, Draw, Fullscreen, LayerSel,
    Load, MipRange, MipSel, Pass, PassKind, Raster, Read, Repeat, ShaderRef, Targets, FULLSCREEN_ENTRY, FULLSCREEN_FILE,
};
pub use resource::{
    AddressMode, BufferDesc, DataSource, FilterMode, Resource, ResourceKind, SamplerDecl, SamplerKind, SizeSpec, TextureDesc, ViewDim,
};
pub use stage::{naga_stage_word, Stage};
pub use variant::{Variant, VariantOption};

use crate::span::{Span, Spanned};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pipeline {
    pub name: Spanned<String>,
    pub params: Vec<Param>,
    pub samplers: Vec<SamplerDecl>,
    pub resources: Vec<Resource>,
    pub passes: Vec<Pass>,
    pub variants: Vec<Variant>,
    /// Named conditions (`let NAME = …`), as declared; each use is a `Condition::Named`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lets: Vec<LetDecl>,
    /// The resource presented or saved.
    pub output: Spanned<String>,
    /// The linear (HDR) image before tone mapping, saved when an `.exr` is asked for.
    pub hdr_output: Option<Spanned<String>>,
    /// Every pass runs every frame (no reuse of unchanged work).
    pub always: bool,
    /// Sub-pixel camera jitter (Halton 2, 3), for temporal accumulation.
    pub jitter: bool,
    /// For a pipeline that uses another: the file as written (`fmt` and `convert` print it).
    #[serde(skip)]
    pub written: Option<Source>,
    pub span: Span,
}

impl Pipeline {
    /// The passes as written: a pass with choices once (its first copy), the rest as they are.
    pub fn written_passes(&self) -> impl Iterator<Item = &Pass> {
        let first_copy = |i: usize, c: &Choice| {
            !self.passes[..i]
                .iter()
                .any(|q| q.choice.as_ref().is_some_and(|d| d.group == c.group))
        };
        let passes = self.passes.iter().enumerate();
        passes
            .filter(move |(i, p)| p.choice.as_ref().is_none_or(|c| first_copy(*i, c)))
            .map(|(_, p)| p)
    }

    /// Equal as data: the same pipeline whatever file, front end or layout it came from (or
    /// which file it used).
    pub fn same_as(&self, other: &Pipeline) -> bool {
        fn strip(v: serde_json::Value) -> serde_json::Value {
            match v {
                serde_json::Value::Object(m) => {
                    // Where items were written (and which used file they came from) aside.
                    let kept = m.into_iter().filter(|(k, _)| k != "span" && k != "from");
                    serde_json::Value::Object(kept.map(|(k, v)| (k, strip(v))).collect())
                }
                serde_json::Value::Array(a) => serde_json::Value::Array(a.into_iter().map(strip).collect()),
                v => v,
            }
        }
        match (serde_json::to_value(self), serde_json::to_value(other)) {
            (Ok(a), Ok(b)) => strip(a) == strip(b),
            _ => false,
        }
    }

    pub fn param(&self, name: &str) -> Option<&Param> {
        self.params.iter().find(|p| p.name.value == name)
    }
    pub fn resource(&self, name: &str) -> Option<&Resource> {
        self.resources.iter().find(|r| r.name.value == name)
    }
    pub fn sampler(&self, name: &str) -> Option<&SamplerDecl> {
        self.samplers.iter().find(|s| s.name.value == name)
    }
    /// The pass of that name a configuration runs (`variant -> option`): of a pass written
    /// with choices, the copy whose arms are chosen; with its index.
    pub fn pass_chosen(&self, name: &str, chosen: &std::collections::BTreeMap<String, String>) -> Option<(usize, &Pass)> {
        let serves = |p: &Pass| p.choice.as_ref().is_none_or(|c| c.serves(chosen));
        self.passes.iter().enumerate().find(|(_, p)| p.name.value == name && serves(p))
    }

    pub fn pass(&self, name: &str) -> Option<&Pass> {
        self.passes.iter().find(|p| p.name.value == name)
    }
    pub fn variant(&self, name: &str) -> Option<&Variant> {
        self.variants.iter().find(|v| v.name.value == name)
    }

    /// A per-light resource that only `shadow_casters` passes write (a shadow map): it needs
    /// an instance per casting light, and may go unwritten when no light casts shadows.
    pub fn written_by_casters_only(&self, r: &Resource) -> bool {
        let mut writers = self
            .passes
            .iter()
            .filter(|q| q.written().any(|w| w.value == r.name.value))
            .peekable();
        r.per_light().is_some() && writers.peek().is_some() && writers.all(|q| q.shadow_casters)
    }
}

/// The identifier a shader uses for a declared name: every character that cannot
/// appear in a WGSL/GLSL identifier becomes `_` (`gbuf.normal` -> `gbuf_normal`).
pub fn shader_ident(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' })
        .collect()
}

/// Shader identifier of the previous-frame value of a history resource.
pub fn history_ident(name: &str) -> String {
    format!("{}_prev", shader_ident(name))
}
