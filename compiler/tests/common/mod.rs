//! Test harness: write a pipeline and its shaders into a fresh directory and compile them
//! exactly as `lightbench check` does.

#![allow(dead_code)]

use lightbench_compiler::diag::Diagnostic;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

static COUNTER: AtomicUsize = AtomicUsize::new(0);

pub fn temp_dir(tag: &str) -> PathBuf {
    let n = COUNTER.fetch_add(1, Ordering::SeqCst);
    // Under cargo's temporary directory, named by test binary, tag and order (no process
    // id), so that running the suite again reuses these directories.
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{}-{tag}-{n}", env!("CARGO_CRATE_NAME")));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("pipelines")).unwrap();
    std::fs::create_dir_all(d.join("shaders")).unwrap();
    d
}

/// Files relative to the project dir: `pipelines/x.ron`, `shaders/y.wgsl`.
pub fn write_project(tag: &str, files: &[(&str, &str)]) -> PathBuf {
    let d = temp_dir(tag);
    for (path, text) in files {
        let p = d.join(path);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, text).unwrap();
    }
    d
}

pub struct Outcome {
    pub session: Session,
    pub dir: PathBuf,
}

impl Outcome {
    /// (code, message, file relative to the project dir, line, column) of each diagnostic.
    pub fn located(&self) -> Vec<(String, String, String, usize, usize)> {
        self.session
            .diags
            .list
            .iter()
            .map(|d| {
                let (f, l, c) = d.location(&self.session.sources).unwrap_or_default();
                let rel = Path::new(&f).strip_prefix(&self.dir).map(|p| p.display().to_string()).unwrap_or(f);
                (d.code.to_string(), d.message.clone(), rel, l, c)
            })
            .collect()
    }

    pub fn errors(&self) -> Vec<&Diagnostic> {
        self.session.diags.errors().collect()
    }

    pub fn dump(&self) -> String {
        self.session.render()
    }
}

pub fn check_project(dir: &Path, pipeline: &str, profile: &Profile, scene: Option<&SceneFeatures>) -> Outcome {
    let mut s = Session::new();
    let path = dir.join(pipeline);
    s.check_file(&path, None, profile, scene);
    Outcome {
        session: s,
        dir: dir.to_path_buf(),
    }
}

/// The repository root (for the bundled pipelines and shaders).
/// Write `files` as a project and plan its `pipelines/m.lbp` for every scene feature on the
/// Vulkan profile (a panic with the diagnostics if it does not plan).
#[allow(dead_code)]
pub fn plan_project(tag: &str, files: &[(&str, &str)]) -> lightbench_compiler::plan::Plan {
    let dir = write_project(tag, files);
    let mut s = lightbench_compiler::Session::new();
    let plan = s.plan_file(
        &dir.join("pipelines/m.lbp"),
        None,
        &Profile::vulkan(),
        &SceneFeatures::everything(),
        &[],
    );
    plan.unwrap_or_else(|| panic!("{}", s.render()))
}

pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// The README and every page of the manual (`docs/`), one text: what tests search for the
/// examples and tables the documentation shows.
pub fn manual() -> String {
    let mut pages: Vec<PathBuf> = std::fs::read_dir(repo_root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    pages.sort();
    std::iter::once(repo_root().join("README.md"))
        .chain(pages)
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

/// A Plan's passes as JSON without where each was written (`origin`, which `plan --explain`
/// shows): what a pipeline written with groups, templates or choices by light kind must plan
/// exactly like, its passes written out.
#[allow(dead_code)]
pub fn plain_passes(plan: &lightbench_compiler::plan::Plan) -> String {
    let mut passes = plan.passes.clone();
    passes.iter_mut().for_each(|p| p.origin = None);
    serde_json::to_string(&passes).unwrap()
}
