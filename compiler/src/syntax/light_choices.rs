//! Stage `light_choices`: a pass that runs per light and says `match light { Directional |
//! Spot: A, Point: B }` for a field or a list element (RON `Match(light: {"Directional | Spot":
//! A, "Point": B})`) becomes one pass per group of light kinds its choices tell apart, named
//! `NAME_KINDS` — `light` with those arms gives `light_directional_spot` and `light_point` —
//! each running per light of its kinds, with each choice's arm for them. One pass per lighting
//! model in the file, the passes a shader needs per light kind in the Plan. Runs on each file's
//! tree after its groups, before composition and the one lowering, so both front ends share it
//! and what the user wrote keeps its span.

use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::ir::LightKind;
use crate::span::Span;
use crate::tree::{Field, Node, Value};

/// Is `n` a choice by light kind (`Match(light: {...})`)?
pub fn is_light_choice(n: &Node) -> bool {
    matches!(&*n.value, Value::Struct { name: Some((k, _)), fields } if k == "Match" && fields.iter().any(|f| f.0 == "light"))
}

/// Does the tree hold a choice by light kind anywhere (then `fmt` and `convert` print it as
/// written)?
pub fn has_light_choices(n: &Node) -> bool {
    if is_light_choice(n) {
        return true;
    }
    let mut found = false;
    n.each_child(|c| found = found || has_light_choices(c));
    found
}

/// The tree with every pass that chooses by light kind split into its passes, in place.
pub fn expand(root: &Node, diags: &mut Diagnostics) -> Node {
    // Only passes choose by light kind (the declarations need no walk).
    let Value::Struct { fields, .. } = &*root.value else {
        return root.clone();
    };
    if !fields.iter().any(|f| f.0 == "passes" && has_light_choices(&f.2)) {
        return root.clone();
    }
    super::with_passes(root, |items| items.iter().flat_map(|p| split(p, diags)).collect())
}

/// One choice's arms: for each light kind of the pass, which arm serves it.
struct Arms<'a> {
    values: Vec<&'a Node>,
    of_kind: Vec<usize>,
}

/// A pass as the passes its light choices make (itself when it has none; none when a choice
/// is wrong, which is reported).
fn split(pass: &Node, diags: &mut Diagnostics) -> Vec<Node> {
    let mut choices = vec![];
    collect(pass, &mut choices);
    if choices.is_empty() {
        return vec![pass.clone()];
    }
    let Value::Struct { fields, .. } = &*pass.value else {
        return vec![pass.clone()];
    };
    let Some(kinds) = per_light_kinds(fields) else {
        let d = Diagnostic::error(
            Code::LightChoice,
            "`match light` chooses by the kind of light a pass repeats over, and this pass has no `per_light` list",
            choices[0].span,
        )
        .with_note("give the pass `per_light(Directional, Spot, Point)` (the kinds it runs for)");
        diags.push(d);
        return vec![];
    };
    let before = diags.error_count();
    let arms: Vec<Arms> = choices.iter().filter_map(|c| arms(c, &kinds, diags)).collect();
    if diags.error_count() > before {
        return vec![];
    }
    let parts = partition(&kinds, &arms);
    if parts.len() == 1 {
        return vec![chosen(pass, &parts[0], &kinds, &choices, &arms, None)];
    }
    let base = fields.iter().find(|f| f.0 == "name").and_then(|f| f.2.text()).unwrap_or("");
    parts
        .iter()
        .map(|part| {
            let suffix: Vec<String> = part.iter().map(|&k| kinds[k].0.to_lowercase()).collect();
            chosen(pass, part, &kinds, &choices, &arms, Some(format!("{base}_{}", suffix.join("_"))))
        })
        .collect()
}

/// Every choice by light kind in `n`, outermost first (one inside another's arm is found when
/// that arm is chosen).
fn collect<'a>(n: &'a Node, out: &mut Vec<&'a Node>) {
    if is_light_choice(n) {
        out.push(n);
    }
    // A choice in an arm is another choice (its arm is picked once that arm is).
    n.each_child(|c| collect(c, out));
}

/// The pass's `per_light` kinds with their nodes, if it lists them.
fn per_light_kinds(fields: &[Field]) -> Option<Vec<(String, Node)>> {
    let v = &fields.iter().find(|f| f.0 == "per_light")?.2;
    let Value::List(items) = &*v.value else { return None };
    items.iter().map(|i| Some((i.text()?.to_string(), i.clone()))).collect()
}

/// A choice's arms, checked: every kind named is a light kind the pass runs for, served once;
/// `_` serves the kinds no other arm names.
fn arms<'a>(choice: &'a Node, kinds: &[(String, Node)], diags: &mut Diagnostics) -> Option<Arms<'a>> {
    let Value::Struct { fields, .. } = &*choice.value else {
        return None;
    };
    let written = fields.iter().find(|f| f.0 == "light").map(|f| &f.2)?;
    let Value::Map(entries) = &*written.value else {
        diags.push(Diagnostic::error(
            Code::TypeMismatch,
            format!(
                "`Match(light: ...)` takes a map of light kinds to values, found {}",
                written.value.kind_word()
            ),
            written.span,
        ));
        return None;
    };
    let mut of_kind: Vec<Option<usize>> = vec![None; kinds.len()];
    let mut default = None;
    let mut values = vec![];
    for (key, value) in entries {
        let at = values.len();
        values.push(value);
        let text = key.text().unwrap_or("");
        if text.trim() == "_" {
            if default.replace(at).is_some() {
                let msg = "two catch-all arms `_`: the second is never chosen";
                diags.push(Diagnostic::error(Code::ChoiceOverlap, msg, key.span));
            }
            continue;
        }
        for kind in text.split('|').map(str::trim) {
            let Some(k) = kinds.iter().position(|(name, _)| name == kind) else {
                diags.push(unknown_kind(kind, kinds, key.span));
                continue;
            };
            if of_kind[k].replace(at).is_some() {
                let msg = format!("{kind} lights are served by two arms: the second is never chosen");
                diags.push(Diagnostic::error(Code::ChoiceOverlap, msg, key.span));
            }
        }
    }
    let missing: Vec<&str> = kinds
        .iter()
        .zip(&of_kind)
        .filter(|(_, a)| a.is_none())
        .map(|((k, _), _)| k.as_str())
        .collect();
    if default.is_none() && !missing.is_empty() {
        let d = Diagnostic::error(
            Code::ChoiceIncomplete,
            format!("no arm for {} lights", missing.join(", ")),
            choice.span,
        )
        .with_note("give each light kind of the pass's `per_light` an arm, or a default arm `_`");
        diags.push(d);
        return None;
    }
    let of_kind = of_kind.into_iter().map(|a| a.or(default).unwrap_or(0)).collect();
    Some(Arms { values, of_kind })
}

/// An arm's key that names no light kind the pass runs for.
fn unknown_kind(kind: &str, kinds: &[(String, Node)], at: Span) -> Diagnostic {
    if LightKind::NAMES.contains(&kind) {
        let runs: Vec<&str> = kinds.iter().map(|(k, _)| k.as_str()).collect();
        return Diagnostic::error(
            Code::LightChoice,
            format!("this pass does not run per {kind} light: its `per_light` lists {}", runs.join(", ")),
            at,
        );
    }
    Diagnostic::error(Code::UnknownValue, format!("unknown light kind `{kind}`"), at).with_note(suggestion_note(kind, &LightKind::NAMES))
}

/// The pass's kinds (indices, in `per_light` order) in groups that every choice serves with
/// one arm each, in the order of each group's first kind.
fn partition(kinds: &[(String, Node)], arms: &[Arms]) -> Vec<Vec<usize>> {
    let mut parts: Vec<Vec<usize>> = vec![];
    for k in 0..kinds.len() {
        let same = |p: &Vec<usize>| arms.iter().all(|a| a.of_kind[p[0]] == a.of_kind[k]);
        match parts.iter_mut().find(|p| same(p)) {
            Some(p) => p.push(k),
            None => parts.push(vec![k]),
        }
    }
    parts
}

/// The pass for the kinds of `part`: each choice replaced by its arm for them (an arm of
/// several list elements spliced into its list), `per_light` listing only them, renamed.
fn chosen(pass: &Node, part: &[usize], kinds: &[(String, Node)], choices: &[&Node], arms: &[Arms], name: Option<String>) -> Node {
    let pick = |c: &Node| -> Option<Node> {
        let i = choices.iter().position(|x| std::sync::Arc::ptr_eq(&x.value, &c.value))?;
        Some(arms[i].values[arms[i].of_kind[part[0]]].clone())
    };
    let Value::Struct { name: kind, fields } = &*pass.value else {
        return pass.clone();
    };
    let fields = fields
        .iter()
        .map(|(k, span, v)| {
            let v = match k.as_str() {
                "name" => name.as_ref().map_or(v.clone(), |n| Node::str(n.clone(), v.span)),
                "per_light" => Node::list(part.iter().map(|&i| kinds[i].1.clone()).collect(), v.span),
                _ => substitute(v, &pick),
            };
            (k.clone(), *span, v)
        })
        .collect();
    Node::new(
        Value::Struct {
            name: kind.clone(),
            fields,
        },
        pass.span,
    )
}

/// `n` with every choice by light kind replaced by the arm `pick` gives (and that arm's own
/// choices replaced in turn).
fn substitute(n: &Node, pick: &dyn Fn(&Node) -> Option<Node>) -> Node {
    if is_light_choice(n) {
        return match pick(n) {
            Some(arm) => substitute(&arm, pick),
            None => n.clone(),
        };
    }
    let value = match &*n.value {
        Value::List(items) => {
            let mut out = vec![];
            for item in items {
                let was_choice = is_light_choice(item);
                let v = substitute(item, pick);
                match (&*v.value, was_choice) {
                    // An arm of several elements stands for them all.
                    (Value::List(several), true) => out.extend(several.iter().cloned()),
                    _ => out.push(v),
                }
            }
            Value::List(out)
        }
        Value::Map(entries) => Value::Map(entries.iter().map(|(k, v)| (k.clone(), substitute(v, pick))).collect()),
        Value::Struct { name, fields } => Value::Struct {
            name: name.clone(),
            fields: fields.iter().map(|(k, s, v)| (k.clone(), *s, substitute(v, pick))).collect(),
        },
        Value::Tuple { name, items } => Value::Tuple {
            name: name.clone(),
            items: items.iter().map(|i| substitute(i, pick)).collect(),
        },
        _ => return n.clone(),
    };
    Node::new(value, n.span)
}
