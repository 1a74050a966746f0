//! Language server, documents: URIs as paths (open documents are held over the disk in the
//! compiler's `vfs::Overlay`, which checks read through), positions as the protocol counts them (0-based lines, UTF-16
//! code units) against byte offsets as spans count them, and the word around an offset.

use lightbench_compiler::vfs::normalize;
use lsp_types::{Position, Range, Uri};
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// The local path a `file:` URI names (percent-escapes decoded); `None` for other schemes.
pub fn path_of(uri: &Uri) -> Option<PathBuf> {
    let rest = uri.as_str().strip_prefix("file://")?;
    // `file://host/path` is not local; `file:///path` is.
    let path = rest.strip_prefix("localhost").unwrap_or(rest);
    if !path.starts_with('/') {
        return None;
    }
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = |b: u8| (b as char).to_digit(16);
        match (
            bytes[i],
            bytes.get(i + 1).copied().and_then(hex),
            bytes.get(i + 2).copied().and_then(hex),
        ) {
            (b'%', Some(h), Some(l)) => {
                out.push((h * 16 + l) as u8);
                i += 3;
            }
            (b, _, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8(out).ok().map(|p| normalize(Path::new(&p)))
}

/// The `file:` URI of a local path.
pub fn uri_of(path: &Path) -> Option<Uri> {
    let mut s = String::from("file://");
    for b in path.to_str()?.bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => s.push(b as char),
            _ => s.push_str(&format!("%{b:02X}")),
        }
    }
    Uri::from_str(&s).ok()
}

/// The protocol's position of a byte offset (clamped to the text, and to a char boundary).
pub fn position(text: &str, offset: usize) -> Position {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    Position {
        line: before.matches('\n').count() as u32,
        character: before[line_start..].encode_utf16().count() as u32,
    }
}

pub fn range(text: &str, start: usize, end: usize) -> Range {
    Range {
        start: position(text, start),
        end: position(text, end.max(start)),
    }
}

/// The byte offset of a protocol position; `None` past the last line. A character past the
/// end of its line is the line's end (as the protocol asks).
pub fn offset(text: &str, pos: Position) -> Option<usize> {
    let mut line_start = 0;
    for _ in 0..pos.line {
        line_start += text[line_start..].find('\n')? + 1;
    }
    let line_end = text[line_start..].find('\n').map_or(text.len(), |i| line_start + i);
    let mut units = 0;
    for (i, c) in text[line_start..line_end].char_indices() {
        if units >= pos.character as usize {
            return Some(line_start + i);
        }
        units += c.len_utf16();
    }
    Some(line_end)
}

/// A character of a dotted name (`gbuf.albedo`).
pub fn name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_' || c == '.'
}

/// A character of a file path as pipelines write them (`lib/brdf.wgsl#fs_main`).
pub fn path_char(c: char) -> bool {
    name_char(c) || matches!(c, '/' | '-' | '#')
}

/// The byte range of the word around `cursor` made of `part` characters.
pub fn word_around(text: &str, cursor: usize, part: fn(char) -> bool) -> (usize, usize) {
    let start = text[..cursor].rfind(|c: char| !part(c)).map_or(0, |i| i + 1);
    let end = text[cursor..].find(|c: char| !part(c)).map_or(text.len(), |i| cursor + i);
    (start, end)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_count_utf16_units_and_round_trip() {
        let text = "ab\n×😀c\nlast";
        let c = text.find('c').unwrap();
        let p = position(text, c);
        assert_eq!((p.line, p.character), (1, 3)); // × is 1 unit, 😀 is 2
        assert_eq!(offset(text, p), Some(c));
        assert_eq!(
            offset(text, Position { line: 1, character: 99 }),
            Some(text.find("\nlast").unwrap())
        );
        assert_eq!(offset(text, Position { line: 9, character: 0 }), None);
    }

    #[test]
    fn uris_and_paths_convert_both_ways() {
        let p = Path::new("/tmp/a b/x#1.lbp");
        let u = uri_of(p).unwrap();
        assert_eq!(u.as_str(), "file:///tmp/a%20b/x%231.lbp");
        assert_eq!(path_of(&u).unwrap(), p);
        assert!(path_of(&Uri::from_str("untitled:Untitled-1").unwrap()).is_none());
    }
}
