//! The spanned, format-neutral syntax tree every front end parses into: RON's data model
//! (structs, tuples, lists, maps, strings, numbers, identifiers). The lowering reads only
//! this tree, so a new front end is just a parser.

use crate::span::Span;
use std::sync::Arc;

#[derive(Clone, Debug)]
pub struct Node {
    /// Shared so that lowering can hand subtrees around without deep copies (and a pass
    /// with choices can keep the tree it was written as: `ir::Choice`).
    pub value: Arc<Value>,
    pub span: Span,
}

/// A struct field: key, the key's span, value.
pub type Field = (String, Span, Node);

#[derive(Clone, Debug)]
pub enum Value {
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    /// A bare identifier: a unit enum variant such as `Viewport` or `None`.
    Ident(String),
    List(Vec<Node>),
    Map(Vec<(Node, Node)>),
    /// `Name(key: value, ...)` or `(key: value, ...)`. The name's span is where the item
    /// starts for messages about it as a whole (a missing key).
    Struct {
        name: Option<(String, Span)>,
        fields: Vec<Field>,
    },
    /// `Name(a, b)` or `(a, b)`; `Name()` and `()` are empty tuples.
    Tuple {
        name: Option<(String, Span)>,
        items: Vec<Node>,
    },
}

impl Node {
    pub fn new(value: Value, span: Span) -> Node {
        Node {
            value: Arc::new(value),
            span,
        }
    }
    pub fn str(s: impl Into<String>, span: Span) -> Node {
        Node::new(Value::Str(s.into()), span)
    }
    pub fn ident(s: impl Into<String>, span: Span) -> Node {
        Node::new(Value::Ident(s.into()), span)
    }
    pub fn int(i: i64, span: Span) -> Node {
        Node::new(Value::Int(i), span)
    }
    pub fn float(f: f64, span: Span) -> Node {
        Node::new(Value::Float(f), span)
    }
    pub fn bool(b: bool, span: Span) -> Node {
        Node::new(Value::Bool(b), span)
    }
    pub fn list(items: Vec<Node>, span: Span) -> Node {
        Node::new(Value::List(items), span)
    }
    pub fn map(entries: Vec<(Node, Node)>, span: Span) -> Node {
        Node::new(Value::Map(entries), span)
    }
    /// `Name(items...)`, e.g. `Fixed(512, 512)`.
    pub fn call(name: &str, items: Vec<Node>, span: Span) -> Node {
        Node::new(
            Value::Tuple {
                name: Some((name.to_string(), span)),
                items,
            },
            span,
        )
    }
    /// An anonymous tuple `(a, b, ...)`.
    pub fn tuple(items: Vec<Node>, span: Span) -> Node {
        Node::new(Value::Tuple { name: None, items }, span)
    }
    /// `Name(key: value, ...)`.
    pub fn structure(name: &str, name_span: Span, fields: Vec<Field>, span: Span) -> Node {
        Node::new(
            Value::Struct {
                name: Some((name.to_string(), name_span)),
                fields,
            },
            span,
        )
    }

    /// The text of a string or identifier.
    pub fn text(&self) -> Option<&str> {
        match &*self.value {
            Value::Str(s) | Value::Ident(s) => Some(s),
            _ => None,
        }
    }

    /// A struct's fields (none for any other value).
    pub fn fields(&self) -> &[Field] {
        match &*self.value {
            Value::Struct { fields, .. } => fields,
            _ => &[],
        }
    }

    /// Call `f` on each child: list and tuple items, map keys and values, field values. No
    /// allocation: the stages that walk whole files call it per node.
    pub fn each_child<'a>(&'a self, mut f: impl FnMut(&'a Node)) {
        match &*self.value {
            Value::List(items) | Value::Tuple { items, .. } => items.iter().for_each(f),
            Value::Map(entries) => entries.iter().for_each(|(k, v)| {
                f(k);
                f(v)
            }),
            Value::Struct { fields, .. } => fields.iter().for_each(|x| f(&x.2)),
            _ => {}
        }
    }

    /// The struct's or tuple's name, if it has one.
    pub fn name(&self) -> Option<&str> {
        match &*self.value {
            Value::Struct { name, .. } | Value::Tuple { name, .. } => name.as_ref().map(|(n, _)| n.as_str()),
            Value::Ident(i) => Some(i),
            _ => None,
        }
    }
}

impl Value {
    /// Human word for `"expected X, found <this>"`.
    pub fn kind_word(&self) -> String {
        match self {
            Value::Bool(_) => "a bool".into(),
            Value::Int(_) => "an integer".into(),
            Value::Float(_) => "a float".into(),
            Value::Str(_) => "a string".into(),
            Value::Ident(i) => format!("`{i}`"),
            Value::List(_) => "a list".into(),
            Value::Map(_) => "a map".into(),
            Value::Struct { name: Some((n, _)), .. } | Value::Tuple { name: Some((n, _)), .. } => format!("`{n}(...)`"),
            Value::Struct { .. } => "a struct".into(),
            Value::Tuple { .. } => "a tuple".into(),
        }
    }
}

/// The same tree with every span in `file` (a tree another compilation parsed from the same
/// text, whose source map numbered the file differently).
pub fn refile(n: &Node, file: crate::span::FileId) -> Node {
    let at = |s: Span| Span { file, ..s };
    let value = match &*n.value {
        Value::List(items) => Value::List(items.iter().map(|i| refile(i, file)).collect()),
        Value::Map(entries) => Value::Map(entries.iter().map(|(k, v)| (refile(k, file), refile(v, file))).collect()),
        Value::Struct { name, fields } => Value::Struct {
            name: name.as_ref().map(|(n, s)| (n.clone(), at(*s))),
            fields: fields.iter().map(|(k, s, v)| (k.clone(), at(*s), refile(v, file))).collect(),
        },
        Value::Tuple { name, items } => Value::Tuple {
            name: name.as_ref().map(|(n, s)| (n.clone(), at(*s))),
            items: items.iter().map(|i| refile(i, file)).collect(),
        },
        leaf => leaf.clone(),
    };
    Node::new(value, at(n.span))
}

/// Equal as data, ignoring spans (for default elision and tests).
pub fn same(a: &Node, b: &Node) -> bool {
    match (&*a.value, &*b.value) {
        (Value::Bool(x), Value::Bool(y)) => x == y,
        (Value::Int(x), Value::Int(y)) => x == y,
        (Value::Float(x), Value::Float(y)) => x == y,
        (Value::Int(x), Value::Float(y)) | (Value::Float(y), Value::Int(x)) => *x as f64 == *y,
        (Value::Str(x), Value::Str(y)) | (Value::Ident(x), Value::Ident(y)) => x == y,
        (Value::List(x), Value::List(y)) => x.len() == y.len() && x.iter().zip(y).all(|(a, b)| same(a, b)),
        (Value::Tuple { name: n1, items: i1 }, Value::Tuple { name: n2, items: i2 }) => {
            n1.as_ref().map(|n| &n.0) == n2.as_ref().map(|n| &n.0) && i1.len() == i2.len() && i1.iter().zip(i2).all(|(a, b)| same(a, b))
        }
        (Value::Struct { name: n1, fields: f1 }, Value::Struct { name: n2, fields: f2 }) => {
            n1.as_ref().map(|n| &n.0) == n2.as_ref().map(|n| &n.0)
                && f1.len() == f2.len()
                && f1.iter().zip(f2).all(|(a, b)| a.0 == b.0 && same(&a.2, &b.2))
        }
        (Value::Map(x), Value::Map(y)) => x.len() == y.len() && x.iter().zip(y).all(|(a, b)| same(&a.0, &b.0) && same(&a.1, &b.1)),
        _ => false,
    }
}
