//! Diagnostics: a code, a message, labelled spans and notes; rendered rustc-style or as JSON.

mod code;
pub mod spelling;

pub use code::Code;

use crate::span::{SourceMap, Span};
use codespan_reporting::diagnostic as cs;
use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Warning,
    Error,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    pub span: Span,
    pub message: String,
    pub primary: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    pub severity: Severity,
    /// Stable, documented identifier (see [`Code`] and the manual's table, docs/diagnostics.md).
    pub code: Code,
    pub message: String,
    /// The first primary label is where the diagnostic "is" (file:line:col).
    pub labels: Vec<Label>,
    pub notes: Vec<String>,
}

impl Diagnostic {
    pub fn error(code: Code, message: impl Into<String>, span: Span) -> Self {
        Self::new(Severity::Error, code, message, span)
    }

    pub fn warning(code: Code, message: impl Into<String>, span: Span) -> Self {
        Self::new(Severity::Warning, code, message, span)
    }

    fn new(severity: Severity, code: Code, message: impl Into<String>, span: Span) -> Self {
        Diagnostic {
            severity,
            code,
            message: message.into(),
            labels: vec![Label {
                span,
                message: String::new(),
                primary: true,
            }],
            notes: vec![],
        }
    }

    /// A diagnostic with no source location (e.g. a file that cannot be read at all).
    pub fn unlocated(severity: Severity, code: Code, message: impl Into<String>) -> Self {
        Diagnostic {
            severity,
            code,
            message: message.into(),
            labels: vec![],
            notes: vec![],
        }
    }

    /// Text under the primary label.
    pub fn with_label_text(mut self, text: impl Into<String>) -> Self {
        if let Some(l) = self.labels.iter_mut().find(|l| l.primary) {
            l.message = text.into();
        }
        self
    }

    pub fn with_secondary(mut self, span: Span, text: impl Into<String>) -> Self {
        self.labels.push(Label {
            span,
            message: text.into(),
            primary: false,
        });
        self
    }

    pub fn with_note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    pub fn primary_span(&self) -> Option<Span> {
        self.labels.iter().find(|l| l.primary).map(|l| l.span)
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// `file:line:col` of the primary label (for tests and one-line output).
    pub fn location(&self, sources: &SourceMap) -> Option<(String, usize, usize)> {
        let span = self.primary_span()?;
        let f = sources.get(span.file);
        let (l, c) = f.line_col(span.start as usize);
        Some((f.name.clone(), l, c))
    }

    /// As shown to a user: about an `.lbp` file, the RON forms its hints quote spelled in
    /// LBP; a secondary label ("declared here") ends at the end of its first line, so a
    /// declaration spanning lines is pointed at, not printed whole.
    pub fn presented(&self, sources: &SourceMap) -> Diagnostic {
        let mut d = self.clone();
        for l in d.labels.iter_mut().filter(|l| !l.primary) {
            let text = &sources.get(l.span.file).text;
            let (start, end) = (l.span.start as usize, (l.span.end as usize).min(text.len()));
            if let Some(nl) = text.get(start..end).and_then(|t| t.find('\n')) {
                l.span.end = (start + nl) as u32;
            }
        }
        let lbp = self.primary_span().is_some_and(|s| sources.get(s.file).name.ends_with(".lbp"));
        if lbp {
            use spelling::spell;
            d.message = spell(&d.message);
            d.notes.iter_mut().for_each(|n| *n = spell(n));
            d.labels.iter_mut().for_each(|l| l.message = spell(&l.message));
        }
        d
    }

    /// rustc-style rendering with source snippets.
    pub fn render(&self, sources: &SourceMap) -> String {
        let d = self.presented(sources);
        d.render_as_is(sources)
    }

    fn render_as_is(&self, sources: &SourceMap) -> String {
        let d = match self.severity {
            Severity::Error => cs::Diagnostic::error(),
            Severity::Warning => cs::Diagnostic::warning(),
        }
        .with_code(self.code.as_str())
        .with_message(&self.message)
        .with_labels(
            self.labels
                .iter()
                .map(|l| {
                    let style = if l.primary {
                        cs::LabelStyle::Primary
                    } else {
                        cs::LabelStyle::Secondary
                    };
                    cs::Label::new(style, l.span.file, l.span.range()).with_message(&l.message)
                })
                .collect(),
        )
        .with_notes(self.notes.clone());
        let config = codespan_reporting::term::Config::default();
        codespan_reporting::term::emit_into_string(&config, sources, &d).unwrap_or_else(|e| {
            format!(
                "{}[{}]: {} (could not render source: {e})\n",
                self.severity_word(),
                self.code,
                self.message
            )
        })
    }

    fn severity_word(&self) -> &'static str {
        match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        }
    }

    /// One JSON object: severity, code, message, file, line, column, end, notes, and every
    /// label (primary and secondary, e.g. the shader-side location) with its own position.
    pub fn to_json(&self, sources: &SourceMap) -> serde_json::Value {
        self.presented(sources).json_as_is(sources)
    }

    fn json_as_is(&self, sources: &SourceMap) -> serde_json::Value {
        let labels: Vec<serde_json::Value> = self
            .labels
            .iter()
            .map(|l| {
                let f = sources.get(l.span.file);
                let (line, column) = f.line_col(l.span.start as usize);
                serde_json::json!({"file": f.name, "line": line, "column": column, "message": l.message, "primary": l.primary})
            })
            .collect();
        let mut obj = serde_json::json!({
            "severity": self.severity,
            "code": self.code,
            "message": self.message,
            "notes": self.notes,
            "labels": labels,
        });
        if let Some(span) = self.primary_span() {
            let f = sources.get(span.file);
            let (line, column) = f.line_col(span.start as usize);
            let (end_line, end_column) = f.line_col(span.end as usize);
            obj["file"] = f.name.clone().into();
            obj["line"] = line.into();
            obj["column"] = column.into();
            obj["end"] = serde_json::json!({ "line": end_line, "column": end_column });
        } else {
            obj["file"] = serde_json::Value::Null;
            obj["line"] = serde_json::Value::Null;
            obj["column"] = serde_json::Value::Null;
            obj["end"] = serde_json::Value::Null;
        }
        obj
    }
}

/// The one error for asking for a geometry stage, wherever it is asked for.
pub fn geometry_shader(span: Span) -> Diagnostic {
    Diagnostic::error(Code::GeometryShader, "geometry shaders are not supported: WGSL, naga and wgpu have no geometry stage", span)
        .with_label_text("geometry stage requested here")
        .with_note("for single-pass layered rendering (e.g. cube shadow maps) use `multiview` (Multiview feature, one pass writing 6 views) or an instanced atlas (`instances: 6` with clip distances into a 3×2 atlas)")
}

/// Collects diagnostics from the stages of one compilation.
#[derive(Clone, Debug, Default)]
pub struct Diagnostics {
    pub list: Vec<Diagnostic>,
}

impl Diagnostics {
    /// Add a diagnostic. The same problem reached again (from another configuration, or
    /// another pass using the same shader or parameter: same severity, code and message) is
    /// reported once, with each further place it applies as an "also here" label.
    pub fn push(&mut self, d: Diagnostic) {
        let same = |e: &&mut Diagnostic| e.severity == d.severity && e.code == d.code && e.message == d.message;
        let Some(existing) = self.list.iter_mut().find(same) else {
            self.list.push(d);
            return;
        };
        for l in d.labels {
            let known = existing.labels.iter().any(|k| k.span == l.span);
            if !known {
                let message = if l.primary { "also here".to_string() } else { l.message };
                existing.labels.push(Label {
                    primary: false,
                    message,
                    ..l
                });
            }
        }
        for n in d.notes {
            if !existing.notes.contains(&n) {
                existing.notes.push(n);
            }
        }
    }
    pub fn extend(&mut self, ds: impl IntoIterator<Item = Diagnostic>) {
        for d in ds {
            self.push(d);
        }
    }
    pub fn has_errors(&self) -> bool {
        self.list.iter().any(|d| d.is_error())
    }
    pub fn error_count(&self) -> usize {
        self.list.iter().filter(|d| d.is_error()).count()
    }
    pub fn warning_count(&self) -> usize {
        self.list.len() - self.error_count()
    }
    pub fn errors(&self) -> impl Iterator<Item = &Diagnostic> {
        self.list.iter().filter(|d| d.is_error())
    }
}

/// The closest candidate by edit distance, when close enough to be a plausible typo. For a
/// dotted name, one that is the input with a suffix (`cube.bias` → `cube.bias_texels`: a
/// parameter renamed when its unit changed) comes first, however long the suffix; a keyword
/// (`param` for `params`, not `param_block`) is a typo.
pub fn did_you_mean<'a>(input: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let input = input.to_lowercase();
    let extends = |c: &str| input.contains('.') && c.to_lowercase().strip_prefix(&input).is_some_and(|rest| rest.starts_with('_'));
    candidates
        .into_iter()
        .map(|c| {
            let score = strsim::normalized_damerau_levenshtein(&input, &c.to_lowercase());
            (if extends(c) { 1.0 + score } else { score }, c)
        })
        .filter(|(score, _)| *score >= 0.6)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, c)| c)
}

/// "did you mean `x`?" or the list of valid names.
pub fn suggestion_note(input: &str, candidates: &[&str]) -> String {
    match did_you_mean(input, candidates.iter().copied()) {
        Some(s) => format!("did you mean `{s}`?"),
        None if candidates.is_empty() => "nothing is declared here".to_string(),
        None => format!(
            "expected one of: {}",
            candidates.iter().map(|c| format!("`{c}`")).collect::<Vec<_>>().join(", ")
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_close_names_only() {
        assert_eq!(did_you_mean("pases", ["passes", "params", "output"]), Some("passes"));
        assert_eq!(did_you_mean("zzzz", ["passes", "params"]), None);
        // A name renamed with its unit is found, before a closer typo.
        assert_eq!(
            did_you_mean("cube.bias", ["cube.size", "cube.bias_texels"]),
            Some("cube.bias_texels")
        );
        assert_eq!(did_you_mean("cube.bia", ["cube.size", "cube.bias_texels"]), Some("cube.size"));
        assert_eq!(did_you_mean("param", ["params", "param_block"]), Some("params"));
    }
}
