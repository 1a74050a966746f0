//! Language server, completion: what may be written at the cursor of a pipeline document,
//! by the key its line is filling (both front ends name keys alike): resource names after
//! `reads`/`color`/`depth`/`writes`, parameters after `params`, passes after `after`,
//! variants and their options in conditions and choices, the entry points of the pass's
//! shader after `vertex`, `fragment` or `entry`, shader files in a pass's quotes, pipeline
//! files after `use`, formats after `texture NAME:`, the grammar's top-level keywords
//! between items and the keys of a pass kind (the syntax tree's own list) inside one; in a
//! scene file, effects and light kinds. Each item replaces the whole word at the cursor.

use super::index::{Index, Kind, ShaderUse};
use super::shader::is_shader;
use super::text::{name_char, offset, path_char, path_of, range, word_around};
use super::words::key_of;
use super::Server;
use lightbench_compiler::front::lbp::grammar as lbp_grammar;
use lightbench_compiler::scene::{file_kind, FileKind};
use lsp_types::{CompletionItem, CompletionItemKind, CompletionResponse, CompletionTextEdit, TextDocumentPositionParams, TextEdit};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

impl Server {
    /// Every item replaces the whole word at the cursor (a dotted name, or a path), so that
    /// `gbuf.alb` becomes `gbuf.albedo` whatever a client counts as a word.
    pub(super) fn complete(&mut self, pos: TextDocumentPositionParams) -> Option<CompletionResponse> {
        let path = path_of(&pos.text_document.uri)?;
        let text = self.text(&path)?;
        let cursor = offset(&text, pos.position)?;
        let line = &text[text[..cursor].rfind('\n').map_or(0, |i| i + 1)..cursor];
        let key = key_of(line);
        let (labels, part) = if file_kind(&path, Some(&text)) == FileKind::Scene {
            (scene_items(key.as_deref()), name_char as WordChar)
        } else {
            self.pipeline_items(&path, &text, cursor, line, key.as_deref())?
        };
        let (a, b) = word_around(&text, cursor, part);
        let replaced = range(&text, a, b);
        let items = labels.into_iter().map(|(label, kind, detail)| CompletionItem {
            kind: Some(kind),
            detail,
            filter_text: Some(label.clone()),
            text_edit: Some(CompletionTextEdit::Edit(TextEdit::new(replaced, label.clone()))),
            label,
            ..Default::default()
        });
        Some(CompletionResponse::Array(items.collect()))
    }

    /// What may be written at the cursor of a pipeline document, and what a word is there.
    fn pipeline_items(&mut self, path: &Path, text: &str, cursor: usize, line: &str, key: Option<&str>) -> Option<(Vec<Label>, WordChar)> {
        self.index(path)?;
        let ix = &self.indexes.get(path)?.1;
        let names = |k: Kind, what: CompletionItemKind| ix.names(k).into_iter().map(move |n| item(n, what));
        let first = line.trim_start().split(|c: char| !name_char(c)).next().unwrap_or("");
        let in_quotes = line.matches('"').count() % 2 == 1;
        // In an LBP choice (`fragment match(v) { a: fs_a, b: fs_| }`) an arm's value is the
        // line's key's; its options are the variant's.
        let key = match line.contains("match(") {
            true if line.rsplit(['{', ',']).next().is_some_and(|arm| arm.contains(':')) => Some(first),
            true => None,
            false => key,
        };
        let items: Vec<Label> = match key {
            Some("reads" | "color" | "depth" | "writes" | "output" | "hdr_output") => {
                names(Kind::Resource, CompletionItemKind::VARIABLE).collect()
            }
            Some("bind") => names(Kind::Resource, CompletionItemKind::VARIABLE)
                .chain(names(Kind::Sampler, CompletionItemKind::VARIABLE))
                .collect(),
            Some("params") => names(Kind::Param, CompletionItemKind::PROPERTY).collect(),
            Some("after") => names(Kind::Pass, CompletionItemKind::FUNCTION).collect(),
            // A condition: a named one, or the start of one written out.
            Some("when" | "let") if matches!(open_call(line), None | Some("all" | "any")) => names(Kind::Let, CompletionItemKind::CONSTANT)
                .chain(CONDITION_WORDS.iter().map(|w| item(w, CompletionItemKind::KEYWORD)))
                .collect(),
            Some("vertex" | "fragment" | "entry") => self.entries_near(path, ix, cursor),
            Some("use") => return Some((self.files_beside(path), path_char)),
            Some("shader") | Some("raster" | "fullscreen" | "compute") if in_quotes => return Some((self.shader_files(path), path_char)),
            Some("format") => formats(),
            _ if first == "texture" && at_format(line) => formats(),
            _ if line.contains("variant(") || line.contains("match(") => variant_items(ix, line),
            _ if depth_at(text, cursor) == 0 && !line.trim_start().contains(' ') && path.extension().is_some_and(|e| e == "lbp") => {
                lbp_grammar::top_level_keywords()
                    .into_iter()
                    .map(|k| item(k, CompletionItemKind::KEYWORD))
                    .collect()
            }
            _ => pass_keys(text, cursor),
        };
        Some((items, name_char))
    }

    /// Entry points of the shader of the pass around the cursor; in a template, of the
    /// shaders its attributes name an entry of or a file for.
    fn entries_near(&self, path: &Path, ix: &Index, cursor: usize) -> Vec<Label> {
        let file = ix.sources.find(&path.display().to_string());
        let around = |kind: Kind| {
            ix.symbols.iter().find(|s| {
                s.kind == kind && Some(s.extent.file) == file && (s.extent.start as usize) <= cursor && cursor <= s.extent.end as usize
            })
        };
        let files: BTreeSet<&str> = match (around(Kind::Pass), around(Kind::Template)) {
            (Some(pass), _) => ix
                .shaders
                .iter()
                .filter(|u| u.pass == pass.name)
                .map(|u| u.file.value.as_str())
                .collect(),
            (None, Some(t)) => {
                let inside =
                    |s: &lightbench_compiler::span::Span| s.file == t.extent.file && t.extent.start <= s.start && s.end <= t.extent.end;
                let named_here = |u: &&ShaderUse| inside(&u.file.span) || u.entry.as_ref().is_some_and(|e| inside(&e.span));
                ix.shaders.iter().filter(named_here).map(|u| u.file.value.as_str()).collect()
            }
            _ => return vec![],
        };
        files
            .into_iter()
            .flat_map(|f| self.shader_entries(path, f))
            .map(|(n, stage, _)| (n, CompletionItemKind::FUNCTION, Some(stage.to_string())))
            .collect()
    }

    /// Shader files below the pipeline's shader folder, as a pass names them.
    fn shader_files(&self, pipeline: &Path) -> Vec<Label> {
        let root = lightbench_compiler::shader_root_for(self.overlay.as_ref(), pipeline, None);
        let found = lightbench_compiler::files_below(&root, is_shader).unwrap_or_default();
        relative(&root, found)
    }

    /// Pipeline files beside this one and below (what `use` may name), not itself.
    fn files_beside(&self, pipeline: &Path) -> Vec<Label> {
        let Some(dir) = pipeline.parent() else { return vec![] };
        let found = lightbench_compiler::pipeline_files(dir).unwrap_or_default();
        let others = found.into_iter().filter(|p| {
            let text = self.text(p);
            p != pipeline && file_kind(p, text.as_deref()) == FileKind::Pipeline
        });
        relative(dir, others.collect())
    }
}

/// Files as completions, named relative to `root`.
fn relative(root: &Path, files: Vec<PathBuf>) -> Vec<Label> {
    let named = files.iter().filter_map(|f| f.strip_prefix(root).ok());
    named.map(|f| (f.display().to_string(), CompletionItemKind::FILE, None)).collect()
}

/// A completion's label (what is inserted), kind and detail.
type Label = (String, CompletionItemKind, Option<String>);

/// What a character of the word a completion replaces may be.
type WordChar = fn(char) -> bool;

/// Braces open at `cursor` (0: between top-level items), strings and comments skipped.
fn depth_at(text: &str, cursor: usize) -> usize {
    let mut depth = 0usize;
    for line in text[..cursor].split('\n') {
        let code = line.split("//").next().unwrap_or("");
        let mut quoted = false;
        for c in code.chars() {
            match c {
                '"' => quoted = !quoted,
                '{' if !quoted => depth += 1,
                '}' if !quoted => depth = depth.saturating_sub(1),
                _ => {}
            }
        }
    }
    depth
}

/// Conditions' words (a name of a `let` stands beside them).
const CONDITION_WORDS: [&str; 9] = ["all", "any", "not", "variant", "effect", "light", "toggle", "reflective", "blended"];

/// The call whose parentheses the end of `line` is inside (`all`, `variant`…), if any.
fn open_call(line: &str) -> Option<&str> {
    let mut open: Vec<&str> = vec![];
    for (i, c) in line.char_indices() {
        match c {
            '(' => open.push(line[..i].rsplit(|c: char| !name_char(c)).next().unwrap_or("")),
            ')' => _ = open.pop(),
            _ => {}
        }
    }
    open.pop()
}

/// Whether an LBP `texture NAME: ` line is at its format (the first word after the colon).
fn at_format(line: &str) -> bool {
    line.split_once(':').is_some_and(|(_, rest)| !rest.trim().contains(' '))
}

/// Every texture format.
fn formats() -> Vec<Label> {
    let names = lightbench_compiler::format::TextureFormat::NAMES;
    names.iter().map(|n| item(n, CompletionItemKind::CONSTANT)).collect()
}

/// In a scene file: effects in `effects: [..]`, the light kinds a scene writes elsewhere.
fn scene_items(key: Option<&str>) -> Vec<Label> {
    use lightbench_compiler::ir::{Effect, LightKind};
    if key == Some("effects") {
        return Effect::NAMES.iter().map(|e| item(e, CompletionItemKind::ENUM_MEMBER)).collect();
    }
    LightKind::PUNCTUAL_NAMES
        .iter()
        .map(|k| item(k, CompletionItemKind::STRUCT))
        .collect()
}

fn item(label: &str, kind: CompletionItemKind) -> Label {
    (label.to_string(), kind, None)
}

/// After `variant(` the variants; after `variant(v, ` or inside `match(v) {` v's options.
fn variant_items(ix: &Index, line: &str) -> Vec<Label> {
    let open = line
        .rfind("variant(")
        .map(|i| i + 8)
        .or_else(|| line.rfind("match(").map(|i| i + 6))
        .unwrap_or(0);
    let inside = &line[open..];
    let named = inside.split([',', ')']).next().unwrap_or("").trim().trim_matches('"');
    let chose = inside.contains(',') || inside.contains('{');
    match ix.find(Kind::Variant, named).filter(|_| chose) {
        Some(v) => ix
            .symbols
            .iter()
            .filter(|s| s.kind == Kind::Option(v))
            .map(|s| item(&s.name, CompletionItemKind::ENUM_MEMBER))
            .collect(),
        None => ix
            .names(Kind::Variant)
            .into_iter()
            .map(|n| item(n, CompletionItemKind::ENUM))
            .collect(),
    }
}

/// The keys of the pass kind the cursor is in (the nearest pass word before it).
fn pass_keys(text: &str, cursor: usize) -> Vec<Label> {
    let before = &text[..cursor];
    let kinds = [
        ("raster", "Raster"),
        ("fullscreen", "Fullscreen"),
        ("compute", "Compute"),
        ("Raster(", "Raster"),
        ("Fullscreen(", "Fullscreen"),
        ("Compute(", "Compute"),
    ];
    let kind = kinds
        .iter()
        .filter_map(|(w, k)| before.rfind(w).map(|i| (i, *k)))
        .max()
        .map(|(_, k)| k);
    let Some(kind) = kind else { return vec![] };
    lightbench_compiler::syntax::lower::pass_keys(kind)
        .into_iter()
        .map(|k| item(k, CompletionItemKind::KEYWORD))
        .collect()
}
