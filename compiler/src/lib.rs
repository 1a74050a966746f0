//! lightbench-compiler: pipeline file -> IR -> checks -> Plan, with no GPU.
//!
//! ```text
//! pipeline file --front end--> IR --checks (naga-validated shaders)--> Checked
//! Checked + scene features + variant choice + capability profile --plan--> Plan
//! ```

pub mod check;
pub mod diag;
pub mod format;
pub mod front;
pub mod ir;
pub mod plan;
pub mod profile;
pub mod scene;
pub mod shader;
pub mod span;

use check::Checked;
use diag::{Diagnostic, Diagnostics, Severity};
use ir::Pipeline;
use plan::{Config, Plan};
use profile::Profile;
use scene::SceneFeatures;
use span::SourceMap;
use std::path::{Path, PathBuf};

/// A Plan together with the validated naga modules of its stages: what the runtime executes.
pub struct Executable {
    pub plan: Plan,
    /// (pass name, stage: "vertex" | "fragment" | "compute") -> module; entry names are in the plan.
    pub modules: std::collections::BTreeMap<(String, String), std::sync::Arc<shader::ShaderModule>>,
    /// Every file that went into it (pipeline, shaders, includes), for manifests and reloading.
    pub files: Vec<String>,
}

/// Everything a compilation touched and reported. Render diagnostics with `sources`.
#[derive(Default)]
pub struct Session {
    pub sources: SourceMap,
    pub diags: Diagnostics,
    /// Compiled shaders, shareable between sessions (`with_cache`) so that a run checking
    /// several pipelines validates each shared shader once.
    pub compiled: std::sync::Arc<shader::CompileCache>,
}

/// Where a pipeline's shader paths are resolved: an explicit root, else the first of
/// `<pipeline dir>/shaders`, `<pipeline dir>/../shaders` that exists, else the pipeline's dir.
pub fn shader_root_for(pipeline: &Path, explicit: Option<&Path>) -> PathBuf {
    if let Some(e) = explicit {
        return e.to_path_buf();
    }
    let dir = pipeline.parent().map(Path::to_path_buf).unwrap_or_default();
    let dir = if dir.as_os_str().is_empty() { PathBuf::from(".") } else { dir };
    for cand in [dir.join("shaders"), dir.join("..").join("shaders")] {
        if cand.is_dir() {
            return normalize(&cand);
        }
    }
    dir
}

/// Remove `.` and `dir/..` pairs lexically so diagnostics show `shaders/x.wgsl`,
/// not `pipelines/../shaders/x.wgsl` (no file system access, symlinks untouched).
fn normalize(p: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component> = vec![];
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    if out.is_empty() {
        return PathBuf::from(".");
    }
    out.iter().collect()
}

/// Pipeline files under a path: the file itself, or every `.ron`/`.lbp` file below a directory.
pub fn pipeline_files(path: &Path) -> std::io::Result<Vec<PathBuf>> {
    if path.is_file() {
        return Ok(vec![path.to_path_buf()]);
    }
    let mut out = vec![];
    let mut dirs = vec![path.to_path_buf()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d)? {
            let p = e?.path();
            if p.is_dir() {
                dirs.push(p);
            } else if matches!(p.extension().and_then(|e| e.to_str()), Some("ron" | "lbp")) {
                out.push(p);
            }
        }
    }
    out.sort();
    Ok(out)
}

impl Session {
    pub fn new() -> Self {
        Self::default()
    }

    /// A session that shares compiled shaders with others holding the same cache.
    pub fn with_cache(compiled: std::sync::Arc<shader::CompileCache>) -> Self {
        Session {
            compiled,
            ..Self::default()
        }
    }

    /// Read and parse a pipeline file into IR (front end chosen by extension).
    pub fn load_pipeline(&mut self, path: &Path) -> Option<Pipeline> {
        let name = path.display().to_string();
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) => {
                self.diags.push(Diagnostic::unlocated(
                    Severity::Error,
                    "file-not-found",
                    format!("cannot read pipeline `{name}`: {e}"),
                ));
                return None;
            }
        };
        self.parse_pipeline(&name, text)
    }

    /// Parse pipeline text; `name` decides the front end by extension and is shown in diagnostics.
    pub fn parse_pipeline(&mut self, name: &str, text: String) -> Option<Pipeline> {
        let file = self.sources.add(name, text.clone());
        match Path::new(name).extension().and_then(|e| e.to_str()) {
            Some("ron") => front::ron::parse_pipeline(file, &text, &mut self.diags),
            Some("lbp") => front::lbp::parse_pipeline(file, &text, &mut self.diags),
            other => {
                self.diags.push(Diagnostic::unlocated(
                    Severity::Error,
                    "unknown-format",
                    format!(
                        "`{name}`: unknown pipeline format `{}` (expected `.ron` or `.lbp`)",
                        other.unwrap_or("")
                    ),
                ));
                None
            }
        }
    }

    /// Run every pipeline-wide check (declarations, shaders, bindings, IO, limits).
    pub fn check(&mut self, pipeline: Pipeline, shader_root: &Path, profile: &Profile) -> Checked {
        let mut loader = shader::ShaderLoader::new(shader_root.to_path_buf(), self.compiled.clone());
        check::check_pipeline(pipeline, profile, &mut loader, &mut self.sources, &mut self.diags)
    }

    /// Plan one configuration. `None` when it has errors (they are in `diags`).
    pub fn plan(&mut self, checked: &Checked, profile: &Profile, scene: &SceneFeatures, variants: &[(String, String)]) -> Option<Plan> {
        if self.diags.has_errors() {
            return None;
        }
        let selection = plan::build::select(&checked.pipeline, profile, variants, &mut self.diags)?;
        let cfg = Config { profile, scene, selection };
        plan::build_plan(checked, &cfg, &mut self.diags)
    }

    /// Plan every configuration `check` covers: the defaults, then each option of each variant
    /// (others at their default); for `scene`, or else for a scene calling for every effect and
    /// one calling for none (both with every light kind), so both sides of effect conditions
    /// are checked.
    pub fn check_configurations(&mut self, checked: &Checked, profile: &Profile, scene: Option<&SceneFeatures>) {
        let scenes = match scene {
            Some(s) => vec![s.clone()],
            // A scene without effects only changes something if some condition asks for one.
            None if !checked
                .pipeline
                .passes
                .iter()
                .any(|p| p.when.as_ref().is_some_and(|w| w.mentions_scene_effects())) =>
            {
                vec![SceneFeatures::everything()]
            }
            None => {
                let mut plain = SceneFeatures::everything();
                plain.name = "<no effects>".into();
                plain.effects.clear();
                plain.reflective = false;
                vec![SceneFeatures::everything(), plain]
            }
        };
        let mut configs: Vec<Vec<(String, String)>> = vec![vec![]];
        for v in &checked.pipeline.variants {
            for o in &v.options {
                configs.push(vec![(v.name.value.clone(), o.name.value.clone())]);
            }
        }
        let mut seen: Vec<std::collections::BTreeMap<String, String>> = vec![];
        for scene in &scenes {
            seen.clear();
            for c in &configs {
                let Some(selection) = plan::build::select(&checked.pipeline, profile, c, &mut self.diags) else {
                    continue;
                };
                // Requesting the default option, or one that falls back to an option already
                // planned, gives a configuration already checked.
                if seen.contains(&selection.chosen) {
                    continue;
                }
                seen.push(selection.chosen.clone());
                let cfg = Config { profile, scene, selection };
                plan::build::schedule(checked, &cfg, &mut self.diags);
            }
        }
    }

    /// Load and check a pipeline file; `None` when it has errors (they are in `diags`).
    fn load_checked(&mut self, path: &Path, shader_root: Option<&Path>, profile: &Profile) -> Option<Checked> {
        let p = self.load_pipeline(path)?;
        let root = shader_root_for(path, shader_root);
        let checked = self.check(p, &root, profile);
        (!self.diags.has_errors()).then_some(checked)
    }

    /// Load, check and plan a pipeline file in one go.
    pub fn plan_file(
        &mut self,
        path: &Path,
        shader_root: Option<&Path>,
        profile: &Profile,
        scene: &SceneFeatures,
        variants: &[(String, String)],
    ) -> Option<Plan> {
        let checked = self.load_checked(path, shader_root, profile)?;
        self.plan(&checked, profile, scene, variants)
    }

    /// Load, check and plan a pipeline file, keeping the shader modules for execution.
    pub fn executable(
        &mut self,
        path: &Path,
        shader_root: Option<&Path>,
        profile: &Profile,
        scene: &SceneFeatures,
        variants: &[(String, String)],
    ) -> Option<Executable> {
        let checked = self.load_checked(path, shader_root, profile)?;
        let plan = self.plan(&checked, profile, scene, variants)?;
        let chosen: std::collections::BTreeMap<String, String> =
            plan.variants.iter().map(|v| (v.variant.clone(), v.option.clone())).collect();
        let mut modules = std::collections::BTreeMap::new();
        for (i, pass) in checked.pipeline.passes.iter().enumerate() {
            if plan.pass(&pass.name.value).is_none() {
                continue;
            }
            let version = checked.version(i, &chosen)?;
            for st in &version.stages {
                modules.insert(
                    (pass.name.value.clone(), check::entry::stage_word(st.stage).to_string()),
                    st.module.clone(),
                );
            }
        }
        let files = (0..self.sources.len())
            .map(|i| self.sources.get(i).name.clone())
            .filter(|n| !n.starts_with("<builtin>"))
            .collect();
        Some(Executable { plan, modules, files })
    }

    /// Load and check a pipeline file across its configurations (what `lightbench check` does).
    pub fn check_file(&mut self, path: &Path, shader_root: Option<&Path>, profile: &Profile, scene: Option<&SceneFeatures>) {
        let Some(checked) = self.load_checked(path, shader_root, profile) else {
            return;
        };
        self.check_configurations(&checked, profile, scene);
    }

    /// All diagnostics rendered rustc-style.
    pub fn render(&self) -> String {
        self.diags.list.iter().map(|d| d.render(&self.sources)).collect::<Vec<_>>().join("")
    }
}
