//! Front ends: parsers from each pipeline language into the one syntax tree, and printers
//! of that tree (for `convert` and `fmt`). Lowering to the IR is `syntax::lower`.

pub mod comments;
pub mod lbp;
pub mod ron;

/// How deep values (RON) and conditions (LBP, RON) may nest: deeper input is a
/// `nesting-too-deep` error, never a stack overflow in the recursive parsers and lowering.
pub const MAX_NESTING: usize = 64;

/// A string literal as both languages write it.
pub fn quote(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            '\0' => out.push_str("\\0"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Where comments before an item go: the earliest of its key's and value's spans (RON
/// writes the key first, LBP the keyword that starts the value).
pub fn item_start(key: &crate::tree::Node, value: &crate::tree::Node) -> crate::span::Span {
    if key.span.start <= value.span.start {
        key.span
    } else {
        value.span
    }
}
