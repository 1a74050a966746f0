//! Lowering of choices inside a pass: `Match(variant: "v", arms: {"a | b": X, "_": Y})`
//! stands for a whole field or for elements of a list field. The pass is lowered once per
//! combination of arms (arms of one variant intersected), each copy running under the
//! options it serves: exactly what writing the copies out by hand with `when` would give.

use super::{Lowerer, Res};
use crate::diag::{suggestion_note, Code, Diagnostic};
use crate::ir::{Choice, Condition, Pass, Source, Variant};
use crate::span::{Span, Spanned};
use crate::tree::{Field, Node, Value};

/// Fields a choice may stand for as a whole.
pub const WHOLE: [&str; 16] = [
    "shader",
    "vertex",
    "fragment",
    "entry",
    "draw",
    "cull",
    "instances",
    "multiview",
    "depth",
    "per_light",
    "param_block",
    "dispatch",
    "repeat",
    "values",
    "constants",
    "bind",
];
/// List fields whose elements a choice may stand for (an arm's list is spliced in).
pub const ELEMENTS: [&str; 4] = ["reads", "writes", "params", "color"];
/// Copies of one pass at most (a product of arms past this is a mistake, not a pipeline).
pub const MAX_COPIES: usize = 256;

/// One arm: the options it serves and its value.
struct Arm {
    options: Vec<String>,
    value: Node,
}

/// A parsed `Match`.
struct Site {
    variant: String,
    arms: Vec<Arm>,
}

/// A copy being built: its fields and, per variant, the options it serves.
#[derive(Clone, Default)]
struct Copy {
    fields: Vec<Field>,
    arms: Vec<(String, Vec<String>)>,
}

impl Copy {
    /// This copy restricted to `options` of `variant`; `None` when nothing is left.
    fn serving(&self, variant: &str, options: &[String]) -> Option<Copy> {
        let mut c = self.clone();
        match c.arms.iter_mut().find(|(v, _)| v == variant) {
            Some((_, have)) => have.retain(|o| options.contains(o)),
            None => c.arms.push((variant.to_string(), options.to_vec())),
        }
        c.arms.iter().all(|(_, o)| !o.is_empty()).then_some(c)
    }
}

pub fn is_match(n: &Node) -> bool {
    matches!(&*n.value, Value::Struct { name: Some((k, _)), .. } if k == "Match")
}

/// The first `Match` inside `n` (itself included).
pub fn find_match(n: &Node) -> Option<&Node> {
    if is_match(n) {
        return Some(n);
    }
    match &*n.value {
        Value::List(items) | Value::Tuple { items, .. } => items.iter().find_map(find_match),
        Value::Map(entries) => entries.iter().find_map(|(k, v)| find_match(k).or_else(|| find_match(v))),
        Value::Struct { fields, .. } => fields.iter().find_map(|f| find_match(&f.2)),
        _ => None,
    }
}

impl Lowerer<'_> {
    /// A pass as written: one IR pass, or one per combination of its choices' arms.
    pub(super) fn pass_with_choices(&mut self, node: &Node, variants: &[Variant], group: u32) -> Vec<Pass> {
        if find_match(node).is_none() {
            return self.pass(node).into_iter().collect();
        }
        let Value::Struct { name, fields } = &*node.value else {
            return self.pass(node).into_iter().collect();
        };
        let Some(copies) = self.copies(fields, variants, node.span) else {
            return vec![];
        };
        let mut out = vec![];
        for c in copies {
            let copy = Node::new(
                Value::Struct {
                    name: name.clone(),
                    fields: c.fields,
                },
                node.span,
            );
            let Some(mut pass) = self.pass(&copy) else { return vec![] };
            let arms = ordered(c.arms, variants);
            let when = pass.when.take();
            pass.when = Some(with_arms(when.clone(), &arms, variants, node.span));
            pass.choice = Some(Choice {
                group,
                arms,
                when,
                source: Some(Source(node.clone())),
            });
            out.push(pass);
        }
        out
    }

    /// Every combination of arms, with the choices replaced by the arms' values.
    fn copies(&mut self, fields: &[Field], variants: &[Variant], span: Span) -> Res<Vec<Copy>> {
        let mut copies = vec![Copy {
            fields: vec![],
            arms: vec![],
        }];
        let mut failed = false;
        for (key, kspan, value) in fields {
            if failed {
                // The copies are lost, but the other choices are still checked: every mistake
                // of the pass is reported at once.
                let _ = self.field_copies(key, value, &Copy::default(), variants);
                continue;
            }
            let mut next = vec![];
            for c in &copies {
                let Some(values) = self.field_copies(key, value, c, variants) else {
                    failed = true;
                    break;
                };
                for (value, c) in values {
                    let mut c = c;
                    c.fields.push((key.clone(), *kspan, value));
                    next.push(c);
                }
            }
            copies = next;
            if copies.len() > MAX_COPIES {
                self.err(
                    Diagnostic::error(
                        Code::LimitExceeded,
                        format!("the pass's choices make more than {MAX_COPIES} copies of it"),
                        span,
                    )
                    .with_note("choose by fewer variants in one pass, or split it into passes"),
                );
                return None;
            }
        }
        (!failed).then_some(copies)
    }

    /// The values one field takes in the copies made from `c` (with what each serves).
    fn field_copies(&mut self, key: &str, value: &Node, c: &Copy, variants: &[Variant]) -> Res<Vec<(Node, Copy)>> {
        if is_match(value) {
            if !WHOLE.contains(&key) && !ELEMENTS.contains(&key) {
                return self.misplaced_choice(key, value);
            }
            let site = self.site(value, variants)?;
            let mut out = vec![];
            for arm in &site.arms {
                let Some(c) = c.serving(&site.variant, &arm.options) else {
                    continue;
                };
                // An arm may choose again (by another variant): its copies, recursively.
                let v = if ELEMENTS.contains(&key) {
                    as_list(&arm.value)
                } else {
                    arm.value.clone()
                };
                out.extend(self.field_copies(key, &v, &c, variants)?);
            }
            return Some(out);
        }
        match (&*value.value, ELEMENTS.contains(&key)) {
            (Value::List(items), true) => self.element_copies(key, items, value.span, c, variants),
            _ => match find_match(value) {
                Some(m) => self.misplaced_choice(key, m),
                None => Some(vec![(value.clone(), c.clone())]),
            },
        }
    }

    /// A list whose elements may be choices: each arm's value spliced in.
    fn element_copies(&mut self, key: &str, items: &[Node], span: Span, c: &Copy, variants: &[Variant]) -> Res<Vec<(Node, Copy)>> {
        let mut partial: Vec<(Vec<Node>, Copy)> = vec![(vec![], c.clone())];
        for item in items {
            if !is_match(item) {
                if let Some(m) = find_match(item) {
                    return self.misplaced_choice(key, m);
                }
                partial.iter_mut().for_each(|(l, _)| l.push(item.clone()));
                continue;
            }
            let site = self.site(item, variants)?;
            let mut next = vec![];
            for (list, c) in &partial {
                for arm in &site.arms {
                    let Some(c) = c.serving(&site.variant, &arm.options) else {
                        continue;
                    };
                    // The arm's elements may choose again: their copies, recursively.
                    for (chosen, c) in self.element_copies(key, &elements(&arm.value), span, &c, variants)? {
                        let mut l = list.clone();
                        l.extend(elements(&chosen));
                        next.push((l, c));
                    }
                }
            }
            partial = next;
        }
        Some(partial.into_iter().map(|(l, c)| (Node::list(l, span), c)).collect())
    }

    fn misplaced_choice<T>(&mut self, key: &str, m: &Node) -> Res<T> {
        let mut d = Diagnostic::error(
            Code::TypeMismatch,
            format!("a choice cannot stand inside a value of `{key}`"),
            m.span,
        )
        .with_label_text("a `Match` here")
        .with_note(format!(
            "a choice stands for a whole pass field ({}) or for elements of {}",
            WHOLE.join(", "),
            ELEMENTS.join(", ")
        ));
        if key == "when" {
            d = d.with_note("`when` takes a condition: `Variant(\"v\", \"a | b\")` holds while option a or b of v is chosen");
        }
        self.err(d);
        None
    }

    /// Parse and check a `Match`: its variant exists, every option is served by exactly one arm.
    fn site(&mut self, node: &Node, variants: &[Variant]) -> Res<Site> {
        // Passes' choices by light kind are gone by now (syntax/light_choices): this one is
        // somewhere else.
        if crate::syntax::light_choices::is_light_choice(node) {
            let msg = "`match light` chooses by the kind of light a pass runs per: it belongs in a pass";
            self.err(Diagnostic::error(Code::LightChoice, msg, node.span));
            return None;
        }
        let mut o = self.obj(node, &["Match"], "choice")?;
        let variant = self.required(&mut o, "variant").and_then(|n| self.string(&n));
        let arms = self.required(&mut o, "arms").and_then(|n| self.string_map(&n));
        self.finish(o, &["variant", "arms"], &[]);
        let (variant, arms) = (variant?, arms?);
        let Some(var) = variants.iter().find(|v| v.name.value == variant.value) else {
            let names: Vec<&str> = variants.iter().map(|v| v.name.value.as_str()).collect();
            self.err(
                Diagnostic::error(
                    Code::UnknownVariant,
                    format!("no variant `{}` to choose by", variant.value),
                    variant.span,
                )
                .with_note(suggestion_note(&variant.value, &names)),
            );
            return None;
        };
        let arms = self.arms(var, arms, node.span)?;
        Some(Site {
            variant: variant.value,
            arms,
        })
    }

    /// The arms' options: named ones checked, `_` taking those no other arm names.
    fn arms(&mut self, var: &Variant, written: Vec<(Spanned<String>, Node)>, span: Span) -> Res<Vec<Arm>> {
        let all = var.option_names();
        let mut seen: Vec<(String, Span)> = vec![];
        let mut arms = vec![];
        let mut default: Option<(Span, Node)> = None;
        let before = self.diags.error_count();
        for (key, value) in written {
            if key.value.trim() == "_" {
                if let Some((first, _)) = &default {
                    self.err(
                        Diagnostic::error(Code::ChoiceOverlap, "two catch-all arms `_`: the second is never chosen", key.span)
                            .with_secondary(*first, "the first `_`"),
                    );
                }
                default = Some((key.span, value));
                continue;
            }
            let mut options = vec![];
            for opt in key.value.split('|').map(str::trim) {
                if let Some((_, first)) = seen.iter().find(|(s, _)| s == opt) {
                    self.err(
                        Diagnostic::error(Code::ChoiceOverlap, format!("option `{opt}` is chosen by two arms"), key.span)
                            .with_secondary(*first, "first chosen here"),
                    );
                } else if !all.contains(&opt) {
                    self.err(
                        Diagnostic::error(
                            Code::UnknownVariantOption,
                            format!("variant `{}` has no option `{opt}`", var.name.value),
                            key.span,
                        )
                        .with_note(suggestion_note(opt, &all)),
                    );
                } else {
                    seen.push((opt.to_string(), key.span));
                    options.push(opt.to_string());
                }
            }
            arms.push(Arm { options, value });
        }
        let rest: Vec<String> = all
            .iter()
            .filter(|o| !seen.iter().any(|(s, _)| s == *o))
            .map(|o| o.to_string())
            .collect();
        match default {
            Some((dspan, _)) if rest.is_empty() => self.diags.push(Diagnostic::warning(
                Code::ChoiceIncomplete,
                format!(
                    "every option of `{}` has its own arm: the default arm `_` serves none",
                    var.name.value
                ),
                dspan,
            )),
            Some((_, value)) => arms.push(Arm { options: rest, value }),
            None if !rest.is_empty() => self.err(
                Diagnostic::error(
                    Code::ChoiceIncomplete,
                    format!("no arm for option{} {} of `{}`", plural(&rest), quoted(&rest), var.name.value),
                    span,
                )
                .with_note("give each option an arm, or a default arm `_`"),
            ),
            None => {}
        }
        (self.diags.error_count() == before).then_some(arms)
    }
}

fn plural(v: &[String]) -> &'static str {
    if v.len() == 1 {
        ""
    } else {
        "s"
    }
}

fn quoted(v: &[String]) -> String {
    v.iter().map(|o| format!("`{o}`")).collect::<Vec<_>>().join(", ")
}

/// An arm's value as list elements: a list's items, or the value itself.
fn elements(n: &Node) -> Vec<Node> {
    match &*n.value {
        Value::List(items) => items.clone(),
        _ => vec![n.clone()],
    }
}

fn as_list(n: &Node) -> Node {
    Node::list(elements(n), n.span)
}

/// Variants in declaration order, each with its options in declaration order.
fn ordered(mut arms: Vec<(String, Vec<String>)>, variants: &[Variant]) -> Vec<(String, Vec<String>)> {
    let pos = |v: &str| variants.iter().position(|x| x.name.value == v).unwrap_or(usize::MAX);
    arms.sort_by_key(|(v, _)| pos(v));
    for (v, opts) in &mut arms {
        let names = variants
            .iter()
            .find(|x| &x.name.value == v)
            .map(|x| x.option_names())
            .unwrap_or_default();
        opts.sort_by_key(|o| names.iter().position(|n| n == o));
    }
    arms
}

/// The copy's condition: the pass's own `when` and, per variant, one of the options it serves.
fn with_arms(when: Option<Spanned<Condition>>, arms: &[(String, Vec<String>)], variants: &[Variant], span: Span) -> Spanned<Condition> {
    let s = |t: &str| Spanned::new(t.to_string(), span);
    let mut all: Vec<Spanned<Condition>> = when.into_iter().collect();
    for (v, opts) in arms {
        let every = variants.iter().find(|x| &x.name.value == v).map_or(0, |x| x.options.len());
        if opts.len() == every {
            continue;
        }
        let one = |o: &String| Spanned::new(Condition::Variant(s(v), s(o)), span);
        all.push(match opts.as_slice() {
            [o] => one(o),
            _ => Spanned::new(Condition::Any(opts.iter().map(one).collect()), span),
        });
    }
    match all.len() {
        1 => all.remove(0),
        _ => Spanned::new(Condition::All(all), span),
    }
}
