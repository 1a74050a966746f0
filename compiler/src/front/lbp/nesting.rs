//! Nesting guard for LBP: pest and the tree builder recurse once per nested condition, so
//! text is scanned for its deepest nesting before parsing, and anything deeper than
//! [`MAX_NESTING`](crate::front::MAX_NESTING) is one located error instead of a stack overflow.

use crate::front::MAX_NESTING;

/// Byte range of the token at which `text` first nests deeper than the limit. A level is
/// an open bracket, or a `not` that applies to what follows (`not not x` is two levels).
pub fn too_deep(text: &str) -> Option<(usize, usize)> {
    let b = text.as_bytes();
    let (mut i, mut depth, mut pending) = (0, 0usize, 0usize);
    let mut stack: Vec<usize> = vec![];
    // `not` chains end at anything but `not`, a word, or the `(` that opens a call.
    let mut after_word = false;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        if let Some(after) = skip_comment(text, i) {
            i = after;
            continue;
        }
        if c != b'(' && !(c.is_ascii_alphabetic() || c == b'_') && after_word {
            pending = 0;
        }
        after_word = false;
        match c {
            b'"' => i = skip_string(b, i),
            b'(' | b'[' | b'{' => {
                stack.push(depth);
                depth += pending + 1;
                pending = 0;
                i += 1;
            }
            b')' | b']' | b'}' => {
                depth = stack.pop().unwrap_or(0);
                pending = 0;
                i += 1;
            }
            c if c.is_ascii_alphabetic() || c == b'_' => {
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_' || b[i] == b'.') {
                    i += 1;
                }
                if &text[start..i] == "not" {
                    pending += 1;
                } else {
                    after_word = true;
                }
            }
            _ => {
                pending = 0;
                i += 1;
            }
        }
        if depth + pending > MAX_NESTING {
            return Some((start, i.max(start + 1)));
        }
    }
    None
}

/// The innermost `{` still open at the end of the text (strings and comments skipped): where
/// a missing `}` belongs.
pub fn unclosed_brace(text: &str) -> Option<usize> {
    let b = text.as_bytes();
    let (mut i, mut open) = (0, vec![]);
    while i < b.len() {
        if let Some(after) = skip_comment(text, i) {
            i = after;
            continue;
        }
        match b[i] {
            b'"' => {
                i = skip_string(b, i);
                continue;
            }
            b'{' => open.push(i),
            b'}' => {
                open.pop();
            }
            _ => {}
        }
        i += 1;
    }
    open.pop()
}

/// Index after the comment starting at `i`, if one does (`//` to the line's end, `/* */`).
fn skip_comment(text: &str, i: usize) -> Option<usize> {
    let rest = &text.as_bytes()[i..];
    if rest.starts_with(b"//") {
        return Some(text[i..].find('\n').map_or(text.len(), |n| i + n));
    }
    if rest.starts_with(b"/*") {
        return Some(text[i + 2..].find("*/").map_or(text.len(), |n| i + n + 4));
    }
    None
}

/// Index after the string literal starting at `i` (escapes skipped; unterminated: the end).
fn skip_string(b: &[u8], mut i: usize) -> usize {
    i += 1;
    while i < b.len() {
        match b[i] {
            b'\\' => i += 2,
            b'"' => return i + 1,
            _ => i += 1,
        }
    }
    b.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_brackets_and_not_chains() {
        let nots = |n: usize| format!("pipeline p\nraster a {{ when {}reflective }}", "not ".repeat(n));
        assert_eq!(too_deep(&nots(MAX_NESTING - 1)), None);
        assert!(too_deep(&nots(MAX_NESTING + 1)).is_some());
        let calls = |n: usize| format!("when {}reflective{}", "all(".repeat(n), ")".repeat(n));
        assert_eq!(too_deep(&calls(MAX_NESTING)), None);
        assert!(too_deep(&calls(MAX_NESTING + 1)).is_some());
        // Many sibling conditions do not add up, and brackets in strings or comments do not count.
        let wide = format!("pipeline p\n{}", "raster a \"x\" { when not reflective }\n".repeat(500));
        assert_eq!(too_deep(&wide), None);
        let quoted = format!("pipeline \"{}\" // {}", "(".repeat(200), "[".repeat(200));
        assert_eq!(too_deep(&quoted), None);
    }
}
