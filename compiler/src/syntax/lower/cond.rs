//! Lowering of `when` conditions.

use super::{Lowerer, Res};
use crate::diag::{suggestion_note, Code, Diagnostic};
use crate::ir::{Condition, Effect, LightKind};
use crate::span::Spanned;
use crate::tree::{Node, Value};

pub const KINDS: [&str; 9] = ["Light", "Effect", "Reflective", "Blended", "Toggle", "Variant", "Not", "All", "Any"];

impl Lowerer<'_> {
    pub(super) fn condition(&mut self, n: &Node) -> Res<Spanned<Condition>> {
        let c = match &*n.value {
            Value::Ident(i) if i == "Reflective" => Condition::Reflective,
            Value::Ident(i) if i == "Blended" => Condition::Blended,
            Value::Tuple {
                name: Some((nm, nspan)),
                items,
            } => match (nm.as_str(), items.as_slice()) {
                ("Light", [k]) => Condition::Light(self.ident(k, "light kind", &LightKind::NAMES, LightKind::from_name)?),
                ("Effect", [e]) => Condition::Effect(self.effect(e)?),
                ("Toggle", [p]) => Condition::Toggle(self.string(p)?),
                ("Variant", [v, o]) => variant_options(self.string(v)?, self.string(o)?),
                ("Not", [c]) => Condition::Not(Box::new(self.condition(c)?)),
                ("All" | "Any", [l]) => {
                    let items = self.list(l)?.to_vec();
                    let cs = items.iter().map(|i| self.condition(i)).collect::<Option<Vec<_>>>()?;
                    if nm == "All" {
                        Condition::All(cs)
                    } else {
                        Condition::Any(cs)
                    }
                }
                (k, _) if KINDS.contains(&k) => {
                    self.err(Diagnostic::error(Code::TypeMismatch, format!("wrong arguments for condition `{k}`"), n.span).with_note(
                        "forms: Light(Point), Effect(Ssr), Reflective, Blended, Toggle(\"param\"), Variant(\"name\", \"option\" or \"a | b\"), Not(c), All([..]), Any([..])",
                    ));
                    return None;
                }
                (k, _) => {
                    self.err(
                        Diagnostic::error(Code::UnknownKind, format!("unknown condition `{k}`"), *nspan)
                            .with_note(suggestion_note(k, &KINDS)),
                    );
                    return None;
                }
            },
            _ => return self.type_err("a condition such as `Effect(Ssr)`", n),
        };
        Some(Spanned::new(c, n.span))
    }
}

/// `Variant("v", "a | b")`: true while any of the options is chosen (as a choice's arm names
/// them); one option is the plain condition. Each option keeps the written text's span.
fn variant_options(v: Spanned<String>, o: Spanned<String>) -> Condition {
    let options: Vec<&str> = o.value.split('|').map(str::trim).collect();
    match options.as_slice() {
        [one] => Condition::Variant(v, Spanned::new(one.to_string(), o.span)),
        many => Condition::Any(
            many.iter()
                .map(|opt| Spanned::new(Condition::Variant(v.clone(), Spanned::new(opt.to_string(), o.span)), o.span))
                .collect(),
        ),
    }
}

impl Lowerer<'_> {
    fn effect(&mut self, e: &Node) -> Res<Effect> {
        let Value::Ident(i) = &*e.value else {
            return self.type_err("an effect name", e);
        };
        match Effect::from_name(i) {
            Some(x) => Some(x),
            None => {
                self.err(
                    Diagnostic::error(Code::UnknownEffect, format!("unknown effect `{i}`"), e.span)
                        .with_note(suggestion_note(i, &Effect::NAMES)),
                );
                None
            }
        }
    }
}
