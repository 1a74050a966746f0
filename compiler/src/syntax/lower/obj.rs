//! A struct of the tree, taken key by key: absent keys come from the defaults table and
//! `finish` reports whatever was not taken (unknown, misplaced or repeated keys).

use super::{Lowerer, Res};
use crate::diag::{geometry_shader, suggestion_note, Code, Diagnostic};
use crate::span::Span;
use crate::syntax::defaults;
use crate::tree::{Field, Node, Value};

pub(crate) struct Obj {
    /// The item's kind as the tree names it (`Texture`, `Raster`...): the defaults' owner.
    pub kind: String,
    /// How messages name the item: "pipeline", "pass `gbuffer`".
    pub what: String,
    pub span: Span,
    /// Where a missing key is reported: the item's name in the tree.
    pub head: Span,
    fields: Vec<(Field, bool)>,
}

impl Obj {
    /// The value of `key`, taken once.
    pub fn take(&mut self, key: &str) -> Option<Node> {
        self.fields.iter_mut().find(|(f, used)| f.0 == key && !*used).map(|(f, used)| {
            *used = true;
            f.2.clone()
        })
    }

    /// The value of `key`, or its default from the table.
    pub fn get(&mut self, key: &str) -> Option<Node> {
        self.take(key).or_else(|| defaults::get(&self.kind, key).map(|d| d.node(self.span)))
    }

    /// Every key written, with where it was written.
    pub fn given(&self) -> impl Iterator<Item = (String, Span)> + '_ {
        self.fields.iter().map(|(f, _)| (f.0.clone(), f.1))
    }

    /// Where the item and each of its keys were written (the first of repeated keys).
    pub fn key_spans(&self) -> crate::ir::scene::KeySpans {
        let mut keys = std::collections::BTreeMap::new();
        for (k, span) in self.given() {
            keys.entry(k).or_insert(span);
        }
        crate::ir::scene::KeySpans { span: self.span, keys }
    }

    pub fn has(&self, key: &str) -> bool {
        self.fields.iter().any(|(f, _)| f.0 == key)
    }

    fn taken(&self, key: &str) -> bool {
        self.fields.iter().any(|(f, used)| f.0 == key && *used)
    }
}

impl Lowerer<'_> {
    /// Open `Name(...)` (or an anonymous `(...)`, taken as the first expected name) as an object.
    pub(super) fn obj(&mut self, node: &Node, expected: &[&str], what: &str) -> Res<Obj> {
        let (name, fields) = match &*node.value {
            Value::Struct { name, fields } => (name.clone(), fields.clone()),
            Value::Tuple { name, items } if items.is_empty() => (name.clone(), vec![]),
            Value::Ident(i) if expected.contains(&i.as_str()) => (Some((i.clone(), node.span)), vec![]),
            // The old form `Point((key: value))`: one pair of parentheses too many.
            Value::Tuple { name: Some((n, _)), items }
                if items.len() == 1 && expected.contains(&n.as_str()) && matches!(&*items[0].value, Value::Struct { name: None, .. }) =>
            {
                self.err(Diagnostic::error(
                    Code::TypeMismatch,
                    format!("`{n}((...))` has one pair of parentheses too many: write `{n}(key: value, ...)`"),
                    node.span,
                ));
                return None;
            }
            _ => return self.type_err(&format!("{what} `{}(...)`", expected.first().unwrap_or(&"")), node),
        };
        let (kind, head) = match name {
            Some((n, nspan)) if !expected.is_empty() && !expected.contains(&n.as_str()) => {
                self.err(
                    Diagnostic::error(Code::UnknownKind, format!("unknown {what} kind `{n}`"), nspan)
                        .with_note(suggestion_note(&n, expected)),
                );
                return None;
            }
            Some((n, nspan)) => (n, nspan),
            None => (expected.first().copied().unwrap_or("").to_string(), node.span),
        };
        Some(Obj {
            kind,
            what: what.to_string(),
            span: node.span,
            head,
            fields: fields.into_iter().map(|f| (f, false)).collect(),
        })
    }

    pub(super) fn required(&mut self, obj: &mut Obj, key: &str) -> Res<Node> {
        let r = obj.take(key);
        if r.is_none() {
            self.err(
                Diagnostic::error(Code::MissingKey, format!("{} is missing required key `{key}`", obj.what), obj.head)
                    .with_label_text(format!("`{key}` is required here")),
            );
        }
        r
    }

    /// Report every key not taken: repeated (`duplicate-key`), belonging to another kind of
    /// item (`misplaced`, `elsewhere` lists those keys) or unknown (with a suggestion).
    pub(super) fn finish(&mut self, obj: Obj, allowed: &[&str], elsewhere: &[&str]) {
        for ((k, kspan, _), used) in &obj.fields {
            if *used {
                continue;
            }
            let d = if obj.taken(k) {
                Diagnostic::error(Code::DuplicateKey, format!("`{k}` is given twice in {}", obj.what), *kspan)
            } else if allowed.contains(&k.as_str()) {
                continue; // taken only in some forms of the item
            } else if matches!(k.as_str(), "geometry" | "geometry_shader" | "gs") {
                geometry_shader(*kspan)
            } else if elsewhere.contains(&k.as_str()) {
                Diagnostic::error(Code::Misplaced, misplaced(k, &obj.kind), *kspan)
            } else {
                Diagnostic::error(Code::UnknownKey, format!("unknown key `{k}` in {}", obj.what), *kspan)
                    .with_note(suggestion_note(k, allowed))
            };
            self.err(d);
        }
    }
}

/// "`cull` is not a property of compute passes", "`compare` does not apply to a color target".
fn misplaced(key: &str, kind: &str) -> String {
    match kind {
        "Target" => format!("`{key}` does not apply to a color target"),
        "Depth" => format!("`{key}` does not apply to a depth target"),
        k => format!("`{key}` is not a property of {} passes", k.to_lowercase()),
    }
}
