//! Language server, completion: what may be written at the cursor of a pipeline document,
//! by the key its line is filling (both front ends name keys alike): resource names after
//! `reads`/`color`/`depth`/`writes`, parameters after `params`, variants and their options
//! in conditions and choices, the entry points of the pass's shader after `vertex`,
//! `fragment` or `entry`, and the keys of a pass kind (the syntax tree's own list) elsewhere;
//! in a scene file, effects and light kinds.

use super::index::{Index, Kind};
use super::text::{offset, path_of};
use super::Server;
use lightbench_compiler::scene::{file_kind, FileKind};
use lsp_types::{CompletionItem, CompletionItemKind, CompletionResponse, TextDocumentPositionParams};

impl Server {
    pub(super) fn complete(&mut self, pos: TextDocumentPositionParams) -> Option<CompletionResponse> {
        let path = path_of(&pos.text_document.uri)?;
        let text = self.text(&path)?;
        let cursor = offset(&text, pos.position)?;
        let line = &text[text[..cursor].rfind('\n').map_or(0, |i| i + 1)..cursor];
        let key = key_of(line);
        if file_kind(&path, Some(&text)) == FileKind::Scene {
            return Some(CompletionResponse::Array(scene_items(key.as_deref())));
        }
        self.index(&path)?;
        let ix = &self.indexes.get(&path)?.1;
        let names = |k: Kind, what: CompletionItemKind| ix.names(k).into_iter().map(move |n| item(n, what));
        let items: Vec<CompletionItem> = match key.as_deref() {
            Some("reads" | "color" | "depth" | "writes" | "output" | "hdr_output") => {
                names(Kind::Resource, CompletionItemKind::VARIABLE).collect()
            }
            Some("bind") => names(Kind::Resource, CompletionItemKind::VARIABLE)
                .chain(names(Kind::Sampler, CompletionItemKind::VARIABLE))
                .collect(),
            Some("params") => names(Kind::Param, CompletionItemKind::PROPERTY).collect(),
            Some("vertex" | "fragment" | "entry") => self.entries_near(&path, ix, &text, cursor),
            _ if line.contains("variant(") || line.contains("match(") => variant_items(ix, line),
            _ => pass_keys(&text, cursor),
        };
        Some(CompletionResponse::Array(items))
    }

    /// Entry points of the shader of the pass around the cursor.
    fn entries_near(&self, path: &std::path::Path, ix: &Index, text: &str, cursor: usize) -> Vec<CompletionItem> {
        let file = ix.sources.find(&path.display().to_string());
        let pass = ix.symbols.iter().find(|s| {
            s.kind == Kind::Pass && Some(s.extent.file) == file && (s.extent.start as usize) <= cursor && cursor <= s.extent.end as usize
        });
        let Some(pass) = pass else { return vec![] };
        let _ = text;
        let files: std::collections::BTreeSet<&str> = ix
            .shaders
            .iter()
            .filter(|u| u.pass == pass.name)
            .map(|u| u.file.value.as_str())
            .collect();
        files
            .into_iter()
            .flat_map(|f| self.shader_entries(path, f))
            .map(|(n, stage, _)| CompletionItem {
                detail: Some(stage.to_string()),
                ..item(&n, CompletionItemKind::FUNCTION)
            })
            .collect()
    }
}

/// In a scene file: effects in `effects: [..]`, the light kinds a scene writes elsewhere.
fn scene_items(key: Option<&str>) -> Vec<CompletionItem> {
    use lightbench_compiler::ir::{Effect, LightKind};
    if key == Some("effects") {
        return Effect::NAMES.iter().map(|e| item(e, CompletionItemKind::ENUM_MEMBER)).collect();
    }
    LightKind::PUNCTUAL_NAMES
        .iter()
        .map(|k| item(k, CompletionItemKind::STRUCT))
        .collect()
}

fn item(label: &str, kind: CompletionItemKind) -> CompletionItem {
    CompletionItem {
        label: label.to_string(),
        kind: Some(kind),
        ..Default::default()
    }
}

/// The key a line is filling: an LBP line's first word, or the last `key:` of a RON line.
fn key_of(line: &str) -> Option<String> {
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

/// After `variant(` the variants; after `variant(v, ` or inside `match(v) {` v's options.
fn variant_items(ix: &Index, line: &str) -> Vec<CompletionItem> {
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
fn pass_keys(text: &str, cursor: usize) -> Vec<CompletionItem> {
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
