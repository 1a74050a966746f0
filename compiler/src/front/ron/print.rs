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
    let mut pr = Printer {
        out: Out::new(source, root),
    };
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
                ("passes", Value::List(items)) => self.passes(items, "    "),
                (_, Value::Map(entries)) => self.map(k, entries),
                _ => {
                    self.out.comments_before(v.span, "    ");
                    let _ = writeln!(self.out.text, "    {k}: {},", inline(v));
                }
            }
        }
        self.out.text.push_str(")\n");
    }

    /// A top-level map: one entry per line; variants and templates one key per line.
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
                (Value::Struct { fields, .. }, Some("Template")) => {
                    let _ = writeln!(self.out.text, "        {}: Template(", inline(k));
                    for (fk, _, fv) in fields {
                        self.out.comments_before(fv.span, "            ");
                        let _ = writeln!(self.out.text, "            {fk}: {},", inline(fv));
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

    /// Passes: one key per line; a group's passes likewise, inside it.
    fn passes(&mut self, items: &[Node], indent: &str) {
        let _ = writeln!(self.out.text, "{indent}passes: [");
        let inner = format!("{indent}    ");
        for p in items {
            self.pass(p, &inner);
        }
        let _ = writeln!(self.out.text, "{indent}],");
    }

    fn pass(&mut self, p: &Node, indent: &str) {
        self.out.comments_before(p.span, indent);
        let inside = crate::span::Span::new(p.span.file, p.span.end as usize, p.span.end as usize);
        let Value::Struct { name, fields } = &*p.value else {
            self.out.comments_before(inside, indent);
            let _ = writeln!(self.out.text, "{indent}{},", inline(p));
            return;
        };
        let kind = name.as_ref().map(|n| n.0.as_str()).unwrap_or("");
        let _ = writeln!(self.out.text, "{indent}{kind}(");
        let inner = format!("{indent}    ");
        let group = kind == "Group";
        // Comments inside a pass body come first in it (as LBP prints them); a group's go
        // before what they preceded.
        if !group {
            self.out.comments_before(inside, &inner);
        }
        for (k, _, v) in fields {
            match (&*v.value, group) {
                (Value::List(items), true) if k == "passes" => self.passes(items, &inner),
                _ => {
                    if group {
                        self.out.comments_before(v.span, &inner);
                    }
                    let _ = writeln!(self.out.text, "{inner}{k}: {},", inline(v));
                }
            }
        }
        let _ = writeln!(self.out.text, "{indent}),");
    }
}
