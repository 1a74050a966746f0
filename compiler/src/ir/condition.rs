//! `when` conditions: boolean expressions over what the scene calls for and over toggles.

use crate::span::Spanned;
use serde::{Deserialize, Serialize};

/// The kinds of lights a frame's light array holds: the scene's punctual lights, then one
/// `Area` light per emissive mesh (derived from the scene, never written in it), which only
/// passes that list it (`per_light(.., Area)`, e.g. an RSM: its light seen from its centre) see.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum LightKind {
    Directional,
    Spot,
    Point,
    Area,
}

impl LightKind {
    pub const ALL: [LightKind; 4] = [LightKind::Directional, LightKind::Spot, LightKind::Point, LightKind::Area];
    pub const NAMES: [&'static str; 4] = ["Directional", "Spot", "Point", "Area"];
    /// The kinds a scene file's `lights` may hold.
    pub const PUNCTUAL_NAMES: [&'static str; 3] = ["Directional", "Spot", "Point"];
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == s)
    }
    /// Whether lights of this kind are written in scenes (not derived from emissive meshes).
    pub fn punctual(self) -> bool {
        self != LightKind::Area
    }
}

/// Effects a scene can call for; a pass's `when` may depend on them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Effect {
    Shadows,
    AmbientOcclusion,
    MultiViewAo,
    Ssr,
    IndirectDiffuse,
    IndirectSpecular,
    Bloom,
}

impl Effect {
    pub const ALL: [Effect; 7] = [
        Effect::Shadows,
        Effect::AmbientOcclusion,
        Effect::MultiViewAo,
        Effect::Ssr,
        Effect::IndirectDiffuse,
        Effect::IndirectSpecular,
        Effect::Bloom,
    ];
    pub const NAMES: [&'static str; 7] = [
        "Shadows",
        "AmbientOcclusion",
        "MultiViewAo",
        "Ssr",
        "IndirectDiffuse",
        "IndirectSpecular",
        "Bloom",
    ];
    pub fn name(self) -> &'static str {
        Self::NAMES[Self::ALL.iter().position(|e| *e == self).unwrap_or(0)]
    }
    pub fn from_name(s: &str) -> Option<Self> {
        Self::NAMES.iter().position(|n| *n == s).map(|i| Self::ALL[i])
    }
}

/// A named condition: `let NAME = CONDITION` (RON `lets: {"NAME": CONDITION}`), used in any
/// condition by its name (RON `Let("NAME")`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LetDecl {
    pub name: Spanned<String>,
    pub value: Spanned<Condition>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Condition {
    /// At least one light of this kind is in the scene.
    Light(LightKind),
    /// The scene calls for this effect.
    Effect(Effect),
    /// Some material in the scene is reflective (drives SSR and indirect specular).
    Reflective,
    /// Some material in the scene is blended (glTF alphaMode BLEND): passes that composite
    /// blended surfaces beyond the `draw: Transparent` one.
    Blended,
    /// A bool parameter's value.
    Toggle(Spanned<String>),
    /// A variant has this option chosen.
    Variant(Spanned<String>, Spanned<String>),
    Not(Box<Spanned<Condition>>),
    All(Vec<Spanned<Condition>>),
    Any(Vec<Spanned<Condition>>),
    /// A named condition (`let NAME = …`) where it is used: the name as written at the use,
    /// and the condition it names (which decides; the name is kept for printing).
    Named(Spanned<String>, Box<Spanned<Condition>>),
}

impl Condition {
    /// Compact text used in plans and explanations: `All(Effect(Ssr), Not(Reflective))`.
    pub fn describe(&self) -> String {
        match self {
            Condition::Light(k) => format!("Light({})", k.name()),
            Condition::Effect(e) => format!("Effect({})", e.name()),
            Condition::Reflective => "Reflective".into(),
            Condition::Blended => "Blended".into(),
            Condition::Toggle(p) => format!("Toggle({:?})", p.value),
            Condition::Variant(v, o) => format!("Variant({:?}, {:?})", v.value, o.value),
            Condition::Not(c) => format!("Not({})", c.describe()),
            Condition::All(cs) => format!("All({})", cs.iter().map(|c| c.describe()).collect::<Vec<_>>().join(", ")),
            Condition::Any(cs) => format!("Any({})", cs.iter().map(|c| c.describe()).collect::<Vec<_>>().join(", ")),
            Condition::Named(_, c) => c.describe(),
        }
    }

    /// The condition that decides: a named one's body (through names naming names).
    pub fn decided(&self) -> &Condition {
        match self {
            Condition::Named(_, c) => c.value.decided(),
            c => c,
        }
    }

    /// The effects the expression asks for (not those under `Not`, which a pass runs
    /// without), in order, each once.
    pub fn effects(&self) -> Vec<Effect> {
        let mut out = vec![];
        self.collect_effects(&mut out);
        out
    }

    fn collect_effects(&self, out: &mut Vec<Effect>) {
        match self {
            Condition::Effect(e) if !out.contains(e) => out.push(*e),
            Condition::All(cs) | Condition::Any(cs) => cs.iter().for_each(|c| c.collect_effects(out)),
            Condition::Named(_, c) => c.collect_effects(out),
            _ => {}
        }
    }

    /// Does the value depend on the effects or materials a scene calls for?
    pub fn mentions_scene_effects(&self) -> bool {
        match self {
            Condition::Effect(_) | Condition::Reflective | Condition::Blended => true,
            Condition::Not(c) | Condition::Named(_, c) => c.mentions_scene_effects(),
            Condition::All(cs) | Condition::Any(cs) => cs.iter().any(|c| c.mentions_scene_effects()),
            _ => false,
        }
    }

    /// Does a variant atom occur in the expression (used to tell "variant not chosen" from
    /// "condition false")?
    pub fn mentions_variant(&self) -> bool {
        !self.variants().is_empty()
    }

    /// The variants the expression names, under `Not` too.
    pub fn variants(&self) -> std::collections::BTreeSet<&str> {
        let mut out = std::collections::BTreeSet::new();
        self.collect_variants(&mut out);
        out
    }

    fn collect_variants<'a>(&'a self, out: &mut std::collections::BTreeSet<&'a str>) {
        match self {
            Condition::Variant(v, _) => _ = out.insert(v.value.as_str()),
            Condition::Not(c) | Condition::Named(_, c) => c.collect_variants(out),
            Condition::All(cs) | Condition::Any(cs) => cs.iter().for_each(|c| c.collect_variants(out)),
            _ => {}
        }
    }
}

impl Condition {
    /// Features every configuration where this condition holds has: those the variant options
    /// it requires need (an option is only chosen where the profile has what it requires).
    pub fn implied_features(&self, p: &super::Pipeline) -> std::collections::BTreeSet<crate::profile::Feature> {
        match self {
            Condition::Variant(v, o) => p
                .variant(&v.value)
                .and_then(|var| var.option(&o.value))
                .map(|opt| opt.requires.iter().map(|f| f.value).collect())
                .unwrap_or_default(),
            Condition::All(cs) => cs.iter().flat_map(|c| c.value.implied_features(p)).collect(),
            Condition::Any(cs) => {
                let mut sets = cs.iter().map(|c| c.value.implied_features(p));
                let first = sets.next().unwrap_or_default();
                sets.fold(first, |acc, s| acc.intersection(&s).copied().collect())
            }
            Condition::Named(_, c) => c.value.implied_features(p),
            _ => Default::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::span::{Span, Spanned};

    /// A pass runs without the effects under `Not`: only the others are asked for.
    #[test]
    fn effects_are_those_asked_for() {
        let at = |c: Condition| Spanned::new(c, Span::default());
        let c = Condition::All(vec![
            at(Condition::Not(Box::new(at(Condition::Effect(Effect::Bloom))))),
            at(Condition::Any(vec![at(Condition::Effect(Effect::Ssr)), at(Condition::Reflective)])),
            at(Condition::Effect(Effect::Ssr)),
        ]);
        assert_eq!(c.effects(), vec![Effect::Ssr]);
    }
}
