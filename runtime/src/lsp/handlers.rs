//! Language server, requests: hover, definition, references, rename, completion, document
//! symbols and formatting over a pipeline document's index. A request that cannot be read is
//! `InvalidParams`, an unknown one `MethodNotFound`; a bug is an `InternalError` answer, and
//! the server goes on.

use super::index::{Index, Kind};
use super::text::{offset, path_of, range, uri_of};
use super::Server;
use lightbench_compiler::scene::{file_kind, FileKind};
use lightbench_compiler::span::Span;
use lsp_server::{ErrorCode, Request, Response};
use lsp_types::request::{self as req, Request as _};
use lsp_types::*;
use serde::de::DeserializeOwned;
use serde_json::Value;
use std::path::{Path, PathBuf};

type Answer = Result<Value, (ErrorCode, String)>;

pub fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        rename_provider: Some(OneOf::Left(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        document_formatting_provider: Some(OneOf::Left(true)),
        completion_provider: Some(CompletionOptions {
            trigger_characters: Some(["(", ",", " ", "\"", "#"].map(String::from).to_vec()),
            ..Default::default()
        }),
        ..Default::default()
    }
}

pub fn answer(server: &mut Server, r: Request) -> Response {
    let id = r.id.clone();
    let answered = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| dispatch(server, r)));
    match answered {
        Ok(Ok(v)) => Response::new_ok(id, v),
        Ok(Err((code, msg))) => Response::new_err(id, code as i32, msg),
        Err(_) => Response::new_err(id, ErrorCode::InternalError as i32, "internal error".into()),
    }
}

fn params<P: DeserializeOwned>(v: Value) -> Result<P, (ErrorCode, String)> {
    serde_json::from_value(v).map_err(|e| (ErrorCode::InvalidParams, e.to_string()))
}

fn json<T: serde::Serialize>(v: T) -> Answer {
    serde_json::to_value(v).map_err(|e| (ErrorCode::InternalError, e.to_string()))
}

fn dispatch(server: &mut Server, r: Request) -> Answer {
    match r.method.as_str() {
        req::HoverRequest::METHOD => {
            let at = params::<HoverParams>(r.params)?.text_document_position_params;
            json(if in_shader(&at) {
                server.shader_hover(at)
            } else {
                server.hover(at)
            })
        }
        req::GotoDefinition::METHOD => {
            let at = params::<GotoDefinitionParams>(r.params)?.text_document_position_params;
            json(if in_shader(&at) {
                server.shader_definition(at)
            } else {
                server.definition(at)
            })
        }
        req::References::METHOD => json(server.references(params::<ReferenceParams>(r.params)?.text_document_position)),
        req::Rename::METHOD => server.rename(params::<RenameParams>(r.params)?),
        req::Completion::METHOD => json(server.complete(params::<CompletionParams>(r.params)?.text_document_position)),
        req::DocumentSymbolRequest::METHOD => json(server.symbols(&params::<DocumentSymbolParams>(r.params)?.text_document)),
        req::Formatting::METHOD => json(server.format(&params::<DocumentFormattingParams>(r.params)?.text_document)),
        m => Err((ErrorCode::MethodNotFound, format!("unknown method `{m}`"))),
    }
}

fn in_shader(at: &TextDocumentPositionParams) -> bool {
    path_of(&at.text_document.uri).is_some_and(|p| super::shader::is_shader(&p))
}

/// A position in a pipeline document, resolved against its index.
pub(super) struct At {
    pub file: usize,
    pub offset: usize,
}

impl Server {
    /// The index of a pipeline document: rebuilt when its text changed and still lowers,
    /// else the last one that did.
    pub(super) fn index(&mut self, path: &Path) -> Option<&Index> {
        let text = self.text(path)?;
        let fresh = self.indexes.get(path).is_some_and(|(t, _)| *t == text);
        if !fresh && file_kind(path, Some(&text)) == FileKind::Pipeline {
            let mut s = self.workspace.session();
            if let Some(p) = s.load_pipeline(path).filter(|_| !s.diags.has_errors()) {
                self.indexes.insert(path.to_path_buf(), (text, Index::of(&p, s.sources)));
            }
        }
        self.indexes.get(path).map(|(_, ix)| ix)
    }

    fn at(&mut self, pos: &TextDocumentPositionParams) -> Option<(PathBuf, At)> {
        let path = path_of(&pos.text_document.uri)?;
        let ix = self.index(&path)?;
        let file = ix.sources.find(&path.display().to_string())?;
        let offset = offset(&ix.sources.get(file).text, pos.position)?;
        Some((path, At { file, offset }))
    }

    fn hover(&mut self, pos: TextDocumentPositionParams) -> Option<Hover> {
        let (path, at) = self.at(&pos)?;
        if let Some(used) = self.used_file_at(&path, &at) {
            return self.use_hover(&path, &used);
        }
        let ix = self.indexes.get(&path).map(|(_, ix)| ix)?;
        let named = ix.at(at.file, at.offset).or_else(|| self.named_at(&path, &at));
        let inside = |s: &Span| s.file == at.file && s.start as usize <= at.offset && at.offset <= s.end as usize;
        let (text, span) = if let Some(sym) = named {
            let s = &ix.symbols[sym];
            let mut text = s.hover.clone();
            let key = format!("{}:{}", s.kind.word(), s.name);
            if let Some(facts) = self.default_runs.get(&path).and_then(|r| r.get(&key)) {
                text += &format!("\n\nOn the default scene (`cornell` at its size, default options): {facts}");
            }
            (text, ix.uses_of(sym).find(inside))
        } else if let Some(f) = ix.formats.iter().find(|f| inside(&f.span)) {
            (format_hover(f.value, &self.profile), Some(f.span))
        } else {
            let u = ix.shader_at(at.file, at.offset)?;
            let entries = self.shader_entries(&path, &u.file.value);
            let list: Vec<String> = entries.iter().map(|(n, stage, _)| format!("- `{n}` ({stage})")).collect();
            (
                format!("**shader** `{}` (pass `{}`)\n\n{}", u.file.value, u.pass, list.join("\n")),
                Some(u.file.span),
            )
        };
        let ix = self.indexes.get(&path).map(|(_, ix)| ix)?;
        Some(Hover {
            contents: HoverContents::Markup(MarkupContent {
                kind: MarkupKind::Markdown,
                value: text,
            }),
            range: span.map(|s| range(&ix.sources.get(s.file).text, s.start as usize, s.end as usize)),
        })
    }

    /// A `use`d pipeline: what it declares that this one takes.
    fn use_hover(&self, path: &Path, used: &Path) -> Option<Hover> {
        let ix = &self.indexes.get(path)?.1;
        let file = ix.sources.find(&used.display().to_string())?;
        let count = |k: Kind| ix.symbols.iter().filter(|s| s.kind == k && s.decl.file == file).count();
        let value = format!(
            "**uses** `{}`: {} parameters, {} resources, {} passes and {} variants declared there are this pipeline's too",
            self.shown(used),
            count(Kind::Param),
            count(Kind::Resource),
            count(Kind::Pass),
            count(Kind::Variant)
        );
        Some(Hover {
            contents: HoverContents::Markup(MarkupContent {
                kind: MarkupKind::Markdown,
                value,
            }),
            range: None,
        })
    }

    fn definition(&mut self, pos: TextDocumentPositionParams) -> Option<GotoDefinitionResponse> {
        let (path, at) = self.at(&pos)?;
        if let Some(file) = self.used_file_at(&path, &at) {
            let uri = uri_of(&file)?;
            return Some(GotoDefinitionResponse::Scalar(Location {
                uri,
                range: Range::default(),
            }));
        }
        let named = self
            .indexes
            .get(&path)?
            .1
            .at(at.file, at.offset)
            .or_else(|| self.named_at(&path, &at));
        let ix = self.indexes.get(&path).map(|(_, ix)| ix)?;
        if let Some(sym) = named {
            return Some(GotoDefinitionResponse::Scalar(ix.location(ix.symbols[sym].decl)?));
        }
        let u = ix.shader_at(at.file, at.offset)?;
        let (file, entry) = (u.file.value.clone(), u.entry.as_ref().map(|e| e.value.clone()));
        let entry = entry.or_else(|| file.split_once('#').map(|(_, e)| e.to_string()));
        let shader = self.shader_path(&path, &file);
        // The entry point where it is written (maybe an included file), else the file's top.
        let found = entry.and_then(|e| self.entries_in(&shader).into_iter().find(|(n, _, _, _)| *n == e));
        let (target, at) = found.map_or((shader, 0), |(_, _, f, at)| (f, at));
        let text = self.text(&target)?;
        Some(GotoDefinitionResponse::Scalar(Location {
            uri: uri_of(&target)?,
            range: range(&text, at, at),
        }))
    }

    fn references(&mut self, pos: TextDocumentPositionParams) -> Option<Vec<Location>> {
        let (path, at) = self.at(&pos)?;
        let sym = self
            .indexes
            .get(&path)?
            .1
            .at(at.file, at.offset)
            .or_else(|| self.named_at(&path, &at))?;
        let ix = self.indexes.get(&path).map(|(_, ix)| ix)?;
        Some(ix.uses_of(sym).filter_map(|s| ix.location(s)).collect())
    }

    /// Rename a resource, parameter, sampler or pass declared in this file, everywhere this
    /// file names it.
    fn rename(&mut self, p: RenameParams) -> Answer {
        let refuse = |m: &str| Err((ErrorCode::InvalidParams, m.to_string()));
        let name_ok = |n: &str| !n.is_empty() && n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.');
        if !name_ok(&p.new_name) {
            return refuse("a name is letters, digits, `_` and `.`");
        }
        let Some((path, at)) = self.at(&p.text_document_position) else {
            return json(Value::Null);
        };
        let Some(ix) = self.indexes.get(&path).map(|(_, ix)| ix) else {
            return json(Value::Null);
        };
        let Some(sym) = ix.at(at.file, at.offset) else {
            return refuse("nothing to rename here");
        };
        let s = &ix.symbols[sym];
        if !matches!(
            s.kind,
            Kind::Resource | Kind::Param | Kind::Sampler | Kind::Pass | Kind::Let | Kind::Template
        ) || s.decl.file != at.file
        {
            return refuse(
                "only resources, parameters, samplers, passes, named conditions and templates declared in this file can be renamed",
            );
        }
        let taken = |k: Kind| ix.find(k, &p.new_name).is_some_and(|other| other != sym);
        // Resources and samplers are bound by one namespace of names.
        let clashes = match s.kind {
            Kind::Resource | Kind::Sampler => taken(Kind::Resource) || taken(Kind::Sampler),
            k => taken(k),
        };
        if clashes {
            return refuse(&format!("a {} named `{}` exists already", s.kind.word(), p.new_name));
        }
        let text = &ix.sources.get(at.file).text;
        let written = text.get(s.decl.start as usize..s.decl.end as usize).unwrap_or("").trim_matches('"');
        if written != s.name {
            // `light` choosing by light kind makes `light_point` and others: their names follow it.
            return refuse("this pass makes one pass per light kind it chooses by, named after it: rename it in the file");
        }
        let edits: Vec<TextEdit> = ix
            .uses_of(sym)
            .filter(|u| u.file == at.file)
            .map(|u| {
                // A RON name is a quoted string: the quotes stay.
                let (mut a, mut b) = (u.start as usize, u.end as usize);
                if text.get(a..a + 1) == Some("\"") && b > a + 1 {
                    (a, b) = (a + 1, b - 1);
                }
                TextEdit::new(range(text, a, b), p.new_name.clone())
            })
            .collect();
        let uri = p.text_document_position.text_document.uri.clone();
        json(WorkspaceEdit::new([(uri, edits)].into_iter().collect()))
    }

    fn symbols(&mut self, doc: &TextDocumentIdentifier) -> Option<DocumentSymbolResponse> {
        let path = path_of(&doc.uri)?;
        let ix = self.index(&path)?;
        let file = ix.sources.find(&path.display().to_string())?;
        let text = &ix.sources.get(file).text;
        let mut out: Vec<DocumentSymbol> = vec![];
        for (i, s) in ix.symbols.iter().enumerate().filter(|(_, s)| s.decl.file == file) {
            let kind = match s.kind {
                Kind::Param => SymbolKind::PROPERTY,
                Kind::Sampler | Kind::Resource => SymbolKind::VARIABLE,
                Kind::Pass => SymbolKind::FUNCTION,
                Kind::Variant => SymbolKind::ENUM,
                Kind::Let => SymbolKind::CONSTANT,
                Kind::Template => SymbolKind::CLASS,
                Kind::Option(_) => continue,
            };
            let children: Vec<DocumentSymbol> = ix
                .symbols
                .iter()
                .filter(|o| o.kind == Kind::Option(i) && o.decl.file == file)
                .map(|o| symbol(text, &o.name, SymbolKind::ENUM_MEMBER, o.extent, o.decl, None))
                .collect();
            out.push(symbol(
                text,
                &s.name,
                kind,
                s.extent,
                s.decl,
                Some(children).filter(|c| !c.is_empty()),
            ));
        }
        Some(DocumentSymbolResponse::Nested(out))
    }

    /// `lightbench fmt` as one edit (`.lbp` documents that parse; nothing otherwise).
    fn format(&mut self, doc: &TextDocumentIdentifier) -> Option<Vec<TextEdit>> {
        let path = path_of(&doc.uri)?;
        if path.extension().and_then(|e| e.to_str()) != Some("lbp") {
            return None;
        }
        let text = self.text(&path)?;
        let mut s = self.workspace.session();
        let p = s.load_pipeline(&path).filter(|_| !s.diags.has_errors())?;
        let printed = lightbench_compiler::front::lbp::print::print(&p, Some(&text));
        Some(if printed == text {
            vec![]
        } else {
            vec![TextEdit::new(range(&text, 0, text.len()), printed)]
        })
    }

    /// Where a pass's shader path resolves, as the check resolves it.
    pub(super) fn shader_path(&self, pipeline: &Path, file: &str) -> PathBuf {
        let file = file.split('#').next().unwrap_or(file);
        lightbench_compiler::shader_root_for(self.overlay.as_ref(), pipeline, None).join(file)
    }

    pub(super) fn shader_entries(&self, pipeline: &Path, file: &str) -> Vec<(String, &'static str, usize)> {
        let shader = self.shader_path(pipeline, file);
        self.entries_in(&shader).into_iter().map(|(n, st, _, at)| (n, st, at)).collect()
    }
}

/// What a texture format holds and allows, on the profile the server checks for.
fn format_hover(f: lightbench_compiler::format::TextureFormat, profile: &lightbench_compiler::profile::Profile) -> String {
    use lightbench_compiler::format::ScalarKind;
    let of = match f.kind() {
        ScalarKind::Float => "float",
        ScalarKind::Uint => "unsigned integer",
        ScalarKind::Sint => "signed integer",
        ScalarKind::Depth => "depth",
    };
    let mut can = vec![];
    for (yes, word) in [
        (f.renderable(profile), "a color target"),
        (f.is_depth(), "a depth target"),
        (f.filterable(profile), "filtered"),
        (f.blendable(), "blended"),
        (f.storage(), "a storage texture"),
    ] {
        if yes {
            can.push(word);
        }
    }
    let channels = if f.components() == 1 {
        "1 channel".to_string()
    } else {
        format!("{} channels", f.components())
    };
    let srgb = if f.is_srgb() { " (sRGB-encoded)" } else { "" };
    format!(
        "**format** `{}`: {} bytes per texel, {channels} of {of}{srgb}\n\nCan be {} (on {}).",
        f.name(),
        f.bytes(),
        can.join(", "),
        profile.name
    )
}

#[allow(deprecated)] // `deprecated` is a field the type still requires
fn symbol(text: &str, name: &str, kind: SymbolKind, extent: Span, decl: Span, children: Option<Vec<DocumentSymbol>>) -> DocumentSymbol {
    let whole = range(text, extent.start.min(decl.start) as usize, extent.end.max(decl.end) as usize);
    DocumentSymbol {
        name: name.to_string(),
        detail: None,
        kind,
        tags: None,
        deprecated: None,
        range: whole,
        selection_range: range(text, decl.start as usize, decl.end as usize),
        children,
    }
}
