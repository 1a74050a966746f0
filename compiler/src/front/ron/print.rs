//! Syntax tree -> RON text (what `lightbench convert --to ron` writes). The pipeline's
//! top-level maps and lists put one item per line, passes and variants one key per line;
//! everything else is inline. Comments from the source are kept before the item they preceded.

use crate::front::comments::Out;
use crate::front::{item_start, quote};
use crate::ir::Pipeline;
use crate::tree::{Node, Value};
use std::fmt::Write;

pub fn print(p: &Pipeline, source: Option<&str>) -> String {
    print_tree(&crate::syntax::raise::pipeline(p), source)
}

pub fn print_tree(root: &Node, source: Option<&str>) -> String {
    let mut pr = Printer { out: Out::new(source) };
    pr.root(root);
    pr.out.finish()
}

struct Printer {
    out: Out,
}

fn num(x: f64) -> String {
    // RON floats need a decimal point or exponent to stay floats.
    let s = format!("{}", x + 0.0); // -0.0 prints as 0.0, as LBP prints it
    if s.contains('.') || s.contains('e') || s.contains("inf") || s.contains("NaN") {
        s
    } else {
        format!("{s}.0")
    }
}

/// A value on one line.
pub fn inline(n: &Node) -> String {
    match &*n.value {
        Value::Bool(b) => b.to_string(),
        Value::Int(i) => i.to_string(),
        Value::Float(f) => num(*f),
        Value::Str(s) => quote(s),
        Value::Ident(i) => i.clone(),
        Value::List(items) => format!("[{}]", items.iter().map(inline).collect::<Vec<_>>().join(", ")),
        Value::Map(entries) => format!(
            "{{{}}}",
            entries
                .iter()
                .map(|(k, v)| format!("{}: {}", inline(k), inline(v)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        Value::Struct { name, fields } => format!(
            "{}({})",
            name.as_ref().map(|n| n.0.as_str()).unwrap_or(""),
            fields
                .iter()
                .map(|(k, _, v)| format!("{k}: {}", inline(v)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        Value::Tuple { name, items } => format!(
            "{}({})",
            name.as_ref().map(|n| n.0.as_str()).unwrap_or(""),
            items.iter().map(inline).collect::<Vec<_>>().join(", ")
        ),
    }
}

impl Printer {
    fn root(&mut self, root: &Node) {
        let Value::Struct { name, fields } = &*root.value else {
            self.out.text.push_str(&inline(root));
            return;
        };
        self.out.comments_before(fields.first().map(|f| f.2.span).unwrap_or(root.span), "");
        let _ = writeln!(self.out.text, "{}(", name.as_ref().map(|n| n.0.as_str()).unwrap_or(""));
        for (k, _, v) in fields {
            match (k.as_str(), &*v.value) {
                ("passes", Value::List(items)) => self.passes(items),
                (_, Value::Map(entries)) => self.map(k, entries),
                _ => {
                    self.out.comments_before(v.span, "    ");
                    let _ = writeln!(self.out.text, "    {k}: {},", inline(v));
                }
            }
        }
        self.out.text.push_str(")\n");
    }

    /// A top-level map: one entry per line; variants one key per line.
    fn map(&mut self, key: &str, entries: &[(Node, Node)]) {
        let _ = writeln!(self.out.text, "    {key}: {{");
        for (k, v) in entries {
            self.out.comments_before(item_start(k, v), "        ");
            match (&*v.value, v.name()) {
                (Value::Struct { fields, .. }, Some("Variant")) => {
                    let _ = writeln!(self.out.text, "        {}: Variant(", inline(k));
                    for (fk, _, fv) in fields {
                        self.variant_field(fk, fv);
                    }
                    self.out.text.push_str("        ),\n");
                }
                _ => {
                    let _ = writeln!(self.out.text, "        {}: {},", inline(k), inline(v));
                }
            }
        }
        self.out.text.push_str("    },\n");
    }

    fn variant_field(&mut self, key: &str, v: &Node) {
        let Value::Map(options) = &*v.value else {
            let _ = writeln!(self.out.text, "            {key}: {},", inline(v));
            return;
        };
        let _ = writeln!(self.out.text, "            {key}: {{");
        for (k, o) in options {
            self.out.comments_before(item_start(k, o), "                ");
            let _ = writeln!(self.out.text, "                {}: {},", inline(k), inline(o));
        }
        self.out.text.push_str("            },\n");
    }

    /// Passes: one key per line.
    fn passes(&mut self, items: &[Node]) {
        self.out.text.push_str("    passes: [\n");
        for p in items {
            self.out.comments_before(p.span, "        ");
            let inside = crate::span::Span::new(p.span.file, p.span.end as usize, p.span.end as usize);
            match &*p.value {
                Value::Struct { name, fields } => {
                    let _ = writeln!(self.out.text, "        {}(", name.as_ref().map(|n| n.0.as_str()).unwrap_or(""));
                    // Comments inside the pass body come first in it (as LBP prints them).
                    self.out.comments_before(inside, "            ");
                    for (k, _, v) in fields {
                        let _ = writeln!(self.out.text, "            {k}: {},", inline(v));
                    }
                    self.out.text.push_str("        ),\n");
                }
                _ => {
                    self.out.comments_before(inside, "        ");
                    let _ = writeln!(self.out.text, "        {},", inline(p));
                }
            }
        }
        self.out.text.push_str("    ],\n");
    }
}
