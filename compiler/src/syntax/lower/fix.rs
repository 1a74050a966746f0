//! Fixed variants (`fix: {"gbuffer": "packed"}`, LBP `fix gbuffer = packed`): a variant of a
//! used pipeline pinned at one option and removed. Every condition, choice and constant that
//! names it is decided as if that option were chosen; passes that could then never run go.

use super::Lowerer;
use crate::diag::{suggestion_note, Code, Diagnostic};
use crate::ir::{Condition, Constant, Pipeline};
use crate::span::Spanned;

/// A condition with one variant decided.
enum Decided {
    True,
    False,
    Open(Spanned<Condition>),
}

fn decide(c: &Spanned<Condition>, v: &str, o: &str) -> Decided {
    let span = c.span;
    match &c.value {
        Condition::Variant(x, y) if x.value == v => {
            if y.value == o {
                Decided::True
            } else {
                Decided::False
            }
        }
        // Fixing decides the named condition itself (its name is for printing the file as
        // written, which a fixed pipeline keeps apart).
        Condition::Named(_, inner) => decide(inner, v, o),
        Condition::Not(inner) => match decide(inner, v, o) {
            Decided::True => Decided::False,
            Decided::False => Decided::True,
            Decided::Open(i) => Decided::Open(Spanned::new(Condition::Not(Box::new(i)), span)),
        },
        Condition::All(cs) | Condition::Any(cs) => {
            let all = matches!(c.value, Condition::All(_));
            // In All, a false part decides it; in Any, a true one.
            let (decisive, neutral) = if all { (false, true) } else { (true, false) };
            let mut open = vec![];
            for part in cs {
                match decide(part, v, o) {
                    Decided::True if decisive => return Decided::True,
                    Decided::False if !decisive => return Decided::False,
                    Decided::Open(p) => open.push(p),
                    _ => {}
                }
            }
            match open.len() {
                0 if neutral => Decided::True,
                0 => Decided::False,
                1 => Decided::Open(open.remove(0)),
                _ => Decided::Open(Spanned::new(if all { Condition::All(open) } else { Condition::Any(open) }, span)),
            }
        }
        _ => Decided::Open(c.clone()),
    }
}

/// `Some(new condition)` (`None` inside: always true), or `None` when it can never hold.
fn decided(c: Option<Spanned<Condition>>, v: &str, o: &str) -> Option<Option<Spanned<Condition>>> {
    match c.map(|c| decide(&c, v, o)) {
        None | Some(Decided::True) => Some(None),
        Some(Decided::False) => None,
        Some(Decided::Open(c)) => Some(Some(c)),
    }
}

impl Lowerer<'_> {
    /// Pin each fixed variant (checked: it exists, and so does the option, which may not
    /// need features, set parameters or substitute shaders — there is no choosing left).
    pub(super) fn fix(&mut self, p: &mut Pipeline, fixes: Vec<(Spanned<String>, Spanned<String>)>) {
        for (v, o) in fixes {
            let Some(i) = p.variants.iter().position(|x| x.name.value == v.value) else {
                let names: Vec<&str> = p.variants.iter().map(|x| x.name.value.as_str()).collect();
                self.err(
                    Diagnostic::error(Code::UnknownVariant, format!("no variant `{}` to fix", v.value), v.span)
                        .with_note(suggestion_note(&v.value, &names)),
                );
                continue;
            };
            let var = &p.variants[i];
            let Some(opt) = var.option(&o.value) else {
                self.err(
                    Diagnostic::error(
                        Code::UnknownVariantOption,
                        format!("variant `{}` has no option `{}`", v.value, o.value),
                        o.span,
                    )
                    .with_note(suggestion_note(&o.value, &var.option_names())),
                );
                continue;
            };
            if !opt.requires.is_empty() || !opt.limits.is_empty() || !opt.params.is_empty() || !opt.shaders.is_empty() || opt.jitter {
                self.err(
                    Diagnostic::error(
                        Code::VariantUnsupported,
                        format!("option `{}` of `{}` cannot be fixed: it needs features or limits, sets parameters, substitutes shaders or jitters", o.value, v.value),
                        o.span,
                    )
                    .with_secondary(opt.name.span, "the option")
                    .with_note("fix a variant at an option that only chooses passes and fields"),
                );
                continue;
            }
            p.variants.remove(i);
            pin(p, &v.value, &o.value);
        }
    }
}

/// Decide `v = o` everywhere: conditions, choices' arms, constants; drop what cannot run.
fn pin(p: &mut Pipeline, v: &str, o: &str) {
    let passes = std::mem::take(&mut p.passes);
    for mut pass in passes {
        let Some(when) = decided(pass.when.take(), v, o) else { continue };
        pass.when = when;
        if let Some(c) = &mut pass.choice {
            if let Some(k) = c.arms.iter().position(|(x, _)| x == v) {
                if !c.arms[k].1.iter().any(|x| x == o) {
                    continue;
                }
                c.arms.remove(k);
            }
            match decided(c.when.take(), v, o) {
                Some(w) => c.when = w,
                None => continue,
            }
        }
        for (_, c) in &mut pass.constants {
            if let Constant::Variant(x, y) = &c.value {
                if x == v {
                    c.value = Constant::Bool(y == o);
                }
            }
        }
        p.passes.push(pass);
    }
}
