//! What a scene calls for, as far as the compiler cares: light kinds and counts, effects,
//! reflective materials, output size. Read from a scene file (RON) for culling.

use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::front::ron::parse as value;
use crate::ir::{Effect, LightKind};
use crate::span::SourceMap;
use crate::syntax::tree::Value;
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneFeatures {
    pub name: String,
    /// Lights that are on, by kind.
    pub lights: BTreeMap<LightKind, u32>,
    pub effects: BTreeSet<Effect>,
    pub reflective: bool,
    pub size: (u32, u32),
}

impl SceneFeatures {
    /// Used when no scene is given: every light kind once, every effect, reflective
    /// materials; so that nothing is culled for lack of scene content.
    pub fn everything() -> Self {
        SceneFeatures {
            name: "<all features>".into(),
            lights: LightKind::ALL.into_iter().map(|k| (k, 1)).collect(),
            effects: Effect::ALL.into_iter().collect(),
            reflective: true,
            size: (1280, 720),
        }
    }

    pub fn light_count(&self, kinds: &[LightKind]) -> u32 {
        kinds.iter().map(|k| self.lights.get(k).copied().unwrap_or(0)).sum()
    }
}

/// Read the features of a scene file. Keys the compiler does not need (camera, models'
/// transforms...) belong to the runtime's scene schema and are not checked here.
pub fn load_scene_features(path: &str, sources: &mut SourceMap, diags: &mut Diagnostics) -> Option<SceneFeatures> {
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) => {
            diags.push(Diagnostic::unlocated(
                crate::diag::Severity::Error,
                Code::FileNotFound,
                format!("cannot read scene `{path}`: {e}"),
            ));
            return None;
        }
    };
    let file = sources.add(path, text.clone());
    let root = match value::parse(file, &text) {
        Ok(n) => n,
        Err(d) => {
            diags.push(d);
            return None;
        }
    };
    let Value::Struct { name, fields } = &*root.value else {
        diags.push(Diagnostic::error(Code::TypeMismatch, "expected `Scene(...)`", root.span));
        return None;
    };
    if name.as_ref().is_some_and(|(n, _)| n != "Scene") {
        diags.push(Diagnostic::error(Code::TypeMismatch, "expected `Scene(...)`", root.span));
        return None;
    }
    let before = diags.error_count();
    let mut sf = SceneFeatures {
        name: std::path::Path::new(path)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or(path)
            .to_string(),
        lights: BTreeMap::new(),
        effects: BTreeSet::new(),
        reflective: false,
        size: (1280, 720),
    };
    let field = |k: &str| fields.iter().find(|f| f.0 == k).map(|f| &f.2);
    if let Some(Value::Str(s)) = field("name").map(|n| &*n.value) {
        sf.name = s.clone();
    }
    if let Some(n) = field("size") {
        match &*n.value {
            Value::Tuple { items, .. } if items.len() == 2 => match (&*items[0].value, &*items[1].value) {
                (Value::Int(w), Value::Int(h)) if *w > 0 && *h > 0 && *w <= 65536 && *h <= 65536 => sf.size = (*w as u32, *h as u32),
                _ => diags.push(Diagnostic::error(
                    Code::ValueOutOfRange,
                    "scene size must be two positive integers",
                    n.span,
                )),
            },
            _ => diags.push(Diagnostic::error(Code::TypeMismatch, "expected `size: (width, height)`", n.span)),
        }
    }
    if let Some(n) = field("lights") {
        match &*n.value {
            Value::List(items) => {
                for it in items {
                    let (kind_name, kspan, lfields) = match &*it.value {
                        Value::Struct {
                            name: Some((k, s)),
                            fields,
                        } => (k.clone(), *s, fields.clone()),
                        Value::Tuple { name: Some((k, s)), items } if items.is_empty() => (k.clone(), *s, vec![]),
                        _ => {
                            diags.push(Diagnostic::error(
                                Code::TypeMismatch,
                                "expected a light such as `Point(...)`",
                                it.span,
                            ));
                            continue;
                        }
                    };
                    let Some(kind) = LightKind::from_name(&kind_name) else {
                        diags.push(
                            Diagnostic::error(Code::UnknownKind, format!("unknown light kind `{kind_name}`"), kspan)
                                .with_note(suggestion_note(&kind_name, &LightKind::NAMES)),
                        );
                        continue;
                    };
                    let on = lfields
                        .iter()
                        .find(|f| f.0 == "on")
                        .map(|f| !matches!(*f.2.value, Value::Bool(false)))
                        .unwrap_or(true);
                    if on {
                        *sf.lights.entry(kind).or_insert(0) += 1;
                    }
                }
            }
            _ => diags.push(Diagnostic::error(Code::TypeMismatch, "expected a list of lights", n.span)),
        }
    }
    if let Some(n) = field("effects") {
        match &*n.value {
            Value::List(items) => {
                for it in items {
                    match &*it.value {
                        Value::Ident(e) => match Effect::from_name(e) {
                            Some(e) => {
                                sf.effects.insert(e);
                            }
                            None => diags.push(
                                Diagnostic::error(Code::UnknownEffect, format!("unknown effect `{e}`"), it.span)
                                    .with_note(suggestion_note(e, &Effect::NAMES)),
                            ),
                        },
                        _ => diags.push(Diagnostic::error(Code::TypeMismatch, "expected an effect name", it.span)),
                    }
                }
            }
            _ => diags.push(Diagnostic::error(Code::TypeMismatch, "expected a list of effects", n.span)),
        }
    }
    if let Some(n) = field("models") {
        if let Value::List(items) = &*n.value {
            for it in items {
                if let Value::Struct { fields, .. } = &*it.value {
                    if fields
                        .iter()
                        .any(|f| f.0 == "reflective" && matches!(*f.2.value, Value::Bool(true)))
                    {
                        sf.reflective = true;
                    }
                }
            }
        }
    }
    if let Some(Value::Bool(b)) = field("reflective").map(|n| &*n.value) {
        sf.reflective |= *b;
    }
    (diags.error_count() == before).then_some(sf)
}
