//! Language server, diagnostics merged: a file used by several pipelines (a shader, a
//! pipeline another one `use`s) is checked once per pipeline, so one mistake is found several
//! times. The copies at one place with one code are one diagnostic: its message says what
//! each pipeline found when they differ, and the notes ("did you mean …") are in the message,
//! where every client shows them.

use super::text::uri_of;
use lsp_types::{Diagnostic, DiagnosticRelatedInformation, Location};
use std::collections::HashMap;
use std::path::Path;

/// A diagnostic as one check found it: the protocol's form (message without notes) and the
/// compiler's notes ("did you mean …"), which go into the message once copies are merged.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    pub d: lsp_types::Diagnostic,
    pub notes: Vec<String>,
}

/// One diagnostic per (place, code, severity) among `copies`, each tagged with the pipeline
/// whose check found it, in the order first found.
pub fn merge(file: &Path, copies: &[(&Path, &Found)], shown: impl Fn(&Path) -> String) -> Vec<Diagnostic> {
    let mut groups: Vec<Vec<(&Path, &Found)>> = vec![];
    // Each group's index by its place, code and severity (linear in the copies).
    let mut by_key: HashMap<String, usize> = HashMap::new();
    for &(checker, found) in copies {
        let d = &found.d;
        let key = format!("{:?} {:?} {:?}", d.range, d.code, d.severity);
        match by_key.get(&key) {
            Some(&g) => groups[g].push((checker, found)),
            None => {
                by_key.insert(key, groups.len());
                groups.push(vec![(checker, found)]);
            }
        }
    }
    groups.iter().map(|g| one(file, g, &shown)).collect()
}

/// The copies of one mistake as one diagnostic.
fn one(file: &Path, copies: &[(&Path, &Found)], shown: &impl Fn(&Path) -> String) -> Diagnostic {
    let mut d = copies[0].1.d.clone();
    let mut related: Vec<DiagnosticRelatedInformation> = vec![];
    for (_, f) in copies {
        for r in f.d.related_information.iter().flatten() {
            if !related.contains(r) {
                related.push(r.clone());
            }
        }
    }
    let mut checkers: Vec<&Path> = copies.iter().map(|(c, _)| *c).collect();
    checkers.dedup();
    // Found in a file that is not itself checked (a shader): which pipelines reach it.
    if !checkers.contains(&file) {
        for c in &checkers {
            if let Some(uri) = uri_of(c) {
                let location = Location {
                    uri,
                    range: Default::default(),
                };
                let message = format!("found checking `{}`", shown(c));
                related.push(DiagnosticRelatedInformation { location, message });
            }
        }
    }
    d.related_information = (!related.is_empty()).then_some(related);
    d.message = message(copies, shown);
    d
}

/// The message, then the notes: once when every pipeline found the same, else each
/// distinct one after the pipelines that found it.
fn message(copies: &[(&Path, &Found)], shown: &impl Fn(&Path) -> String) -> String {
    let text = |f: &Found| {
        let mut lines = vec![f.d.message.clone()];
        lines.extend(f.notes.iter().cloned());
        lines
    };
    // Distinct texts, each with the pipelines that found it.
    let mut distinct: Vec<(Vec<String>, Vec<String>)> = vec![];
    for (c, f) in copies {
        let t = text(f);
        let name = format!("`{}`", shown(c));
        match distinct.iter_mut().find(|(d, _)| *d == t) {
            Some((_, names)) if names.contains(&name) => {}
            Some((_, names)) => names.push(name),
            None => distinct.push((t, vec![name])),
        }
    }
    if distinct.len() == 1 {
        return distinct.remove(0).0.join("\n");
    }
    let first = &distinct[0].0[0];
    let same_message = distinct.iter().all(|(t, _)| t[0] == *first);
    let mut lines = vec![];
    if same_message {
        lines.push(first.clone());
    }
    for (t, names) in &distinct {
        let said = if same_message { &t[1..] } else { &t[..] };
        let said = if said.is_empty() {
            "(nothing more)".to_string()
        } else {
            said.join("; ")
        };
        lines.push(format!("checking {}: {said}", names.join(", ")));
    }
    lines.join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;
    use lsp_types::{NumberOrString, Position, Range};

    fn found(line: u32, code: &str, message: &str, notes: &[&str]) -> Found {
        let at = Position { line, character: 4 };
        let d = Diagnostic {
            range: Range { start: at, end: at },
            code: Some(NumberOrString::String(code.into())),
            message: message.into(),
            ..Default::default()
        };
        let notes = notes.iter().map(|n| n.to_string()).collect();
        Found { d, notes }
    }

    fn shown(p: &Path) -> String {
        p.file_name().unwrap().to_string_lossy().into_owned()
    }

    #[test]
    fn one_mistake_found_by_two_pipelines_is_one_diagnostic() {
        let (own, user) = (Path::new("/p/deferred.lbp"), Path::new("/p/deferred_gi.lbp"));
        let a = found(3, "unknown-resource", "no resource named `x`", &["did you mean `y`?"]);
        let other = found(5, "unknown-pass", "no pass named `z`", &[]);
        let got = merge(own, &[(own, &a), (own, &other), (user, &a)], shown);
        assert_eq!(got.len(), 2);
        assert_eq!(got[0].message, "no resource named `x`\ndid you mean `y`?");
        // Found in the file's own check: no "found checking" entries.
        assert!(got[0].related_information.is_none());
    }

    #[test]
    fn copies_that_differ_name_each_pipeline() {
        let (own, user) = (Path::new("/p/deferred.lbp"), Path::new("/p/deferred_gi.lbp"));
        let a = found(3, "unknown-pass", "no pass named `lightng`", &["did you mean `lighting`?"]);
        let b = found(3, "unknown-pass", "no pass named `lightng`", &[]);
        let got = merge(own, &[(own, &a), (user, &b)], shown);
        assert_eq!(got.len(), 1);
        assert_eq!(
            got[0].message,
            "no pass named `lightng`\nchecking `deferred.lbp`: did you mean `lighting`?\nchecking `deferred_gi.lbp`: (nothing more)"
        );
        let c = found(3, "unknown-pass", "no pass named `q`", &[]);
        let got = merge(own, &[(own, &a), (user, &c)], shown);
        assert_eq!(
            got[0].message,
            "checking `deferred.lbp`: no pass named `lightng`; did you mean `lighting`?\nchecking `deferred_gi.lbp`: no pass named `q`"
        );
    }

    #[test]
    fn a_shader_mistake_names_every_pipeline_that_reaches_it() {
        let shader = Path::new("/p/shaders/ambient.wgsl");
        let (a, b) = (Path::new("/p/deferred.lbp"), Path::new("/p/deferred_gi.lbp"));
        let e = found(1, "wgsl-parse", "expected `(`", &[]);
        let got = merge(shader, &[(a, &e), (b, &e)], shown);
        assert_eq!(got.len(), 1);
        assert_eq!(got[0].message, "expected `(`");
        let related: Vec<&str> = got[0].related_information.iter().flatten().map(|r| r.message.as_str()).collect();
        assert_eq!(related, ["found checking `deferred.lbp`", "found checking `deferred_gi.lbp`"]);
    }
}
