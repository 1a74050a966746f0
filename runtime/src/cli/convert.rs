//! `lightbench convert` (RON <-> LBP, lossless) and `lightbench fmt` (canonical LBP).

use super::{usage_error, EXIT_ERRORS, EXIT_OK};
use crate::io::write_atomic;
use lightbench_compiler::front::{lbp, ron};
use lightbench_compiler::Session;
use std::path::Path;

fn load(path: &Path) -> Result<(lightbench_compiler::ir::Pipeline, String), i32> {
    if !path.is_file() {
        return Err(usage_error(format!("no such file: {}", path.display())));
    }
    let mut s = Session::new();
    let text = std::fs::read_to_string(path).map_err(|e| usage_error(format!("{}: {e}", path.display())))?;
    match s.parse_pipeline(&path.display().to_string(), text.clone()) {
        Some(p) if !s.diags.has_errors() => Ok((p, text)),
        _ => {
            eprint!("{}", s.render());
            Err(EXIT_ERRORS)
        }
    }
}

pub fn convert(input: &Path, to: &str, out: Option<&Path>) -> i32 {
    let (pipeline, text) = match load(input) {
        Ok(x) => x,
        Err(code) => return code,
    };
    let printed = match to {
        "ron" => ron::print::print(&pipeline, Some(&text)),
        "lbp" => lbp::print::print(&pipeline, Some(&text)),
        other => return usage_error(format!("--to {other}: expected `ron` or `lbp`")),
    };
    match out {
        Some(o) => match write_atomic(o, printed.as_bytes()) {
            Ok(()) => EXIT_OK,
            Err(e) => {
                eprintln!("error: {e}");
                EXIT_ERRORS
            }
        },
        None => {
            print!("{printed}");
            EXIT_OK
        }
    }
}

/// Rewrite an `.lbp` file in canonical layout; with `check`, only report whether it already is.
pub fn fmt(file: &Path, check: bool) -> i32 {
    if file.extension().and_then(|e| e.to_str()) != Some("lbp") {
        return usage_error(format!("{}: `fmt` formats .lbp files", file.display()));
    }
    let (pipeline, text) = match load(file) {
        Ok(x) => x,
        Err(code) => return code,
    };
    let printed = lbp::print::print(&pipeline, Some(&text));
    if printed == text {
        return EXIT_OK;
    }
    if check {
        eprintln!("{} is not formatted", file.display());
        return EXIT_ERRORS;
    }
    match write_atomic(file, printed.as_bytes()) {
        Ok(()) => EXIT_OK,
        Err(e) => {
            eprintln!("error: {e}");
            EXIT_ERRORS
        }
    }
}
