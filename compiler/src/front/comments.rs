//! Comments of a pipeline file, kept by the formatter and converters: each comment is
//! re-emitted before the item that follows it in the source.

use crate::span::Span;
use crate::tree::{Node, Value};

#[derive(Clone, Debug, PartialEq)]
pub struct Comment {
    pub start: usize,
    /// The text without its `//` or `/* */` markers, one entry per line.
    pub lines: Vec<String>,
}

/// Every `//` and `/* */` comment outside string literals, in order.
pub fn collect(src: &str) -> Vec<Comment> {
    let b = src.as_bytes();
    let mut out = vec![];
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'"' => {
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    if b[i] == b'\\' {
                        i += 1;
                    }
                    i += 1;
                }
                i += 1;
            }
            b'/' if b.get(i + 1) == Some(&b'/') => {
                let start = i;
                let end = src[i..].find('\n').map(|n| i + n).unwrap_or(src.len());
                out.push(Comment {
                    start,
                    lines: vec![src[i + 2..end].trim_end().to_string()],
                });
                i = end;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                let start = i;
                let end = src[i + 2..].find("*/").map(|n| i + 2 + n).unwrap_or(src.len());
                out.push(Comment {
                    start,
                    lines: src[i + 2..end].lines().map(|l| l.trim().to_string()).collect(),
                });
                i = (end + 2).min(src.len());
            }
            _ => i += 1,
        }
    }
    out
}

/// Where each declaration and pass of a pipeline tree starts (the top-level maps' entries,
/// lists' items and groups' passes): a comment before one of them is that item's, wherever the printer puts it (a
/// `let` written before the parameters is printed after the resources, its comment with it).
pub fn anchors(root: &Node) -> Vec<usize> {
    let Value::Struct { fields, .. } = &*root.value else {
        return vec![];
    };
    let mut out = vec![];
    for (_, _, v) in fields {
        match &*v.value {
            Value::Map(entries) => out.extend(entries.iter().map(|(k, v)| crate::front::item_start(k, v).start as usize)),
            Value::List(items) => passes(items, &mut out),
            _ => {}
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Where each item of a list starts, and each pass of a group in it (a comment inside a group
/// stays there when a top-level item after the group is printed before it).
fn passes(items: &[Node], out: &mut Vec<usize>) {
    for i in items {
        out.push(i.span.start as usize);
        if let Value::Struct { fields, .. } = &*i.value {
            for (_, _, v) in fields.iter().filter(|f| f.0 == "passes") {
                if let Value::List(inner) = &*v.value {
                    passes(inner, out);
                }
            }
        }
    }
}

/// Hands out comments: `before(span)` takes every comment starting before the item that no
/// other item's start (`anchors`) comes between, `rest()` whatever is left at the end.
pub struct Comments {
    /// In source order.
    list: Vec<Comment>,
    taken: Vec<bool>,
    /// Every comment before this one is taken.
    first: usize,
    /// Sorted.
    anchors: Vec<usize>,
}

impl Comments {
    pub fn new(src: Option<&str>, anchors: Vec<usize>) -> Self {
        let list = src.map(collect).unwrap_or_default();
        Comments {
            taken: vec![false; list.len()],
            list,
            first: 0,
            anchors,
        }
    }

    pub fn before(&mut self, span: Span) -> Vec<Comment> {
        let at = span.start as usize;
        while self.taken.get(self.first) == Some(&true) {
            self.first += 1;
        }
        let mut out = vec![];
        for i in self.first..self.list.len() {
            let c = &self.list[i];
            if c.start >= at {
                break;
            }
            // Another item starts between the comment and this one: the comment is that one's.
            let next = self.anchors.partition_point(|&a| a <= c.start);
            if !self.taken[i] && self.anchors.get(next).is_none_or(|&a| a >= at) {
                self.taken[i] = true;
                out.push(c.clone());
            }
        }
        out
    }

    pub fn rest(&mut self) -> Vec<Comment> {
        let rest = self
            .list
            .iter()
            .zip(&self.taken)
            .filter(|(_, t)| !**t)
            .map(|(c, _)| c.clone())
            .collect();
        self.taken.fill(true);
        rest
    }
}

/// Text being printed, with the source's comments placed before the items they preceded.
pub struct Out {
    pub text: String,
    comments: Comments,
}

impl Out {
    /// For printing `root`, whose items' spans are in `source`.
    pub fn new(source: Option<&str>, root: &Node) -> Self {
        Out {
            text: String::new(),
            comments: Comments::new(source, anchors(root)),
        }
    }

    /// Emit the comments that come before `span` at an indent.
    pub fn comments_before(&mut self, span: Span, indent: &str) {
        let cs = self.comments.before(span);
        emit(&mut self.text, &cs, indent);
    }

    /// The text, with the comments left over at the end.
    pub fn finish(mut self) -> String {
        let rest = self.comments.rest();
        emit(&mut self.text, &rest, "");
        self.text
    }
}

/// Write comments as `//` lines at an indent.
pub fn emit(out: &mut String, comments: &[Comment], indent: &str) {
    for c in comments {
        for l in &c.lines {
            if l.is_empty() {
                out.push_str(&format!("{indent}//\n"));
            } else {
                out.push_str(&format!("{indent}//{}{l}\n", if l.starts_with(' ') { "" } else { " " }));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_comments_but_not_in_strings() {
        let c = collect("a // one\n\"x // no\" /* two\n  three */ b");
        assert_eq!(c.len(), 2);
        assert_eq!(c[0].lines, vec![" one"]);
        assert_eq!(c[1].lines, vec!["two", "three"]);
    }
}
