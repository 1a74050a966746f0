//! Language server, words under the cursor: the key a line is filling, and names the IR
//! keeps no place for — a pass named by `after` or `replace`, a file named by `use` — read
//! from the line they are written on.

use super::handlers::At;
use super::index::Kind;
use super::text::{name_char, word_around};
use super::Server;
use std::path::{Path, PathBuf};

/// The key a line is filling: an LBP line's first word, or the last `key:` of a RON line.
pub fn key_of(line: &str) -> Option<String> {
    let word = |s: &str| s.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect::<String>();
    if let Some(i) = line.rfind(':') {
        let before = line[..i].trim_end();
        let start = before
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .map_or(0, |j| j + 1);
        let k = word(&before[start..]);
        if !k.is_empty() && !before[..start].trim_end().ends_with('"') {
            return Some(k);
        }
    }
    Some(word(line.trim_start())).filter(|w| !w.is_empty())
}

/// The line around a byte offset, and its key: an LBP line's first word, or the last
/// `key:` of a RON line.
pub fn line_key(text: &str, at: usize) -> (&str, Option<String>) {
    let start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let end = text[at..].find('\n').map_or(text.len(), |i| at + i);
    let line = &text[start..end];
    (line, key_of(&text[start..at]))
}

impl Server {
    /// A symbol named where the IR keeps no span: `after`/`replace` targets (passes, or any
    /// declaration `replace` names), read from the word at the cursor.
    pub(super) fn named_at(&self, path: &Path, at: &At) -> Option<usize> {
        let ix = &self.indexes.get(path)?.1;
        let text = &ix.sources.get(at.file).text;
        let (_, key) = line_key(text, at.offset);
        let (a, b) = word_around(text, at.offset, name_char);
        let word = &text[a..b];
        match key.as_deref()? {
            "after" => ix.find(Kind::Pass, word),
            "replace" => [Kind::Pass, Kind::Param, Kind::Resource, Kind::Sampler, Kind::Variant, Kind::Let]
                .into_iter()
                .find_map(|k| ix.find(k, word)),
            _ => None,
        }
    }

    /// The pipeline file a `use` line names, resolved beside the pipeline, when it exists.
    pub(super) fn used_file_at(&self, path: &Path, at: &At) -> Option<PathBuf> {
        let ix = &self.indexes.get(path)?.1;
        let text = &ix.sources.get(at.file).text;
        let (line, key) = line_key(text, at.offset);
        if key.as_deref() != Some("use") {
            return None;
        }
        let quoted = line.split('"').nth(1)?;
        let here = Path::new(&ix.sources.get(at.file).name);
        let file = here.parent()?.join(quoted);
        self.exists(&file).then_some(file)
    }
}
