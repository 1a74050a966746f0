//! Stage `groups`: a block of passes that share attributes — LBP `group { when …  cull None
//! raster a "a.wgsl" { … } … }`, RON `Group(when: …, cull: None, passes: [ … ])` — becomes
//! its passes, each given the group's attributes it does not set itself: a `when` holds
//! together with the pass's own (`All`), `reads` come before the pass's, any other attribute of
//! the pass's own wins. Groups nest. This runs on each file's tree before composition and the
//! one lowering, so both front ends share it and every attribute keeps the span it was written
//! at (a problem with a group's attribute points at the group's line).

use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::tree::{Field, Node, Value};

/// Does the pipeline tree hold a group (then `fmt` and `convert` print it as written)?
pub fn has_groups(root: &Node) -> bool {
    passes(root).is_some_and(|list| list.iter().any(is_group))
}

/// The tree with every group replaced by its passes, in order.
pub fn expand(root: &Node, diags: &mut Diagnostics) -> Node {
    if !has_groups(root) {
        return root.clone();
    }
    super::with_passes(root, |items| {
        let mut out = vec![];
        flatten(items, &[], &mut out, diags);
        out
    })
}

fn passes(root: &Node) -> Option<&[Node]> {
    let Value::Struct { fields, .. } = &*root.value else { return None };
    match fields.iter().find(|f| f.0 == "passes").map(|f| &*f.2.value) {
        Some(Value::List(items)) => Some(items),
        _ => None,
    }
}

fn is_group(n: &Node) -> bool {
    matches!(&*n.value, Value::Struct { name: Some((k, _)), .. } if k == "Group")
}

/// Each item's passes with the attributes `inherited` from the groups around it.
fn flatten(items: &[Node], inherited: &[Field], out: &mut Vec<Node>, diags: &mut Diagnostics) {
    for item in items {
        let Value::Struct { name, fields } = &*item.value else {
            out.push(item.clone());
            continue;
        };
        if !is_group(item) {
            let fields = with_inherited(fields, inherited);
            out.push(Node::new(
                Value::Struct {
                    name: name.clone(),
                    fields,
                },
                item.span,
            ));
            continue;
        }
        // A group's name is the reader's (and `plan --explain`'s): no attribute of its passes.
        let own: Vec<Field> = fields.iter().filter(|f| f.0 != "passes" && f.0 != "name").cloned().collect();
        if let Some((_, span, _)) = own.iter().find(|f| f.0 == "replace") {
            let d = Diagnostic::error(Code::UnknownKey, "a group replaces nothing: its passes do", *span)
                .with_note("a group gives its passes attributes they share (`when`, `cull`, `reads`, `per_light`, …)");
            diags.push(d);
            continue;
        }
        let inner: Vec<Node> = match fields.iter().find(|f| f.0 == "passes").map(|f| &*f.2.value) {
            Some(Value::List(items)) if !items.is_empty() => items.clone(),
            _ => {
                let head = name.as_ref().map_or(item.span, |(_, s)| *s);
                diags.push(Diagnostic::warning(Code::EmptyGroup, "a group without passes", head));
                continue;
            }
        };
        flatten(&inner, &with_inherited(&own, inherited), out, diags);
    }
}

/// `own` fields with the `outer` ones they lack; `when`s joined (both hold), `reads` the
/// outer's first.
pub(super) fn with_inherited(own: &[Field], outer: &[Field]) -> Vec<Field> {
    let mut out: Vec<Field> = own.to_vec();
    for (k, span, v) in outer {
        let Some(at) = out.iter().position(|f| f.0 == *k) else {
            out.push((k.clone(), *span, v.clone()));
            continue;
        };
        let mine = &out[at].2;
        let joined = match k.as_str() {
            "when" => Node::call("All", vec![Node::list(vec![v.clone(), mine.clone()], mine.span)], mine.span),
            "reads" => match (&*v.value, &*mine.value) {
                (Value::List(a), Value::List(b)) => Node::list(a.iter().chain(b).cloned().collect(), mine.span),
                _ => continue,
            },
            _ => continue,
        };
        out[at].2 = joined;
    }
    out
}
