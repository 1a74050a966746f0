//! Language server, diagnostics: a check of each pipeline an edit touches (the pipeline
//! itself, or every pipeline that uses the edited shader or pipeline file), its compiler
//! diagnostics turned into the protocol's, per file, as `check --format json` locates them.

use super::merge::Found;
use super::text::{range, uri_of};
use super::Server;
use lightbench_compiler::diag::{Diagnostic, Severity};
use lightbench_compiler::scene::{file_kind, FileKind};
use lightbench_compiler::span::SourceMap;
use lsp_types::{DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString, PublishDiagnosticsParams};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// One pipeline's diagnostics, by the file each is located in.
pub type ByFile = BTreeMap<PathBuf, Vec<Found>>;

impl Server {
    /// The files to check again after these changed: a changed pipeline, scene or sweep
    /// file itself, and every pipeline whose last check read a changed file. A changed file
    /// no check has read yet (a shader opened first) has the workspace's pipelines checked.
    pub fn to_check(&mut self, changed: &BTreeSet<PathBuf>) -> BTreeSet<PathBuf> {
        let mut out = BTreeSet::new();
        for c in changed {
            if file_kind(c, self.overlay.get(c).as_deref()) != FileKind::Other {
                out.insert(c.clone());
            }
            let readers: Vec<&PathBuf> = self.deps.iter().filter(|(_, d)| d.contains(c)).map(|(p, _)| p).collect();
            if readers.is_empty() && !out.contains(c) {
                out.extend(self.known_pipelines().into_iter().filter(|p| !self.deps.contains_key(p)));
            }
            out.extend(readers.into_iter().cloned());
        }
        out
    }

    /// Check each file in turn and publish, after each check, the diagnostics of every file
    /// it changed. What the earlier checks of these files found is set aside first, so that
    /// no publication mixes copies from before the edit with those after it.
    pub fn publish(&mut self, files: &[PathBuf], mut send: impl FnMut(PublishDiagnosticsParams)) {
        let mut stale: BTreeMap<PathBuf, ByFile> = files.iter().filter_map(|f| Some((f.clone(), self.published.remove(f)?))).collect();
        let mut sent: BTreeMap<PathBuf, Vec<lsp_types::Diagnostic>> = BTreeMap::new();
        for f in files {
            // A document closed that is no file on disk (never saved, or deleted) is no
            // longer checked: what it showed is cleared.
            let found = if self.exists(f) {
                self.check(f)
            } else {
                self.deps.remove(f);
                ByFile::new()
            };
            // The checked file too: an empty list clears what the client showed.
            let mut touched: BTreeSet<PathBuf> = [f.clone()].into();
            touched.extend(found.keys().cloned());
            touched.extend(stale.remove(f).into_iter().flat_map(|old| old.into_keys()));
            self.published.insert(f.clone(), found);
            for file in touched {
                let Some(params) = self.params_for(&file) else { continue };
                // Published in this flush already, the same: not again.
                if sent.get(&file) != Some(&params.diagnostics) {
                    sent.insert(file, params.diagnostics.clone());
                    send(params);
                }
            }
        }
    }

    /// Every diagnostic located in `file`, one per mistake however many pipelines found it
    /// (see [`super::merge`]).
    fn params_for(&self, file: &Path) -> Option<PublishDiagnosticsParams> {
        // The file's own check first, then the others by name: the order does not depend on
        // which pipeline was checked when.
        let mut checkers: Vec<&PathBuf> = self
            .published
            .iter()
            .filter(|(_, by)| by.contains_key(file))
            .map(|(c, _)| c)
            .collect();
        checkers.sort_by_key(|c| (c.as_path() != file, c.to_path_buf()));
        let copies: Vec<(&Path, &Found)> = checkers
            .into_iter()
            .flat_map(|c| self.published[c][file].iter().map(move |f| (c.as_path(), f)))
            .collect();
        let mut diagnostics = super::merge::merge(file, &copies, |p| self.shown(p));
        for d in &mut diagnostics {
            d.message = self.relative_paths(&d.message);
            d.related_information
                .iter_mut()
                .flatten()
                .for_each(|r| r.message = self.relative_paths(&r.message));
        }
        Some(PublishDiagnosticsParams {
            uri: uri_of(file)?,
            diagnostics,
            version: None,
        })
    }

    /// Paths in a message as `check` run in the workspace folder prints them: relative.
    fn relative_paths(&self, text: &str) -> String {
        let mut out = text.to_string();
        for r in &self.roots {
            out = out.replace(&format!("{}/", r.display()), "");
        }
        out
    }

    /// A path as `check` prints it: relative to the workspace folder it is in.
    pub fn shown(&self, path: &Path) -> String {
        let relative = self.roots.iter().find_map(|r| path.strip_prefix(r).ok());
        relative.unwrap_or(path).display().to_string()
    }

    /// Check one file as `lightbench check` would, through the open documents.
    fn check(&mut self, path: &Path) -> ByFile {
        let mut s = self.workspace.session();
        let checked = match file_kind(path, self.overlay.get(path).as_deref()) {
            FileKind::Scene => {
                crate::scene::load_in(&mut s, &path.display().to_string());
                None
            }
            FileKind::Sweep => {
                // Sweep specs report unlocated errors: shown at the top of the file.
                if let Err(e) = crate::sweep::spec::load(path) {
                    let code = lightbench_compiler::diag::Code::SweepSpec;
                    s.diags.push(Diagnostic::unlocated(Severity::Error, code, e.to_string()));
                }
                None
            }
            _ => {
                // What `check_file` does, keeping the checked pipeline for the default Plan.
                let checked = s.load_checked(path, None, &self.profile);
                if let Some(c) = &checked {
                    s.check_configurations(c, &self.profile, None);
                }
                self.deps.insert(path.to_path_buf(), s.dependencies().clone());
                checked.filter(|_| !s.diags.has_errors())
            }
        };
        let mut out = ByFile::new();
        for d in &s.diags.list {
            let (file, mut found) = to_lsp(d, &s.sources, path);
            found.d.code_description = self.manual.clone().map(|href| lsp_types::CodeDescription { href });
            if file != path {
                self.name_passes(path, &file, &mut found.d);
            }
            out.entry(file).or_default().push(found);
        }
        if let Some(c) = checked {
            self.plan_default(path, &mut s, &c);
        }
        out
    }

    /// A diagnostic located in a shader: which passes of the pipeline use that shader.
    fn name_passes(&mut self, pipeline: &Path, shader: &Path, d: &mut lsp_types::Diagnostic) {
        let Some(ix) = self.index(pipeline) else { return };
        let uses: Vec<(String, String, lightbench_compiler::span::Span)> = ix
            .shaders
            .iter()
            .map(|u| (u.pass.clone(), u.file.value.clone(), u.file.span))
            .collect();
        for (pass, file, span) in uses {
            if self.shader_path(pipeline, &file) != shader {
                continue;
            }
            let Some(ix) = self.indexes.get(pipeline).map(|(_, ix)| ix) else {
                return;
            };
            if let Some(location) = ix.location(span) {
                let message = format!("used by pass `{pass}`");
                d.related_information
                    .get_or_insert_with(Vec::new)
                    .push(DiagnosticRelatedInformation { location, message });
            }
        }
    }

    /// What the pipeline runs on the default scene (`render`'s `cornell`) with its default
    /// options, pass by pass: repetitions, or why it is culled (pass hovers show it).
    /// Planned from the check's own result, in its session (its diagnostics already taken).
    fn plan_default(&mut self, path: &Path, s: &mut lightbench_compiler::Session, checked: &lightbench_compiler::check::Checked) {
        let Some(scene) = lightbench_compiler::ir::scene::builtin::by_name("cornell") else {
            return;
        };
        let Some(plan) = s.plan(checked, &self.profile, &scene.features([]), &[]) else {
            return;
        };
        let mut runs = BTreeMap::new();
        for p in &plan.passes {
            let times = if p.repetitions == 1 {
                "once".to_string()
            } else {
                format!("{} times", p.repetitions)
            };
            runs.insert(format!("pass:{}", p.name), format!("runs {times}"));
        }
        for c in &plan.culled {
            runs.entry(format!("pass:{}", c.name)).or_insert(format!("culled: {}", c.reason));
        }
        for r in &plan.resources {
            runs.insert(format!("resource:{}", r.name), resource_facts(r));
        }
        self.default_runs.insert(path.to_path_buf(), runs);
    }
}

/// A resource in the default scene's Plan: its size there, instances, usages, memory.
fn resource_facts(r: &lightbench_compiler::plan::PlanResource) -> String {
    use lightbench_compiler::plan::ResourceShape;
    let size = match &r.shape {
        ResourceShape::Texture { extent, layers, .. } if *layers > 1 => format!("{}×{}×{layers}", extent.0, extent.1),
        ResourceShape::Texture { extent, .. } => format!("{}×{}", extent.0, extent.1),
        ResourceShape::Buffer { size, .. } => format!("{size} bytes"),
        ResourceShape::AccelerationStructure => "built from the scene".to_string(),
    };
    let usage: Vec<&str> = r.usage.iter().map(|u| u.name()).collect();
    let instances = if r.instances == 1 {
        String::new()
    } else {
        format!(", {} instances", r.instances)
    };
    format!("{size}{instances}; usage {}; {} KiB", usage.join(", "), r.bytes.div_ceil(1024))
}

/// A compiler diagnostic as the protocol's, with the file it is located in (an unlocated one
/// at the top of the file checked). Secondary labels become related information; notes stay
/// apart until the copies of one mistake are merged.
fn to_lsp(d: &Diagnostic, sources: &SourceMap, checked: &Path) -> (PathBuf, Found) {
    let d = d.presented(sources);
    let at = |span: lightbench_compiler::span::Span| {
        let f = sources.get(span.file);
        let r = range(&f.text, span.start as usize, span.end as usize);
        (PathBuf::from(&f.name), r)
    };
    let (file, primary) = d.primary_span().map(at).unwrap_or((checked.to_path_buf(), Default::default()));
    let mut related: Vec<DiagnosticRelatedInformation> = vec![];
    let mut relate = |file: &Path, range, message: String| {
        if let Some(uri) = uri_of(file) {
            related.push(DiagnosticRelatedInformation {
                location: Location { uri, range },
                message,
            });
        }
    };
    for l in d.labels.iter().filter(|l| !l.primary) {
        let (f, r) = at(l.span);
        relate(&f, r, l.message.clone());
    }
    let diagnostic = lsp_types::Diagnostic {
        range: primary,
        severity: Some(match d.severity {
            Severity::Error => DiagnosticSeverity::ERROR,
            Severity::Warning => DiagnosticSeverity::WARNING,
        }),
        code: Some(NumberOrString::String(d.code.as_str().to_string())),
        source: Some("lightbench".into()),
        message: d.message.clone(),
        related_information: (!related.is_empty()).then_some(related),
        ..Default::default()
    };
    let notes = d.notes.clone();
    (file, Found { d: diagnostic, notes })
}
