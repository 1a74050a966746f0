//! Composition: a pipeline that `use`s another is that pipeline's tree with this file's
//! items merged in, by name — added, `Replace(..)`d (LBP `replace`), removed (`remove`), a
//! pass placed `after` another — before the one lowering. Conflicts are located errors. The
//! used file's variants can be fixed (`fix`): the lowering pins them (`lower::fix`).

use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::span::Span;
use crate::tree::{Field, Node, Value};
use std::collections::HashMap;

/// Keys only a pipeline that uses another may have (besides `use`), with what they do.
const COMPOSING: [(&str, &str); 2] = [("remove", "remove its items"), ("fix", "fix its variants")];

/// The maps of named items a pipeline declares (merged by name when one uses another).
const ITEM_MAPS: [&str; 5] = ["params", "samplers", "resources", "variants", "lets"];

/// Kinds `remove` takes, and the tree key holding each.
const REMOVABLE: [(&str, &str); 6] = [
    ("Pass", "passes"),
    ("Resource", "resources"),
    ("Param", "params"),
    ("Sampler", "samplers"),
    ("Variant", "variants"),
    ("Let", "lets"),
];

fn get<'a>(f: &'a [Field], key: &str) -> Option<&'a Node> {
    f.iter().find(|x| x.0 == key).map(|x| &x.2)
}

/// The `use` of a pipeline tree: the used file as written, and where.
pub fn used(root: &Node) -> Option<(String, Span)> {
    get(root.fields(), "use").and_then(|n| n.text().map(|t| (t.to_string(), n.span)))
}

/// A second `use` (a pipeline builds on one other; a chain of `use`s composes more) is a
/// located error, not a silent choice of one.
pub fn reject_second_use(root: &Node, diags: &mut Diagnostics) {
    let mut uses = root.fields().iter().filter(|f| f.0 == "use");
    let Some((_, first, _)) = uses.next() else { return };
    for (_, again, _) in uses {
        diags.push(
            Diagnostic::error(Code::DuplicateKey, "`use` is given twice: a pipeline uses one other", *again)
                .with_secondary(*first, "the first `use`")
                .with_note("to build on two pipelines, let one of them `use` the other"),
        );
    }
}

/// A pass node's name.
fn pass_name(p: &Node) -> Option<&str> {
    get(p.fields(), "name").and_then(Node::text)
}

/// `Replace(x)`: the replacement.
pub fn replacement(n: &Node) -> Option<&Node> {
    match &*n.value {
        Value::Tuple { name: Some((k, _)), items } if k == "Replace" && items.len() == 1 => Some(&items[0]),
        _ => None,
    }
}

/// A file that uses none may not replace, remove or place passes: say so where it tries
/// (and a `use` that names no file is a type error).
pub fn reject_composing(root: &Node, diags: &mut Diagnostics) {
    if let Some(u) = get(root.fields(), "use") {
        diags.push(
            Diagnostic::error(
                Code::TypeMismatch,
                format!("expected a pipeline file name, found {}", u.value.kind_word()),
                u.span,
            )
            .with_label_text("`use: \"file.ron\"` (LBP `use \"file.lbp\"`)"),
        );
    }
    let why = "only a pipeline that uses another (`use: \"file\"`) can";
    for (k, span, _) in root.fields() {
        if let Some((_, does)) = COMPOSING.iter().find(|(c, _)| c == k) {
            diags.push(Diagnostic::error(Code::Misplaced, format!("`{k}`: {why} {does}"), *span));
        }
    }
    for p in get(root.fields(), "passes").map(list).unwrap_or(&[]) {
        for (k, span, _) in p.fields().iter().filter(|f| f.0 == "after" || f.0 == "replace") {
            diags.push(Diagnostic::error(
                Code::Misplaced,
                format!("`{k}`: {why} place or replace its passes"),
                *span,
            ));
        }
    }
    for (_, _, m) in root.fields().iter().filter(|f| ITEM_MAPS.contains(&f.0.as_str())) {
        for (k, v) in entries(m) {
            if replacement(v).is_some() {
                diags.push(Diagnostic::error(
                    Code::Misplaced,
                    format!("`Replace`: {why} replace its items"),
                    k.span,
                ));
            }
        }
    }
}

fn list(n: &Node) -> &[Node] {
    match &*n.value {
        Value::List(items) => items,
        _ => &[],
    }
}

fn entries(n: &Node) -> &[(Node, Node)] {
    match &*n.value {
        Value::Map(e) => e,
        _ => &[],
    }
}

/// `base` (the used pipeline, itself composed) with `own`'s items merged in.
pub fn merge(base: &Node, own: &Node, diags: &mut Diagnostics) -> Node {
    let mut out: Vec<Field> = base.fields().iter().filter(|f| f.0 != "use").cloned().collect();
    removals(own, &mut out, diags);
    for (key, span, value) in own.fields() {
        let map = key == "fix" || ITEM_MAPS.contains(&key.as_str());
        match key.as_str() {
            "use" | "remove" => {}
            // Not a map: left as written, for the lowering to say what it should be.
            _ if map && !matches!(&*value.value, Value::Map(_)) => set(&mut out, key, *span, value.clone()),
            _ if map => merge_map(&mut out, key, *span, value, diags),
            "passes" if !matches!(&*value.value, Value::List(_)) => set(&mut out, key, *span, value.clone()),
            "passes" => merge_passes(&mut out, *span, value, diags),
            _ => set(&mut out, key, *span, value.clone()),
        }
    }
    Node::new(
        Value::Struct {
            name: match &*own.value {
                Value::Struct { name, .. } => name.clone(),
                _ => None,
            },
            fields: out,
        },
        own.span,
    )
}

fn set(out: &mut Vec<Field>, key: &str, span: Span, value: Node) {
    match out.iter_mut().find(|f| f.0 == key) {
        Some(f) => *f = (key.to_string(), span, value),
        None => out.push((key.to_string(), span, value)),
    }
}

/// Apply `remove: [Pass("x"), Resource("y"), ...]`.
fn removals(own: &Node, out: &mut [Field], diags: &mut Diagnostics) {
    let Some(remove) = get(own.fields(), "remove") else { return };
    if !matches!(&*remove.value, Value::List(_)) {
        diags.push(Diagnostic::error(
            Code::TypeMismatch,
            format!("expected a list `[Pass(\"name\"), ...]`, found {}", remove.value.kind_word()),
            remove.span,
        ));
    }
    for item in list(remove) {
        let (kind, name) = match &*item.value {
            Value::Tuple { name: Some((k, _)), items } if items.len() == 1 => (k.as_str(), items[0].text()),
            _ => ("", None),
        };
        let (Some((_, key)), Some(name)) = (REMOVABLE.iter().find(|(k, _)| *k == kind), name) else {
            diags.push(Diagnostic::error(
                Code::TypeMismatch,
                "expected `Pass(\"name\")`, `Resource(..)`, `Param(..)`, `Sampler(..)`, `Variant(..)` or `Let(..)`",
                item.span,
            ));
            continue;
        };
        let Some(field) = out.iter_mut().find(|f| f.0 == *key) else {
            diags.push(unknown(kind, name, &[], item.span));
            continue;
        };
        let node = &mut field.2;
        let (found, names) = match &*node.value {
            Value::List(items) => {
                let names: Vec<String> = items.iter().filter_map(|p| pass_name(p).map(str::to_string)).collect();
                let kept: Vec<Node> = items.iter().filter(|p| pass_name(p) != Some(name)).cloned().collect();
                let found = kept.len() < items.len();
                *node = Node::list(kept, node.span);
                (found, names)
            }
            Value::Map(e) => {
                let names: Vec<String> = e.iter().filter_map(|(k, _)| k.text().map(str::to_string)).collect();
                let kept: Vec<(Node, Node)> = e.iter().filter(|(k, _)| k.text() != Some(name)).cloned().collect();
                let found = kept.len() < e.len();
                *node = Node::map(kept, node.span);
                (found, names)
            }
            _ => (false, vec![]),
        };
        if !found {
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            diags.push(unknown(kind, name, &names, item.span));
        }
    }
}

fn unknown(kind: &str, name: &str, names: &[&str], span: Span) -> Diagnostic {
    let code = match kind {
        "Pass" => Code::UnknownPass,
        "Resource" => Code::UnknownResource,
        "Param" => Code::UnknownParam,
        // Samplers are named among resources (`bind` takes either).
        "Sampler" => Code::UnknownResource,
        _ => Code::UnknownVariant,
    };
    Diagnostic::error(code, format!("the used pipeline has no {} `{name}`", kind.to_lowercase()), span)
        .with_note(suggestion_note(name, names))
}

/// A map of the used file with this file's entries: new ones added, `Replace(..)` ones
/// replacing theirs in place; one of the same name without `Replace` is a conflict.
fn merge_map(out: &mut Vec<Field>, key: &str, span: Span, own: &Node, diags: &mut Diagnostics) {
    let mut merged: Vec<(Node, Node)> = get(out, key).map(entries).unwrap_or(&[]).to_vec();
    // Where each name is in `merged` (the first of a name), so a merge stays linear.
    let mut index: HashMap<Option<String>, usize> = HashMap::new();
    for (i, (b, _)) in merged.iter().enumerate() {
        index.entry(b.text().map(str::to_string)).or_insert(i);
    }
    let what = key.trim_end_matches('s');
    for (k, v) in entries(own) {
        let at = index.get(&k.text().map(str::to_string)).copied();
        match (replacement(v), at) {
            (Some(r), Some(i)) => merged[i] = (k.clone(), r.clone()),
            (Some(_), None) => diags.push(
                Diagnostic::error(
                    Code::UnknownKey,
                    format!("nothing to replace: the used pipeline has no {what} `{}`", k.text().unwrap_or("")),
                    k.span,
                )
                .with_note("without `Replace` (LBP `replace`) the item is added"),
            ),
            (None, Some(i)) if key != "fix" => diags.push(
                Diagnostic::error(
                    Code::DuplicateName,
                    format!("{what} `{}` is declared by the used pipeline too", k.text().unwrap_or("")),
                    k.span,
                )
                .with_secondary(merged[i].0.span, "declared here")
                .with_note("write `Replace(...)` (LBP `replace`) to change it, or `remove` it first"),
            ),
            (None, Some(i)) => merged[i] = (k.clone(), v.clone()),
            (None, None) => {
                index.insert(k.text().map(str::to_string), merged.len());
                merged.push((k.clone(), v.clone()))
            }
        }
    }
    set(out, key, span, Node::map(merged, span));
}

/// The used file's passes with this file's: `replace: true` ones in place of theirs,
/// `after: "pass"` ones after it (in this file's order), the rest at the end.
fn merge_passes(out: &mut Vec<Field>, span: Span, own: &Node, diags: &mut Diagnostics) {
    let mut passes: Vec<Node> = get(out, "passes").map(list).unwrap_or(&[]).to_vec();
    // Where the next pass placed after each anchor goes.
    let mut cursor: Vec<(String, usize)> = vec![];
    let own_names: Vec<&str> = list(own).iter().filter_map(pass_name).collect();
    for p in list(own) {
        let f = p.fields();
        let name = pass_name(p).unwrap_or("");
        let replace = matches!(get(f, "replace").map(|n| &*n.value), Some(Value::Bool(true)));
        let after = get(f, "after");
        let stripped = strip(p);
        let existing = passes.iter().position(|b| pass_name(b) == Some(name));
        let at = match (existing, replace) {
            (Some(i), true) => {
                passes.remove(i);
                cursor.iter_mut().filter(|(_, c)| *c > i).for_each(|(_, c)| *c -= 1);
                Some(i)
            }
            (None, true) => {
                let names: Vec<&str> = passes.iter().filter_map(pass_name).collect();
                diags.push(
                    Diagnostic::error(
                        Code::UnknownPass,
                        format!("nothing to replace: the used pipeline has no pass `{name}`"),
                        p.span,
                    )
                    .with_note(suggestion_note(name, &names)),
                );
                continue;
            }
            (Some(i), false) => {
                diags.push(
                    Diagnostic::error(
                        Code::DuplicateName,
                        format!("pass `{name}` is declared by the used pipeline too"),
                        p.span,
                    )
                    .with_secondary(passes[i].span, "declared here")
                    .with_note("write `replace: true` (LBP `replace fullscreen ...`) to change it, or `remove` it first"),
                );
                continue;
            }
            (None, false) => None,
        };
        // A pass that cannot be placed still joins (at the end), so that passes placed after
        // it are not reported too.
        let index = match after {
            Some(a) => {
                let others: Vec<&str> = own_names.iter().copied().filter(|n| *n != name).collect();
                place_after(&passes, &mut cursor, (a, &others), diags).unwrap_or(passes.len())
            }
            None => at.unwrap_or(passes.len()),
        };
        cursor.iter_mut().filter(|(_, c)| *c >= index).for_each(|(_, c)| *c += 1);
        passes.insert(index, stripped);
    }
    set(out, "passes", span, Node::list(passes, span));
}

/// The index after `anchor` (and after what was placed after it before); `own`: this file's
/// other passes (placed in the order written).
fn place_after(
    passes: &[Node],
    cursor: &mut Vec<(String, usize)>,
    (anchor, own): (&Node, &[&str]),
    diags: &mut Diagnostics,
) -> Option<usize> {
    let Some(a) = anchor.text().filter(|_| matches!(&*anchor.value, Value::Str(_))) else {
        diags.push(Diagnostic::error(
            Code::TypeMismatch,
            format!("expected a pass name, found {}", anchor.value.kind_word()),
            anchor.span,
        ));
        return None;
    };
    // (The caller moves every cursor at or past the index it inserts at on by one.)
    if let Some((_, c)) = cursor.iter().find(|(n, _)| n == a) {
        return Some(*c);
    }
    let Some(i) = passes.iter().position(|b| pass_name(b) == Some(a)) else {
        let d = Diagnostic::error(Code::UnknownPass, format!("no pass `{a}` to place this pass after"), anchor.span);
        let d = if own.contains(&a) {
            d.with_note(format!(
                "`{a}` is declared later in this file: passes are placed in the order written, so declare it first"
            ))
        } else {
            let used = passes.iter().filter_map(pass_name);
            let mut names: Vec<&str> = used.filter(|n| !own.contains(n)).collect();
            names.extend(own);
            d.with_note(suggestion_note(a, &names))
        };
        diags.push(d);
        return None;
    };
    cursor.push((a.to_string(), i + 1));
    Some(i + 1)
}

/// A pass without its placement keys.
fn strip(p: &Node) -> Node {
    match &*p.value {
        Value::Struct { name, fields } => Node::new(
            Value::Struct {
                name: name.clone(),
                fields: fields.iter().filter(|f| f.0 != "after" && f.0 != "replace").cloned().collect(),
            },
            p.span,
        ),
        _ => p.clone(),
    }
}
