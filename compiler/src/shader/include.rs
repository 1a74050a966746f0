//! `#include "path"` for WGSL and GLSL, with a source map back to every file.
//!
//! We chose a small include mechanism over the `wesl` crate: wesl covers WGSL only (our
//! GLSL 450 shaders need the same helpers), and its module system mangles imported
//! names, while our binding rule matches shader globals to pipeline resources *by name*.
//! Textual include-once keeps names intact and the segment table below maps every
//! naga span back to the file and line it came from.

use crate::diag::{Code, Diagnostic};
use crate::span::{FileId, SourceMap, Span};

/// A piece of the expanded source that came verbatim from one file.
#[derive(Clone, Debug)]
pub struct Segment {
    pub start: usize,
    pub len: usize,
    pub file: FileId,
    pub file_offset: usize,
}

#[derive(Clone, Debug, Default)]
pub struct Expanded {
    pub text: String,
    pub segments: Vec<Segment>,
    /// Every file that contributed, the root first (for hot reload and hashing).
    pub files: Vec<FileId>,
    /// Beside `files`: each one's path as the shader or its `#include` names it.
    pub paths: Vec<String>,
}

impl Expanded {
    /// Map a byte range of the expanded text back to a file span.
    pub fn map(&self, range: std::ops::Range<usize>) -> Option<Span> {
        let seg = self
            .segments
            .iter()
            .find(|s| range.start >= s.start && range.start < s.start + s.len.max(1))
            .or_else(|| self.segments.last().filter(|s| range.start >= s.start))?;
        let start = seg.file_offset + (range.start - seg.start).min(seg.len);
        let end = seg.file_offset + (range.end.max(range.start) - seg.start).min(seg.len);
        Some(Span::new(seg.file, start, end.max(start)))
    }
}

/// The path an `#include "path"` line names: `None` when the line is no `#include`,
/// `Some(None)` when it is one without a quoted path.
pub fn included(line: &str) -> Option<Option<&str>> {
    let rest = line.trim_start().strip_prefix("#include")?.trim();
    Some(rest.strip_prefix('"').and_then(|r| r.strip_suffix('"')))
}

/// How many files deep includes may nest (each level is a recursion of the expander).
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// Shader and include paths are relative to the shader root and may not leave it: no
/// absolute paths, no `..` climbing above the root. (Checked on the text, so that nothing
/// outside the root is even opened; links are resolved and confined again when reading:
/// `Vfs::within`.)
pub fn confined(path: &str) -> Result<(), String> {
    use std::path::Component;
    let p = std::path::Path::new(path);
    let mut depth = 0usize;
    for c in p.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir if depth > 0 => depth -= 1,
            Component::ParentDir => return Err(format!("`{path}` leaves the shader root (paths are relative to it)")),
            Component::RootDir | Component::Prefix(_) => {
                return Err(format!(
                    "`{path}` is absolute: shader and include paths are relative to the shader root"
                ))
            }
        }
    }
    Ok(())
}

/// Reads shader files for the expander (through the workspace's virtual file system).
pub trait ShaderFs {
    fn read(&self, path: &str) -> std::io::Result<String>;
    /// The name diagnostics show for a shader path (e.g. the path on disk).
    fn display(&self, path: &str) -> String {
        path.to_string()
    }
}

/// Load `path` (already known to exist as `root_file`) and expand its includes.
pub fn expand(fs: &dyn ShaderFs, sources: &mut SourceMap, root_file: FileId, root_path: &str) -> Result<Expanded, Diagnostic> {
    let mut out = Expanded::default();
    let mut stack = vec![root_path.to_string()];
    let mut done: Vec<String> = vec![];
    expand_file(fs, sources, root_file, &mut stack, &mut done, &mut out)?;
    Ok(out)
}

fn expand_file(
    fs: &dyn ShaderFs,
    sources: &mut SourceMap,
    file: FileId,
    stack: &mut Vec<String>,
    done: &mut Vec<String>,
    out: &mut Expanded,
) -> Result<(), Diagnostic> {
    out.files.push(file);
    out.paths.push(stack.last().cloned().unwrap_or_default());
    let text = sources.get(file).text.clone();
    let mut copied_to = 0;
    // Only lines holding `#include` can be directives: jump from one to the next (by `#`,
    // which a byte search finds fastest; WGSL has no other use for it).
    let mut from = 0;
    while let Some(at) = text[from..].find('#').map(|i| from + i) {
        if !text[at..].starts_with("#include") {
            from = at + 1;
            continue;
        }
        let this_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
        let line_start = text[at..].find('\n').map_or(text.len(), |i| at + i + 1);
        from = line_start;
        let line = &text[this_start..line_start];
        let Some(found) = included(line) else {
            continue;
        };
        let indent = line.len() - line.trim_start().len();
        let directive = Span::new(file, this_start + indent, this_start + line.trim_end().len());
        let Some(path) = found else {
            return Err(Diagnostic::error(Code::IncludeSyntax, "expected `#include \"path\"`", directive));
        };
        // Text before the directive.
        push(out, &text, file, copied_to, this_start);
        copied_to = line_start;
        if stack.iter().any(|s| s == path) {
            let mut chain: Vec<&str> = stack.iter().map(|s| s.as_str()).collect();
            chain.push(path);
            return Err(
                Diagnostic::error(Code::IncludeCycle, format!("include cycle: {}", chain.join(" -> ")), directive)
                    .with_label_text(format!("`{path}` is already being included")),
            );
        }
        if done.iter().any(|d| d == path) {
            continue; // include-once: WGSL forbids redefinitions
        }
        if let Err(why) = confined(path) {
            return Err(Diagnostic::error(Code::OutsideRoot, why, directive));
        }
        if stack.len() >= MAX_INCLUDE_DEPTH {
            let msg = format!("includes nested more than {MAX_INCLUDE_DEPTH} files deep");
            return Err(Diagnostic::error(Code::NestingTooDeep, msg, directive));
        }
        let child = match sources.find(&fs.display(path)) {
            Some(id) => id,
            None => match fs.read(path) {
                Ok(t) => sources.add(fs.display(path), t),
                Err(e) => {
                    let code = match crate::vfs::read_error_code(&e) {
                        Code::FileNotFound => Code::IncludeNotFound,
                        c => c,
                    };
                    return Err(Diagnostic::error(
                        code,
                        format!("cannot read included file `{path}`: {e}"),
                        directive,
                    ));
                }
            },
        };
        stack.push(path.to_string());
        expand_file(fs, sources, child, stack, done, out)?;
        stack.pop();
        done.push(path.to_string());
        if !out.text.ends_with('\n') {
            out.text.push('\n');
        }
    }
    push(out, &text, file, copied_to, text.len());
    Ok(())
}

fn push(out: &mut Expanded, text: &str, file: FileId, from: usize, to: usize) {
    if to > from {
        out.segments.push(Segment {
            start: out.text.len(),
            len: to - from,
            file,
            file_offset: from,
        });
        out.text.push_str(&text[from..to]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    struct Mem(HashMap<&'static str, &'static str>);
    impl ShaderFs for Mem {
        fn read(&self, p: &str) -> std::io::Result<String> {
            self.0
                .get(p)
                .map(|s| s.to_string())
                .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::NotFound, "no such file"))
        }
    }

    #[test]
    fn maps_spans_back_to_included_files() {
        let fs = Mem([("a.wgsl", "#include \"b.wgsl\"\nfn a() {}\n"), ("b.wgsl", "fn b() {}\n")].into());
        let mut sm = SourceMap::new();
        let a = sm.add("a.wgsl", fs.read("a.wgsl").unwrap());
        let e = expand(&fs, &mut sm, a, "a.wgsl").unwrap();
        assert_eq!(e.text, "fn b() {}\nfn a() {}\n");
        let sb = e.map(3..4).unwrap();
        assert_eq!(sm.get(sb.file).name, "b.wgsl");
        assert_eq!(sb.start, 3);
        let sa = e.map(13..14).unwrap();
        assert_eq!(sa.file, a);
        assert_eq!(sm.get(a).line_col(sa.start as usize), (2, 4));
    }

    #[test]
    fn paths_stay_inside_the_root() {
        assert!(confined("lib/a.wgsl").is_ok() && confined("lib/../b.wgsl").is_ok() && confined("./c.wgsl").is_ok());
        for bad in ["/etc/passwd", "../x.wgsl", "lib/../../x.wgsl", "a/../../../etc/passwd"] {
            assert!(confined(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn include_cycle_is_reported_at_the_directive() {
        let fs = Mem([("a.wgsl", "#include \"b.wgsl\"\n"), ("b.wgsl", "\n  #include \"a.wgsl\"\n")].into());
        let mut sm = SourceMap::new();
        let a = sm.add("a.wgsl", fs.read("a.wgsl").unwrap());
        let err = expand(&fs, &mut sm, a, "a.wgsl").unwrap_err();
        assert_eq!(err.code, "include-cycle");
        assert!(err.message.contains("a.wgsl -> b.wgsl -> a.wgsl"));
        let (f, l, c) = err.location(&sm).unwrap();
        assert_eq!((f.as_str(), l, c), ("b.wgsl", 2, 3));
    }
}
