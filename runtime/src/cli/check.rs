//! `lightbench check`: front end, shader validation and every check stage, no GPU.

use super::{usage_error, Format, EXIT_ERRORS, EXIT_OK, EXIT_USAGE};
use lightbench_compiler::diag::{Code, Diagnostic, Severity};
use lightbench_compiler::scene::{file_kind, FileKind};
use lightbench_compiler::{pipeline_files, Session, Workspace};
use std::path::{Path, PathBuf};

pub fn run(paths: &[PathBuf], format: Format, profile: &str, scene: Option<&str>, shaders: Option<&Path>, params: &[String]) -> i32 {
    let profile = match super::profile(profile) {
        Ok(p) => p,
        Err(e) => return refuse(format, e.to_string()),
    };
    let files = match files_of(paths) {
        Ok(f) => f,
        Err(e) => return refuse(format, e),
    };
    // Pipelines in one run share compiled shaders.
    let ws = Workspace::disk();
    if let Err(e) = check_params(&ws, &files, (shaders, &profile), params) {
        return refuse(format, e.to_string());
    }
    let (mut errors, mut warnings, mut scenes, mut sweeps) = (0, 0, 0, 0);
    // What planning needs of the scene (its models' JSON, no geometry or texture), once for
    // every pipeline.
    let scene_features = match scene {
        Some(spec) => {
            let mut s = ws.session();
            let loaded = crate::scene::features_in(&mut s, spec);
            emit(&s, format); // warnings too (skipped primitives, unsupported material modes)
            warnings += s.diags.warning_count();
            match loaded {
                Some(features) => Some(features),
                None => return EXIT_ERRORS,
            }
        }
        None => None,
    };
    // The pipeline files checked as one run (in parallel, each shader compiled once); the
    // report keeps the order of the files.
    let kinds: Vec<FileKind> = files.iter().map(|f| kind(f)).collect();
    let pipelines: Vec<PathBuf> = files
        .iter()
        .zip(&kinds)
        .filter(|(_, k)| **k == FileKind::Pipeline)
        .map(|(f, _)| f.clone())
        .collect();
    let mut checked = ws.check_files(&pipelines, shaders, &profile, scene_features.as_ref()).into_iter();
    for (f, kind) in files.iter().zip(kinds) {
        let s = match kind {
            // `kind` never says `Other`: such a file is checked as a pipeline.
            FileKind::Pipeline | FileKind::Other => match checked.next() {
                Some(s) => s,
                None => continue,
            },
            FileKind::Scene => {
                scenes += 1;
                // A scene file among the pipelines: checked as `render --scene` would read it.
                let mut s = ws.session();
                crate::scene::load_in(&mut s, &f.display().to_string());
                s
            }
            FileKind::Sweep => {
                sweeps += 1;
                // A sweep spec (`init` writes them into `sweeps/`): checked as `sweep` reads it.
                let mut s = ws.session();
                if let Err(e) = crate::sweep::spec::load(f) {
                    let msg = match e {
                        crate::error::Error::Usage(m) | crate::error::Error::Input(m) => m,
                        e => e.to_string(),
                    };
                    s.diags.push(Diagnostic::unlocated(Severity::Error, Code::SweepSpec, msg));
                }
                s
            }
        };
        emit(&s, format);
        errors += s.diags.error_count();
        warnings += s.diags.warning_count();
    }
    if format == Format::Human {
        let mut others = String::new();
        if scenes > 0 {
            others += &format!(" and {scenes} scene file(s)");
        }
        if sweeps > 0 {
            others += &format!(" and {sweeps} sweep spec(s)");
        }
        let n = files.len() - scenes - sweeps;
        eprintln!(
            "checked {n} pipeline file(s){others} against profile `{}`: {errors} error(s), {warnings} warning(s)",
            profile.name
        );
    }
    if errors > 0 {
        EXIT_ERRORS
    } else {
        EXIT_OK
    }
}

/// A usage error in the format asked for: under `--format json`, one object as a diagnostic's
/// (`code` "usage", no file) on stdout, where a tool reading the output looks.
fn refuse(format: Format, msg: String) -> i32 {
    match format {
        Format::Human => usage_error(msg),
        Format::Json => {
            let obj = serde_json::json!({"severity": "error", "code": "usage", "message": msg, "notes": [], "labels": [], "file": null});
            println!("{obj}");
            EXIT_USAGE
        }
    }
}

/// The files the paths name: each file, and the pipeline and scene files below each directory.
fn files_of(paths: &[PathBuf]) -> std::result::Result<Vec<PathBuf>, String> {
    let mut files = vec![];
    for p in paths {
        let Ok(meta) = std::fs::metadata(p) else {
            return Err(format!("no such file or directory: {}", p.display()));
        };
        if !meta.is_file() && !meta.is_dir() {
            return Err(format!(
                "{} is not a regular file or a directory (a device, pipe or socket): nothing to check",
                p.display()
            ));
        }
        match pipeline_files(p) {
            Ok(f) if f.is_empty() => return Err(format!("no pipeline files (.ron, .lbp) in {}", p.display())),
            Ok(f) => files.extend(f),
            Err(e) => return Err(format!("cannot list {}: {e}", p.display())),
        }
    }
    Ok(files)
}

/// `--param` values: each name a parameter or per-pass value (`PASS.KEY`) of some pipeline,
/// and its value valid for every pipeline that has it. A pipeline that does not check
/// offers its declared parameters (its errors are reported with the others).
fn check_params(
    ws: &Workspace,
    files: &[PathBuf],
    (shaders, profile): (Option<&Path>, &lightbench_compiler::profile::Profile),
    params: &[String],
) -> crate::error::Result<()> {
    use lightbench_compiler::plan::{declared_param, pass_value_params};
    let params = super::parse_assignments("--param", "NAME=VALUE", params)?;
    if params.is_empty() {
        return Ok(());
    }
    let settable = |f: &PathBuf| match ws.session().load_checked(f, shaders, profile) {
        Some(c) => {
            let mut all: Vec<_> = c.pipeline.params.iter().map(declared_param).collect();
            all.extend(pass_value_params(&c));
            all
        }
        None => Session::new()
            .load_pipeline(f)
            .map(|p| p.params.iter().map(declared_param).collect())
            .unwrap_or_default(),
    };
    let declared: Vec<_> = files.iter().filter(|f| kind(f) == FileKind::Pipeline).flat_map(settable).collect();
    for (name, text) in &params {
        let decls: Vec<_> = declared.iter().filter(|p| &p.name == name).collect();
        if decls.is_empty() {
            let hint = lightbench_compiler::diag::did_you_mean(name, declared.iter().map(|p| p.name.as_str()))
                .map(|m| format!(" (did you mean `{m}`?)"))
                .unwrap_or_default();
            return Err(crate::error::Error::Usage(format!(
                "--param `{name}`: no checked pipeline has this parameter{hint}"
            )));
        }
        for p in decls {
            lightbench_compiler::plan::ParamValues::parse_text(std::slice::from_ref(p), name, text)
                .map_err(|e| crate::error::Error::Usage(format!("--param: {e}")))?;
        }
    }
    Ok(())
}

/// What a file given to `check` holds, read from disk as every user file is; a file that is
/// neither `.ron` nor `.lbp` is checked as a pipeline (and reported as of unknown format).
fn kind(f: &Path) -> FileKind {
    use lightbench_compiler::vfs::Vfs;
    let text = (f.extension().and_then(|e| e.to_str()) == Some("ron")).then(|| lightbench_compiler::vfs::DiskVfs.read(f).ok());
    match file_kind(f, text.flatten().as_deref()) {
        FileKind::Other => FileKind::Pipeline,
        k => k,
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
