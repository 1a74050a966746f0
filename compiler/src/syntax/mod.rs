//! The syntax layer shared by every front end: one table of defaults, one lowering
//! (`crate::tree` -> IR) and one raise (IR -> tree) that both printers print.

pub mod compose;
pub mod defaults;
pub mod groups;
pub mod light_choices;
pub mod lower;
pub mod origins;
pub mod raise;
pub mod templates;

use crate::tree::{Node, Value};

/// The pipeline tree with its `passes` list made again by `f` (each file-level stage that
/// turns written passes into passes: groups, choices by light kind).
pub(crate) fn with_passes(root: &Node, mut f: impl FnMut(&[Node]) -> Vec<Node>) -> Node {
    let Value::Struct { name, fields } = &*root.value else {
        return root.clone();
    };
    let fields = fields
        .iter()
        .map(|(k, span, v)| match (k.as_str(), &*v.value) {
            ("passes", Value::List(items)) => (k.clone(), *span, Node::list(f(items), v.span)),
            _ => (k.clone(), *span, v.clone()),
        })
        .collect();
    Node::new(
        Value::Struct {
            name: name.clone(),
            fields,
        },
        root.span,
    )
}
