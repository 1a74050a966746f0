//! Stage `origins`: where each pass of a file was written — the groups around it, the
//! templates it is like, the name it had before a choice by light kind made passes of it —
//! read from the file's tree before templates, groups and light choices turn it into plain
//! passes, so that `plan --explain` can say where a pass came from ("in group `shadow_maps` ›
//! group `point_shadows`; like `two_sided`"). Keyed by the span of the pass as written, which
//! those stages keep.

use crate::span::Span;
use crate::tree::{Field, Node, Value};

/// Where one pass was written; the words are made only when asked (`describe`).
pub struct Origin {
    /// The pass as written (the passes made of it keep it).
    pub span: Span,
    /// The pass as written, and the groups around it, outermost first.
    pass: Node,
    groups: std::sync::Arc<Vec<Node>>,
}

impl Origin {
    /// What its writing says beyond the pass `planned` (its name in the Plan), if anything:
    /// the groups around it, the templates it is like, the pass a choice by light kind made
    /// it of.
    pub fn describe(&self, planned: &str) -> Option<String> {
        let mut parts = vec![];
        if !self.groups.is_empty() {
            let groups: Vec<String> = self.groups.iter().map(group_words).collect();
            parts.push(format!("in {}", groups.join(" › ")));
        }
        if let Some(l) = like(self.pass.fields()) {
            parts.push(format!("like {l}"));
        }
        let written = self
            .pass
            .fields()
            .iter()
            .find(|x| x.0 == "name")
            .and_then(|x| x.2.text())
            .unwrap_or("");
        if planned != written {
            parts.push(format!("one of the passes `{written}` makes by light kind"));
        }
        (!parts.is_empty()).then(|| parts.join("; "))
    }
}

/// A group as `describe` names it: `group `name` (like …)`.
fn group_words(g: &Node) -> String {
    let f = g.fields();
    let name = f.iter().find(|x| x.0 == "name").and_then(|x| x.2.text());
    let mut here = name.map_or("a group".to_string(), |n| format!("group `{n}`"));
    if let Some(l) = like(f) {
        here += &format!(" (like {l})");
    }
    here
}

/// Where each pass of a file's tree was written.
pub fn of(root: &Node) -> Vec<Origin> {
    let mut out = vec![];
    if let Value::Struct { fields, .. } = &*root.value {
        for (_, _, v) in fields.iter().filter(|f| f.0 == "passes") {
            walk(v, &std::sync::Arc::new(vec![]), &mut out);
        }
    }
    out
}

fn walk(list: &Node, groups: &std::sync::Arc<Vec<Node>>, out: &mut Vec<Origin>) {
    let Value::List(items) = &*list.value else { return };
    for item in items {
        if item.name() != Some("Group") {
            out.push(Origin {
                span: item.span,
                pass: item.clone(),
                groups: groups.clone(),
            });
            continue;
        }
        let inner = std::sync::Arc::new(groups.iter().cloned().chain([item.clone()]).collect());
        for (_, _, v) in item.fields().iter().filter(|x| x.0 == "passes") {
            walk(v, &inner, out);
        }
    }
}

/// `a, b(x)` for an item `like` templates.
fn like(f: &[Field]) -> Option<String> {
    let l = &f.iter().find(|x| x.0 == "like")?.2;
    let refs: Vec<&Node> = match &*l.value {
        Value::List(items) => items.iter().collect(),
        _ => vec![l],
    };
    let one = |r: &Node| -> String {
        let Value::Tuple { items, .. } = &*r.value else {
            return String::new();
        };
        let name = items.first().and_then(|n| n.text()).unwrap_or("");
        let args: Vec<String> = items[1..].iter().map(argument).collect();
        if args.is_empty() {
            format!("`{name}`")
        } else {
            format!("`{name}({})`", args.join(", "))
        }
    };
    Some(refs.into_iter().map(one).collect::<Vec<_>>().join(", "))
}

fn argument(n: &Node) -> String {
    match &*n.value {
        Value::Str(s) | Value::Ident(s) => s.clone(),
        Value::Int(i) => i.to_string(),
        Value::Float(x) => x.to_string(),
        Value::Bool(b) => b.to_string(),
        Value::Tuple { items, .. } => format!("({})", items.iter().map(argument).collect::<Vec<_>>().join(", ")),
        _ => "…".to_string(),
    }
}
