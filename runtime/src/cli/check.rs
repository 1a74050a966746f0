//! `lightbench check`: front end, shader validation and every check stage, no GPU.

use super::{usage_error, Format, EXIT_ERRORS, EXIT_OK};
use lightbench_compiler::scene::load_scene_features;
use lightbench_compiler::{pipeline_files, Session, Workspace};
use std::path::{Path, PathBuf};

pub fn run(paths: &[PathBuf], format: Format, profile: &str, scene: Option<&Path>, shaders: Option<&Path>) -> i32 {
    let profile = match super::profile(profile) {
        Ok(p) => p,
        Err(e) => return usage_error(e),
    };
    let mut files = vec![];
    for p in paths {
        if !p.exists() {
            return usage_error(format!("no such file or directory: {}", p.display()));
        }
        match pipeline_files(p) {
            Ok(f) if f.is_empty() => return usage_error(format!("no pipeline files (.ron, .lbp) in {}", p.display())),
            Ok(f) => files.extend(f),
            Err(e) => return usage_error(format!("cannot list {}: {e}", p.display())),
        }
    }
    let mut errors = 0;
    let mut warnings = 0;
    // Pipelines in one run share compiled shaders.
    let ws = Workspace::disk();
    for f in &files {
        let mut s = ws.session();
        let scene_features = match scene {
            Some(path) => match load_scene_features(&path.display().to_string(), &mut s.sources, &mut s.diags) {
                Some(sf) => Some(sf),
                None => {
                    emit(&s, format);
                    return EXIT_ERRORS;
                }
            },
            None => None,
        };
        s.check_file(f, shaders, &profile, scene_features.as_ref());
        emit(&s, format);
        errors += s.diags.error_count();
        warnings += s.diags.warning_count();
    }
    if format == Format::Human {
        eprintln!(
            "checked {} pipeline file(s) against profile `{}`: {errors} error(s), {warnings} warning(s)",
            files.len(),
            profile.name
        );
    }
    if errors > 0 {
        EXIT_ERRORS
    } else {
        EXIT_OK
    }
}

pub fn emit(s: &Session, format: Format) {
    match format {
        Format::Human => eprint!("{}", s.render()),
        Format::Json => {
            for d in &s.diags.list {
                println!("{}", d.to_json(&s.sources));
            }
        }
    }
}
