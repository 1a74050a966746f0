//! `lightbench convert` (RON <-> LBP, lossless) and `lightbench fmt` (canonical LBP). Both
//! write through `files`: atomically, through symlinks, keeping the mode; `fmt` refuses to
//! replace a file that changed while it ran, `convert` to overwrite its own input, and both
//! to write what does not read back as the same pipeline.

use super::{usage_error, EXIT_ERRORS, EXIT_OK};
use crate::files::{self, Snapshot};
use lightbench_compiler::front::{lbp, ron};
use lightbench_compiler::ir::Pipeline;
use lightbench_compiler::Session;
use std::path::Path;

/// The pipeline, its text and what the file looked like when read.
fn load(path: &Path) -> Result<(Pipeline, String, Snapshot), i32> {
    if !path.is_file() {
        return Err(usage_error(format!("no such file: {}", path.display())));
    }
    let mut s = Session::new();
    let parsed = s.load_pipeline(path).filter(|_| !s.diags.has_errors());
    let Some(pipeline) = parsed else {
        eprint!("{}", s.render());
        return Err(EXIT_ERRORS);
    };
    let name = path.display().to_string();
    let text = s.sources.find(&name).map(|id| s.sources.get(id).text.clone()).unwrap_or_default();
    // The snapshot must be of exactly the text that was parsed, or an edit in between is lost.
    match Snapshot::of(path) {
        Ok(snap) if snap.bytes() == text.as_bytes() => Ok((pipeline, text, snap)),
        Ok(_) => {
            eprintln!("error: {name} changed while it was read; try again");
            Err(EXIT_ERRORS)
        }
        Err(e) => Err(usage_error(format!("{name}: {e}"))),
    }
}

/// The printed text read back as the same pipeline, or nothing is written: a printer that
/// lost or garbled something (a bug of ours) must not damage the user's file.
fn reads_back(pipeline: &Pipeline, printed: &str, input: &Path, ext: &str) -> Result<(), i32> {
    let mut s = Session::new();
    // Named as beside the input (nothing is read there): a `use` finds the file it names.
    let name = input.with_extension(ext).display().to_string();
    match s.parse_pipeline(&name, printed.to_string()) {
        Some(p) if !s.diags.has_errors() && p.same_as(pipeline) => Ok(()),
        _ => {
            eprint!("{}", s.render());
            eprintln!(
                "error: the {ext} printed for this pipeline does not read back as the same pipeline \
                 (a bug in lightbench's printer; please report it); nothing was written"
            );
            Err(EXIT_ERRORS)
        }
    }
}

pub fn convert(input: &Path, to: &str, out: Option<&Path>) -> i32 {
    if !matches!(to, "ron" | "lbp") {
        return usage_error(format!("--to {to}: expected `ron` or `lbp`"));
    }
    if let Some(o) = out {
        let ext = o.extension().and_then(|e| e.to_str()).unwrap_or("");
        if ext != to {
            return usage_error(format!(
                "-o {}: the name says `.{ext}` but --to is `{to}`; name it `.{to}`",
                o.display()
            ));
        }
        if files::same_file(input, o) {
            return usage_error(format!("-o {} is the input file; write the conversion elsewhere", o.display()));
        }
    }
    let (pipeline, text, _) = match load(input) {
        Ok(x) => x,
        Err(code) => return code,
    };
    let printed = match to {
        "ron" => ron::print::print(&pipeline, Some(&text)),
        _ => lbp::print::print(&pipeline, Some(&text)),
    };
    if let Err(code) = reads_back(&pipeline, &printed, input, to) {
        return code;
    }
    let Some(o) = out else {
        print!("{printed}");
        return EXIT_OK;
    };
    match files::write_atomic(o, printed.as_bytes()) {
        Ok(()) => EXIT_OK,
        Err(e) => {
            eprintln!("error: {e}");
            EXIT_ERRORS
        }
    }
}

/// Where `fmt --check` finds a file unformatted: the first line that differs, as written and
/// as `fmt` would write it.
fn unformatted(file: &Path, text: &str, printed: &str) -> String {
    let (a, b): (Vec<&str>, Vec<&str>) = (text.lines().collect(), printed.lines().collect());
    let i = (0..a.len().max(b.len())).find(|&i| a.get(i) != b.get(i)).unwrap_or(a.len());
    let show = |l: Option<&&str>| l.map_or("(end of file)".to_string(), |l| format!("`{l}`"));
    format!(
        "{}:{}: not formatted\n  written: {}\n  fmt:     {}\n(run `lightbench fmt {}` to rewrite it)\n",
        file.display(),
        i + 1,
        show(a.get(i)),
        show(b.get(i)),
        file.display()
    )
}

/// Rewrite an `.lbp` file in canonical layout; with `check`, only report whether it already is.
pub fn fmt(file: &Path, check: bool) -> i32 {
    if file.extension().and_then(|e| e.to_str()) != Some("lbp") {
        return usage_error(format!("{}: `fmt` formats .lbp files", file.display()));
    }
    let (pipeline, text, snapshot) = match load(file) {
        Ok(x) => x,
        Err(code) => return code,
    };
    let printed = lbp::print::print(&pipeline, Some(&text));
    if printed == text {
        if !check {
            // Nothing to write, but a killed run's temporary is cleaned as a write would.
            files::clean_stale_beside(file);
        }
        return EXIT_OK;
    }
    if let Err(code) = reads_back(&pipeline, &printed, file, "lbp") {
        return code;
    }
    if check {
        eprint!("{}", unformatted(file, &text, &printed));
        return EXIT_ERRORS;
    }
    match files::replace(file, printed.as_bytes(), &snapshot) {
        Ok(()) => EXIT_OK,
        Err(e) => {
            eprintln!("error: {e}");
            EXIT_ERRORS
        }
    }
}
