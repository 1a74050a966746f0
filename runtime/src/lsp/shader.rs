//! Language server, inside shaders: hover on a `frame.` field (its declaration and comment in
//! `lib/frame.wgsl`) and on a global that a pipeline using the shader binds (the declaration
//! it binds to, by the binding rule), and definition from such a global to that declaration.

use super::index::{Index, Kind};
use super::text::{offset, path_of, range, word_around};
use super::Server;
use lightbench_compiler::shader::include;
use lightbench_compiler::vfs::Vfs;
use lsp_types::{GotoDefinitionResponse, Hover, HoverContents, MarkupContent, MarkupKind, TextDocumentPositionParams};
use std::path::{Path, PathBuf};

pub fn is_shader(path: &Path) -> bool {
    matches!(path.extension().and_then(|e| e.to_str()), Some("wgsl" | "frag" | "vert" | "comp"))
}

/// The identifier at a byte offset, with where it starts.
fn word_at(text: &str, at: usize) -> Option<(usize, &str)> {
    let (start, end) = word_around(text, at, |c| c.is_ascii_alphanumeric() || c == '_');
    (start < end).then(|| (start, &text[start..end]))
}

/// A declaration's name as a shader global (the binding rule): other characters become `_`.
fn global_name(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '_' { c } else { '_' })
        .collect()
}

/// The symbol a shader global binds to in this pipeline: a resource (or its previous frame),
/// a sampler, or a parameter (its block field: the last segment or the whole identifier).
fn bound(ix: &Index, word: &str) -> Option<usize> {
    let named = |k: Kind, w: &str| ix.symbols.iter().position(|s| s.kind == k && global_name(&s.name) == w);
    let field = |w: &str| {
        let last = |s: &str| s.rsplit('.').next().unwrap_or(s).to_string();
        ix.symbols
            .iter()
            .position(|s| s.kind == Kind::Param && (last(&s.name) == w || global_name(&s.name) == w))
    };
    named(Kind::Resource, word)
        .or_else(|| word.strip_suffix("_prev").and_then(|w| named(Kind::Resource, w)))
        .or_else(|| named(Kind::Sampler, word))
        .or_else(|| field(word))
}

impl Server {
    /// The shader text and the word under the cursor, with the pipelines whose last check read
    /// the shader.
    fn shader_word(&mut self, pos: &TextDocumentPositionParams) -> Option<(PathBuf, String, usize, String, Vec<PathBuf>)> {
        let path = path_of(&pos.text_document.uri)?;
        let text = self.text(&path)?;
        let at = offset(&text, pos.position)?;
        let (start, word) = word_at(&text, at)?;
        let word = word.to_string();
        let mut readers: Vec<PathBuf> = self
            .deps
            .iter()
            .filter(|(_, d)| d.contains(&path))
            .map(|(p, _)| p.clone())
            .collect();
        readers.sort();
        Some((path, text, start, word, readers))
    }

    pub(super) fn shader_hover(&mut self, pos: TextDocumentPositionParams) -> Option<Hover> {
        let (path, text, start, word, readers) = self.shader_word(&pos)?;
        let shown = if text[..start].ends_with("frame.") {
            frame_field(&self.frame_source(&path)?, &word)?
        } else {
            let mut lines = vec![];
            for p in readers {
                let Some(ix) = self.index(&p) else { continue };
                if let Some(sym) = bound(ix, &word) {
                    lines.push(format!("bound by `{}`:\n\n{}", p.display(), ix.symbols[sym].hover));
                }
            }
            (!lines.is_empty()).then(|| lines.join("\n\n---\n\n"))?
        };
        Some(Hover {
            contents: HoverContents::Markup(MarkupContent {
                kind: MarkupKind::Markdown,
                value: shown,
            }),
            range: Some(range(&text, start, start + word.len())),
        })
    }

    pub(super) fn shader_definition(&mut self, pos: TextDocumentPositionParams) -> Option<GotoDefinitionResponse> {
        if let Some(included) = self.included_at(&pos) {
            return Some(GotoDefinitionResponse::Scalar(included));
        }
        let (_, _, _, word, readers) = self.shader_word(&pos)?;
        let mut found = vec![];
        for p in readers {
            let Some(ix) = self.index(&p) else { continue };
            if let Some(sym) = bound(ix, &word) {
                found.extend(ix.location(ix.symbols[sym].decl));
            }
        }
        (!found.is_empty()).then_some(GotoDefinitionResponse::Array(found))
    }

    /// A shader file's entry points with the files they are written in, its `#include`d files
    /// searched too (as the compiler splices them; each file once).
    pub(super) fn entries_in(&self, shader: &Path) -> Vec<(String, &'static str, PathBuf, usize)> {
        let (mut out, mut todo, mut seen) = (vec![], vec![shader.to_path_buf()], vec![]);
        while let Some(f) = todo.pop() {
            if seen.contains(&f) || seen.len() > 64 {
                continue;
            }
            seen.push(f.clone());
            let Some(text) = self.text(&f) else {
                continue;
            };
            out.extend(
                super::index::entry_points(&text, &f)
                    .into_iter()
                    .map(|(n, st, at)| (n, st, f.clone(), at)),
            );
            let targets = text.lines().filter_map(|l| include::included(l).flatten());
            todo.extend(targets.filter_map(|t| self.include_target(&f, t)));
        }
        out
    }

    /// Where an `#include "target"` of `from` resolves: the nearest folder above it holding
    /// the path (include paths are relative to the shader root, which they may not leave, as
    /// the compiler confines them; links resolved, as it does).
    fn include_target(&self, from: &Path, target: &str) -> Option<PathBuf> {
        include::confined(target).ok()?;
        // Folders inside the workspace only (without one: the shader's folder and its parent).
        let dir = from.parent()?;
        let inside = |d: &Path| match self.roots.is_empty() {
            true => d == dir || Some(d) == dir.parent(),
            false => self.roots.iter().any(|r| d.starts_with(r)),
        };
        let root = dir.ancestors().take_while(|d| inside(d)).find(|d| self.exists(&d.join(target)))?;
        let file = root.join(target);
        self.overlay.within(root, &file).ok().map(|_| file)
    }

    /// On an `#include "path"` line: the included file (paths are relative to the shader root,
    /// the nearest folder above the shader in which the path exists).
    fn included_at(&self, pos: &TextDocumentPositionParams) -> Option<lsp_types::Location> {
        let path = path_of(&pos.text_document.uri)?;
        let text = self.text(&path)?;
        let target = include::included(text.lines().nth(pos.position.line as usize)?)??;
        let file = self.include_target(&path, target)?;
        Some(lsp_types::Location {
            uri: super::text::uri_of(&file)?,
            range: Default::default(),
        })
    }

    /// `lib/frame.wgsl` under the shader root of the shader's folder (or above it).
    fn frame_source(&self, shader: &Path) -> Option<String> {
        self.text(&self.include_target(shader, "lib/frame.wgsl")?)
    }
}

/// A field of `struct Frame`: its declaration and the comment lines above it.
fn frame_field(frame: &str, field: &str) -> Option<String> {
    let body = frame.split("struct Frame {").nth(1)?.split("\n}").next()?;
    let lines: Vec<&str> = body.lines().collect();
    let i = lines.iter().position(|l| l.trim_start().starts_with(&format!("{field}:")))?;
    let comments: Vec<&str> = lines[..i]
        .iter()
        .rev()
        .take_while(|l| l.trim_start().starts_with("//"))
        .map(|l| l.trim_start().trim_start_matches("//").trim())
        .collect();
    let doc: Vec<&str> = comments.into_iter().rev().collect();
    Some(format!(
        "**frame** `{}`\n\n{}",
        lines[i].trim().trim_end_matches(','),
        doc.join(" ")
    ))
}
