//! Lowering of `when` conditions.

use super::{Lowerer, Res};
use crate::diag::{suggestion_note, Code, Diagnostic};
use crate::ir::{Condition, Effect, LetDecl, LightKind};
use crate::span::Spanned;
use crate::tree::{Node, Value};

pub const KINDS: [&str; 10] = [
    "Light",
    "Effect",
    "Reflective",
    "Blended",
    "Toggle",
    "Variant",
    "Not",
    "All",
    "Any",
    "Let",
];

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
                ("Let", [name]) => {
                    let name = self.string(name)?;
                    let body = self.named(&name)?;
                    Condition::Named(name, Box::new(body))
                }
                ("All" | "Any", [l]) => {
                    let items = self.list(l)?.to_vec();
                    // Every part lowered, so that each part's problems are said at once.
                    let parts: Vec<_> = items.iter().map(|i| self.condition(i)).collect();
                    let cs = parts.into_iter().collect::<Option<Vec<_>>>()?;
                    if nm == "All" {
                        Condition::All(cs)
                    } else {
                        Condition::Any(cs)
                    }
                }
                (k, _) if KINDS.contains(&k) => {
                    self.err(Diagnostic::error(Code::TypeMismatch, format!("wrong arguments for condition `{k}`"), n.span).with_note(
                        "forms: Light(Point), Effect(Ssr), Reflective, Blended, Toggle(\"param\"), Variant(\"name\", \"option\" or \"a | b\"), Not(c), All([..]), Any([..]), Let(\"name\")",
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

impl Lowerer<'_> {
    /// The condition `let` named `name` declares, lowered where it is used (so that its
    /// problems point at the `let`); unknown names and names that lead back to themselves are
    /// located errors at the use.
    fn named(&mut self, name: &Spanned<String>) -> Res<Spanned<Condition>> {
        let Some(node) = self
            .lets
            .written
            .iter()
            .find(|(n, _)| n.value == name.value)
            .map(|(_, v)| v.clone())
        else {
            let names: Vec<&str> = self.lets.written.iter().map(|(n, _)| n.value.as_str()).collect();
            let d = Diagnostic::error(
                Code::UnknownLet,
                format!("no `let` declares the condition `{}`", name.value),
                name.span,
            )
            .with_note(suggestion_note(&name.value, &names));
            self.err(d);
            return None;
        };
        if let Some(at) = self.lets.open.iter().position(|n| *n == name.value) {
            let mut chain = self.lets.open[at..].to_vec();
            chain.push(name.value.clone());
            let d = Diagnostic::error(
                Code::LetCycle,
                format!("named conditions lead back to themselves: {}", chain.join(" -> ")),
                name.span,
            );
            self.err(d);
            return None;
        }
        if let Some(done) = self.lets.lowered.get(&name.value) {
            return done.clone();
        }
        self.lets.open.push(name.value.clone());
        let body = self.condition(&node);
        self.lets.open.pop();
        self.lets.lowered.insert(name.value.clone(), body.clone());
        body
    }

    /// The declared named conditions (what a printer writes back), each lowered where it was
    /// used or else here; one no condition uses is warned about, at its name.
    pub(super) fn lets_declared(&mut self) -> Vec<LetDecl> {
        let written = self.lets.written.clone();
        let mut out = vec![];
        for (name, _) in &written {
            if !self.lets.lowered.contains_key(&name.value) {
                let d = Diagnostic::warning(Code::UnusedLet, format!("no condition uses `{}`", name.value), name.span);
                self.err(d);
            }
            let value = self.named(name);
            out.extend(value.map(|value| LetDecl { name: name.clone(), value }));
        }
        out
    }
}
