//! Variants: named choices that swap passes (via `when: Variant(..)`) or shaders.

use super::Literal;
use crate::profile::Feature;
use crate::span::{Span, Spanned};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VariantOption {
    pub name: Spanned<String>,
    /// wgpu features the option needs.
    pub requires: Vec<Spanned<Feature>>,
    /// Minimum values of named limits (e.g. `max_multiview_view_count: 6`).
    pub limits: Vec<(Spanned<String>, Spanned<u64>)>,
    /// Option to use instead when the capability profile lacks a requirement.
    pub fallback: Option<Spanned<String>>,
    /// Shader substitutions: pass name -> shader file (same entry points).
    pub shaders: Vec<(Spanned<String>, Spanned<String>)>,
    /// A preset: parameter values the option brings (`set(ao.samples = 8)`), used in place of
    /// the parameters' defaults while it is chosen; a user's own override still wins.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub params: Vec<(Spanned<String>, Spanned<Literal>)>,
    /// The option jitters the camera by a sub-pixel offset each frame (as the pipeline's
    /// `jitter` does), for the passes it brings that accumulate over frames (TAA).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub jitter: bool,
    pub doc: Option<String>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Variant {
    pub name: Spanned<String>,
    pub options: Vec<VariantOption>,
    pub default: Spanned<String>,
    pub doc: Option<String>,
    pub span: Span,
}

impl Variant {
    pub fn option(&self, name: &str) -> Option<&VariantOption> {
        self.options.iter().find(|o| o.name.value == name)
    }
    pub fn option_names(&self) -> Vec<&str> {
        self.options.iter().map(|o| o.name.value.as_str()).collect()
    }
}
