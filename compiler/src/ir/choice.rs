//! Choices inside a pass: a pass written once with fields chosen by variants
//! (`Match(variant: .., arms: {..})`) is lowered to one pass per combination of arms, each
//! running under the options its arms serve. This is what each copy keeps of that.

use super::Condition;
use crate::span::Spanned;
use crate::tree::{same, Node};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Choice {
    /// The written pass, by its place among the file's passes: the copies of one pass share
    /// it (and its name).
    pub group: u32,
    /// Per variant chosen by, the options this copy serves (in declaration order).
    pub arms: Vec<(String, Vec<String>)>,
    /// The pass's own `when`; the copy's `Pass::when` adds its arms to it.
    pub when: Option<Spanned<Condition>>,
    /// The pass as written, choices and all (for `fmt` and `convert`).
    #[serde(skip)]
    pub source: Option<Source>,
}

impl Choice {
    /// Does this copy serve the chosen options (`variant -> option`)?
    pub fn serves(&self, chosen: &std::collections::BTreeMap<String, String>) -> bool {
        self.arms.iter().all(|(v, opts)| chosen.get(v).is_some_and(|o| opts.contains(o)))
    }

    /// `gbuffer = fat, cube_shadow = classic | multiview`: the arms, as `plan --explain` shows them.
    pub fn describe(&self) -> String {
        let arms: Vec<String> = self.arms.iter().map(|(v, o)| format!("{v} = {}", o.join(" | "))).collect();
        arms.join(", ")
    }
}

/// A syntax tree kept in the IR; equal as data (spans aside).
#[derive(Clone, Debug)]
pub struct Source(pub Node);

impl PartialEq for Source {
    fn eq(&self, other: &Self) -> bool {
        same(&self.0, &other.0)
    }
}
