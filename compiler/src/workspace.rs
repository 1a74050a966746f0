//! The compile workspace: what a long-running process holds between compilations (the
//! virtual file system and the compiled-module cache), and the [`Session`] of one
//! compilation (its sources, diagnostics and the files it depended on).

use crate::check::{self, Checked};
use crate::diag::{Code, Diagnostic, Diagnostics, Severity};
use crate::ir::Pipeline;
use crate::plan::{self, Config, ParamValues, Plan};
use crate::profile::Profile;
use crate::scene::SceneFeatures;
use crate::shader::{ModuleCache, ShaderLoader, ShaderModule};
use crate::span::SourceMap;
use crate::tree::Node;
use crate::vfs::{normalize, DiskVfs, Vfs};
use rayon::prelude::*;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Pipelines using pipelines, at most this deep.
pub const MAX_USE_DEPTH: usize = 8;

/// `deferred.ron` for `pipelines/deferred.ron`: how a pass's origin reads.
fn file_name(path: &str) -> String {
    Path::new(path)
        .file_name()
        .map_or(path.to_string(), |f| f.to_string_lossy().into_owned())
}

/// A Plan together with the validated modules of its stages: what the runtime executes.
pub struct Executable {
    pub plan: Plan,
    /// Per Plan pass, the module of each of its stages (aligned with `PlanPass::stages`).
    pub modules: Vec<Vec<Arc<ShaderModule>>>,
    /// Every file the compilation read or tried to read (pipeline, shaders, includes):
    /// what a watcher watches and a manifest hashes.
    pub files: BTreeSet<PathBuf>,
}

/// What a long-running process keeps between compilations.
#[derive(Clone)]
pub struct Workspace {
    vfs: Arc<dyn Vfs>,
    modules: Arc<ModuleCache>,
}

impl Default for Workspace {
    fn default() -> Self {
        Workspace::new(Arc::new(DiskVfs))
    }
}

impl Workspace {
    pub fn new(vfs: Arc<dyn Vfs>) -> Self {
        Workspace {
            vfs,
            modules: Arc::new(ModuleCache::default()),
        }
    }

    /// Reading the real file system.
    pub fn disk() -> Self {
        Self::default()
    }

    /// Keep at most `n` compiled modules (least recently used evicted first).
    pub fn with_module_capacity(mut self, n: usize) -> Self {
        self.modules = Arc::new(ModuleCache::with_capacity(n));
        self
    }

    /// What the compiled-module cache did so far: compilations, hits, evictions, entries.
    pub fn module_stats(&self) -> crate::shader::cache::CacheStats {
        self.modules.stats()
    }

    /// A new compilation sharing this workspace's files and compiled modules.
    pub fn session(&self) -> Session {
        Session {
            sources: SourceMap::new(),
            diags: Diagnostics::default(),
            vfs: self.vfs.clone(),
            modules: self.modules.clone(),
            dependencies: BTreeSet::new(),
            run: None,
            origins: vec![],
        }
    }

    /// `Session::check_file` over several files as one run (what `lightbench check` does):
    /// the files checked in parallel, a shader they share compiled once (the module cache
    /// lets the others wait for it). One session per file, in the order given, holding that
    /// file's diagnostics.
    pub fn check_files(
        &self,
        files: &[PathBuf],
        shader_root: Option<&Path>,
        profile: &Profile,
        scene: Option<&SceneFeatures>,
    ) -> Vec<Session> {
        // One read of each file for all of them; the sessions keep the workspace's view.
        let snapshot: Arc<dyn Vfs> = Arc::new(crate::vfs::Snapshot::new(self.vfs.clone()));
        let run = Arc::new(Run::default());
        files
            .par_iter()
            .map(|f| {
                let mut s = self.session();
                s.vfs = snapshot.clone();
                s.run = Some(run.clone());
                s.check_file(f, shader_root, profile, scene);
                s.vfs = self.vfs.clone();
                s.run = None;
                s
            })
            .collect()
    }

    pub fn modules(&self) -> &ModuleCache {
        &self.modules
    }

    pub fn vfs(&self) -> &Arc<dyn Vfs> {
        &self.vfs
    }
}

/// One compilation: everything it touched and reported. Render diagnostics with `sources`.
pub struct Session {
    pub sources: SourceMap,
    pub diags: Diagnostics,
    vfs: Arc<dyn Vfs>,
    modules: Arc<ModuleCache>,
    dependencies: BTreeSet<PathBuf>,
    /// What the sessions of one run (`check_files`) share, if part of one.
    run: Option<Arc<Run>>,
    /// Where the passes of the files being composed were written (stage `origins`).
    origins: Vec<crate::syntax::origins::Origin>,
}

/// What the sessions of one run made of the files of its snapshot, for the others to take.
#[derive(Default)]
struct Run {
    trees: Trees,
    data: check::data::Decoded,
    expansions: Arc<crate::shader::Expansions>,
}

/// The pipeline files the sessions of one run parsed without a word of complaint: a file
/// several pipelines use (`deferred_gi` uses `deferred`) is parsed once. Keyed by the name
/// diagnostics show; the text must match.
#[derive(Default)]
struct Trees(crate::memo::Memo<String, Arc<(String, Node)>>);

impl Trees {
    /// The tree of `text` if another session parsed it, its spans moved into `file`.
    fn get(&self, name: &str, text: &str, file: crate::span::FileId) -> Option<Node> {
        let kept = self.0.get(name).filter(|k| k.0 == text)?;
        Some(crate::tree::refile(&kept.1, file))
    }

    fn put(&self, name: &str, text: &str, tree: &Node) {
        self.0.put(name.to_string(), Arc::new((text.to_string(), tree.clone())));
    }
}

impl Default for Session {
    fn default() -> Self {
        Workspace::disk().session()
    }
}

/// Where a pipeline's shader paths are resolved: an explicit root, else the first existing
/// folder of `shader_candidates`, else the pipeline's own folder.
pub fn shader_root_for(vfs: &dyn Vfs, pipeline: &Path, explicit: Option<&Path>) -> PathBuf {
    if let Some(e) = explicit {
        return e.to_path_buf();
    }
    shader_candidates(pipeline)
        .into_iter()
        .find(|c| vfs.is_dir(c))
        .unwrap_or_else(|| pipeline_dir(pipeline))
}

fn pipeline_dir(pipeline: &Path) -> PathBuf {
    let dir = pipeline.parent().map(Path::to_path_buf).unwrap_or_default();
    if dir.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        dir
    }
}

/// The `shaders/` folders a pipeline looks for, nearest first: beside it, one folder up,
/// and beside the nearest enclosing `pipelines/` folder — so `pipelines/sub/deeper/p.ron`
/// finds its project's `shaders/`, while a pipeline outside any `pipelines/` folder never
/// climbs into an unrelated project above it.
pub fn shader_candidates(pipeline: &Path) -> Vec<PathBuf> {
    let dir = pipeline_dir(pipeline);
    let mut out = vec![normalize(&dir.join("shaders")), normalize(&dir.join("..").join("shaders"))];
    let absolute = std::path::absolute(&dir).unwrap_or_else(|_| dir.clone());
    let project = absolute.ancestors().find(|a| a.file_name().is_some_and(|n| n == "pipelines"));
    if let Some(shaders) = project.and_then(Path::parent).map(|root| root.join("shaders")) {
        if !out.iter().any(|c| std::path::absolute(c).is_ok_and(|a| normalize(&a) == shaders)) {
            out.push(shaders);
        }
    }
    out
}

/// Said where a shader is not found: the folder paths resolve against, and when no
/// `shaders/` folder was found, the ones looked for.
fn shader_root_note(vfs: &dyn Vfs, pipeline: &Path, root: &Path) -> String {
    let candidates = shader_candidates(pipeline);
    if root == pipeline_dir(pipeline) && !candidates.iter().any(|c| vfs.is_dir(c)) {
        let list: Vec<String> = candidates.iter().map(|c| format!("`{}`", c.display())).collect();
        format!(
            "no `shaders/` folder at {}: shader paths resolve against the pipeline's folder `{}` (or give `--shaders DIR`)",
            list.join(", "),
            root.display()
        )
    } else {
        format!("shader paths resolve against `{}`", root.display())
    }
}

/// Pipeline files under a path on disk: the file itself, or every `.ron`/`.lbp` file below a
/// directory (see [`files_below`]).
pub fn pipeline_files(path: &Path) -> std::io::Result<Vec<PathBuf>> {
    if path.is_file() {
        return Ok(vec![path.to_path_buf()]);
    }
    files_below(path, |p| matches!(p.extension().and_then(|e| e.to_str()), Some("ron" | "lbp")))
}

/// Every file below a directory that `keep` accepts, sorted (hidden directories such as `.git`
/// are skipped). Symlinks are followed, but each directory and each file (by its canonical
/// path) is visited once, so symlink loops end and a linked file is listed once.
pub fn files_below(path: &Path, keep: impl Fn(&Path) -> bool) -> std::io::Result<Vec<PathBuf>> {
    let mut out = vec![];
    let mut seen_dirs = BTreeSet::new();
    let mut seen_files = BTreeSet::new();
    let mut dirs = vec![path.to_path_buf()];
    while let Some(d) = dirs.pop() {
        // A dangling or unreadable link is skipped like any non-pipeline entry.
        let Ok(canonical) = std::fs::canonicalize(&d) else { continue };
        if !seen_dirs.insert(canonical) {
            continue;
        }
        let mut entries: Vec<PathBuf> = std::fs::read_dir(&d)?.filter_map(|e| e.ok().map(|e| e.path())).collect();
        entries.sort();
        for p in entries {
            let hidden = p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.starts_with('.'));
            if p.is_dir() && !hidden {
                dirs.push(p);
            } else if p.is_file() && keep(&p) {
                if let Ok(c) = std::fs::canonicalize(&p) {
                    if seen_files.insert(c) {
                        out.push(p);
                    }
                }
            }
        }
    }
    out.sort();
    Ok(out)
}

impl Session {
    /// A standalone compilation reading the disk (with a cache of its own).
    pub fn new() -> Self {
        Self::default()
    }

    /// Every file this compilation read or tried to read.
    pub fn dependencies(&self) -> &BTreeSet<PathBuf> {
        &self.dependencies
    }

    /// A built-in scene or scene file, through this session's file system (see `scene::load`).
    pub fn load_scene(&mut self, spec: &str) -> Option<crate::scene::SceneDesc> {
        if crate::scene::builtin::by_name(spec).is_none() {
            self.dependencies.insert(PathBuf::from(spec));
        }
        crate::scene::load(self.vfs.as_ref(), spec, &mut self.sources, &mut self.diags)
    }

    /// Read and parse a pipeline file into IR (front end chosen by extension).
    pub fn load_pipeline(&mut self, path: &Path) -> Option<Pipeline> {
        let (name, text) = self.read_pipeline(path)?;
        self.parse_pipeline(&name, text)
    }

    /// A pipeline file's name (as diagnostics show it) and text.
    fn read_pipeline(&mut self, path: &Path) -> Option<(String, String)> {
        let name = path.display().to_string();
        self.dependencies.insert(path.to_path_buf());
        let text = match self.vfs.read(path) {
            Ok(t) => t,
            Err(e) => {
                let msg = format!("cannot read pipeline `{name}`: {e}");
                let code = crate::vfs::read_error_code(&e);
                // Invalid UTF-8 is located at its first bad byte (the text shown with it
                // replaced), so `--format json` has its line and column too.
                let d = match e.get_ref().and_then(|i| i.downcast_ref::<crate::vfs::InvalidUtf8>()) {
                    Some(bad) => {
                        let file = self.sources.add(name.clone(), bad.text.clone());
                        // U+FFFD stands where the bad bytes began: three bytes.
                        let end = (bad.at + 3).min(bad.text.len());
                        Diagnostic::error(code, msg, crate::span::Span::new(file, bad.at, end))
                    }
                    None => Diagnostic::unlocated(Severity::Error, code, msg),
                };
                self.diags.push(d);
                return None;
            }
        };
        Some((name, text))
    }

    /// Parse pipeline text; `name` decides the front end by extension and is shown in diagnostics.
    pub fn parse_pipeline(&mut self, name: &str, text: String) -> Option<Pipeline> {
        match self.parse_pipeline_partial(name, text) {
            (Some(p), true) => Some(p),
            _ => None,
        }
    }

    /// Parse pipeline text: the pipeline and `true`, or (when lowering reported errors) what
    /// of it did lower and `false`, for the checks that do not depend on what was left out.
    fn parse_pipeline_partial(&mut self, name: &str, text: String) -> (Option<Pipeline>, bool) {
        let file = self.sources.add(name, text.clone());
        let tree = match Path::new(name).extension().and_then(|e| e.to_str()) {
            Some(ext @ ("ron" | "lbp")) => self.parse_tree(ext, name, &text, file),
            other => {
                self.diags.push(Diagnostic::unlocated(
                    Severity::Error,
                    Code::UnknownFormat,
                    format!(
                        "`{name}`: unknown pipeline format `{}` (expected `.ron` or `.lbp`)",
                        other.unwrap_or("")
                    ),
                ));
                None
            }
        };
        let Some(tree) = tree else { return (None, false) };
        let before = self.diags.error_count();
        self.origins.clear();
        let merged = self.compose(name, &tree, &mut vec![]);
        let mut p = merged.and_then(|m| crate::syntax::lower::pipeline_partial(&m, &mut self.diags));
        if let Some(p) = p.as_mut() {
            // By the span the pass was written at (the expansion stages keep it).
            let origins: HashMap<_, _> = std::mem::take(&mut self.origins).into_iter().map(|o| (o.span, o)).collect();
            for pass in &mut p.passes {
                pass.origin = origins.get(&pass.span).and_then(|o| o.describe(&pass.name.value));
            }
        }
        // A pipeline that uses another, or groups passes, prints as written.
        let as_written = crate::syntax::compose::used(&tree).is_some()
            || crate::syntax::groups::has_groups(&tree)
            || crate::syntax::templates::has_templates(&tree)
            || crate::syntax::light_choices::has_light_choices(&tree);
        if let Some(p) = p.as_mut().filter(|_| as_written) {
            p.written = Some(crate::ir::Source(tree));
            for pass in p.passes.iter_mut().filter(|x| x.span.file != file) {
                pass.from = Some(file_name(&self.sources.get(pass.span.file).name));
            }
        }
        (p, self.diags.error_count() == before)
    }

    /// The syntax tree of a pipeline file (`ext`: `ron` or `lbp`), added as `file`: parsed,
    /// or another session's parse of the same text in this run.
    fn parse_tree(&mut self, ext: &str, name: &str, text: &str, file: crate::span::FileId) -> Option<Node> {
        if let Some(tree) = self.run.as_ref().and_then(|r| r.trees.get(name, text, file)) {
            return Some(tree);
        }
        let before = self.diags.list.len();
        let tree = match ext {
            "ron" => crate::front::ron::parse_tree(file, text, &mut self.diags),
            _ => crate::front::lbp::parse_tree(file, text, &mut self.diags),
        };
        // Only a parse that said nothing is shared: each session reports its own warnings.
        if let (Some(run), Some(tree), true) = (&self.run, &tree, self.diags.list.len() == before) {
            run.trees.put(name, text, tree);
        }
        tree
    }

    /// The pipeline a tree means: itself, or the pipeline it uses (composed in turn) with its
    /// items merged in. `chain`: the files being composed, for cycles and the depth limit.
    fn compose(&mut self, name: &str, tree: &Node, chain: &mut Vec<PathBuf>) -> Option<Node> {
        // Each file's templates give their attributes, its groups become their passes, and
        // passes choosing by light kind one pass per kind they tell apart, before items merge
        // by name.
        self.origins.extend(crate::syntax::origins::of(tree));
        let tree = &crate::syntax::templates::expand(tree, &mut self.diags);
        let tree = &crate::syntax::groups::expand(tree, &mut self.diags);
        let tree = &crate::syntax::light_choices::expand(tree, &mut self.diags);
        crate::syntax::compose::reject_second_use(tree, &mut self.diags);
        let Some((used, at)) = crate::syntax::compose::used(tree) else {
            crate::syntax::compose::reject_composing(tree, &mut self.diags);
            return Some(tree.clone());
        };
        let here = Path::new(name);
        let dir = here.parent().unwrap_or(Path::new("")).to_path_buf();
        let path = normalize(&dir.join(&used));
        // The confinement data files have (links are resolved when reading, `read_used`).
        let problem = if crate::shader::include::confined(&used).is_err() {
            Some((
                Code::OutsideRoot,
                format!("`{used}`: a used pipeline is a file in this pipeline's directory (or below it)"),
            ))
        } else if chain.contains(&path) || path == normalize(here) {
            // In the order they are written: the first file's `use` first.
            let names: Vec<String> = chain
                .iter()
                .map(|p| p.as_path())
                .chain([here, path.as_path()])
                .map(|p| p.display().to_string())
                .collect();
            Some((Code::IncludeCycle, format!("pipelines use each other: {}", names.join(" -> "))))
        } else if chain.len() >= MAX_USE_DEPTH {
            Some((Code::NestingTooDeep, format!("pipelines use others more than {MAX_USE_DEPTH} deep")))
        } else {
            None
        };
        if let Some((code, msg)) = problem {
            self.diags.push(Diagnostic::error(code, msg, at));
            return None;
        }
        let base = self.read_used(&dir, &path, at)?;
        chain.push(normalize(here));
        let base = self.compose(&path.display().to_string(), &base, chain);
        chain.pop();
        Some(crate::syntax::compose::merge(&base?, tree, &mut self.diags))
    }

    /// A used pipeline file's tree; a file that cannot be read, or that a link takes out of
    /// `dir`, is an error at the `use`.
    fn read_used(&mut self, dir: &Path, path: &Path, at: crate::span::Span) -> Option<Node> {
        let name = path.display().to_string();
        self.dependencies.insert(path.to_path_buf());
        let text = match self.vfs.within(dir, path).and_then(|()| self.vfs.read(path)) {
            Ok(t) => t,
            Err(e) => {
                let code = crate::vfs::read_error_code(&e);
                self.diags
                    .push(Diagnostic::error(code, format!("cannot read the used pipeline `{name}`: {e}"), at));
                return None;
            }
        };
        let file = self.sources.add(name.clone(), text.clone());
        match path.extension().and_then(|e| e.to_str()) {
            Some(ext @ ("ron" | "lbp")) => self.parse_tree(ext, &name, &text, file),
            _ => {
                let msg = format!("`{name}`: unknown pipeline format (expected `.ron` or `.lbp`)");
                self.diags.push(Diagnostic::error(Code::UnknownFormat, msg, at));
                None
            }
        }
    }

    /// Run every pipeline-wide check (declarations, shaders, bindings, IO, limits).
    pub fn check(&mut self, pipeline: Pipeline, shader_root: &Path, profile: &Profile) -> Checked {
        let file = self.sources.get(pipeline.span.file).name.clone();
        let mut loader = ShaderLoader::new(shader_root.to_path_buf(), self.vfs.clone(), self.modules.clone());
        loader.not_found_note = Some(shader_root_note(self.vfs.as_ref(), Path::new(&file), shader_root));
        loader.expansions = self.run.as_ref().map(|r| r.expansions.clone());
        let mut checked = check::check_pipeline(pipeline, profile, &mut loader, &mut self.sources, &mut self.diags);
        self.dependencies.extend(loader.dependencies);
        let mut ctx = check::data::DataCtx {
            vfs: self.vfs.as_ref(),
            dir: Path::new(&file).parent().map(Path::to_path_buf).unwrap_or_default(),
            read: &mut self.dependencies,
            decoded: self.run.as_ref().map(|r| &r.data),
        };
        checked.data = check::data::check(&checked.pipeline, &mut ctx, &mut self.diags);
        checked
    }

    /// Plan one configuration. `None` when it has errors (they are in `diags`).
    pub fn plan(&mut self, checked: &Checked, profile: &Profile, scene: &SceneFeatures, variants: &[(String, String)]) -> Option<Plan> {
        self.plan_with(checked, (profile, scene), variants, &ParamValues::new())
    }

    /// `plan` with parameter overrides that size resources (`size: Param(..)`).
    pub fn plan_with(
        &mut self,
        checked: &Checked,
        (profile, scene): (&Profile, &SceneFeatures),
        variants: &[(String, String)],
        params: &ParamValues,
    ) -> Option<Plan> {
        if self.diags.has_errors() {
            return None;
        }
        let selection = plan::select(&checked.pipeline, profile, variants, &mut self.diags)?;
        let cfg = Config {
            profile,
            scene,
            selection,
            params,
            scene_known: true,
            orders: None,
        };
        plan::build_plan(checked, &cfg, &mut self.diags)
    }

    /// Plan every configuration `check` covers (the full Plan, as `render` would build it): the defaults, then each option of each variant
    /// (others at their default); for `scene`, or else for a scene calling for every effect and
    /// one calling for none (both with every light kind), so both sides of effect conditions
    /// are checked.
    pub fn check_configurations(&mut self, checked: &Checked, profile: &Profile, scene: Option<&SceneFeatures>) {
        let scene_given = scene.is_some();
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
        // Selection is cheap and reports in order; the plans are independent, so they are
        // built in parallel, each into its own diagnostics, merged in configuration order
        // (the same merge as a serial run: `push` folds repeats into "also here").
        let mut jobs = vec![];
        for scene in &scenes {
            let mut seen: Vec<BTreeMap<String, String>> = vec![];
            for c in &configs {
                let Some(selection) = plan::select(&checked.pipeline, profile, c, &mut self.diags) else {
                    continue;
                };
                // Requesting the default option, or one that falls back to an option already
                // planned, gives a configuration already checked.
                if seen.contains(&selection.chosen) {
                    continue;
                }
                seen.push(selection.chosen.clone());
                jobs.push((scene, selection));
            }
        }
        let none = ParamValues::new();
        let orders = crate::plan::order::Orders::default();
        let found: Vec<Diagnostics> = jobs
            .into_par_iter()
            .map(|(scene, selection)| {
                let cfg = Config {
                    profile,
                    scene,
                    selection,
                    params: &none,
                    scene_known: scene_given,
                    orders: Some(&orders),
                };
                let mut diags = Diagnostics::default();
                // Every stage of planning that can fail, sizing included (extents, mips).
                plan::check_configuration(checked, &cfg, &mut diags);
                diags
            })
            .collect();
        for d in found.into_iter().flat_map(|d| d.list) {
            self.diags.push(d);
        }
    }

    /// Load and check a pipeline file; `None` when it has errors (they are in `diags`). When
    /// some values do not lower, the shaders of the passes that did are still checked.
    pub fn load_checked(&mut self, path: &Path, shader_root: Option<&Path>, profile: &Profile) -> Option<Checked> {
        let (p, root) = self.load_for_check(path, shader_root, profile)?;
        let checked = self.check(p, &root, profile);
        (!self.diags.has_errors()).then_some(checked)
    }

    /// The front half of `load_checked`: a pipeline that lowered whole, with the folder its
    /// shader paths resolve in. One some of whose values did not lower has the shaders of
    /// the passes that did checked here, and gives `None`.
    fn load_for_check(&mut self, path: &Path, shader_root: Option<&Path>, profile: &Profile) -> Option<(Pipeline, PathBuf)> {
        let (name, text) = self.read_pipeline(path)?;
        let root = shader_root_for(self.vfs.as_ref(), path, shader_root);
        match self.parse_pipeline_partial(&name, text) {
            (Some(p), true) => Some((p, root)),
            (partial, _) => {
                if let Some(partial) = partial {
                    let mut loader = ShaderLoader::new(root, self.vfs.clone(), self.modules.clone());
                    check::check_shaders(&partial, profile, &mut loader, &mut self.sources, &mut self.diags);
                    self.dependencies.extend(loader.dependencies);
                }
                None
            }
        }
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
        self.executable(path, shader_root, profile, scene, variants).map(|e| e.plan)
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
        self.executable_with(path, shader_root, (profile, scene), variants, &ParamValues::new())
    }

    /// `executable` with parameter overrides that size resources (`size: Param(..)`).
    pub fn executable_with(
        &mut self,
        path: &Path,
        shader_root: Option<&Path>,
        (profile, scene): (&Profile, &SceneFeatures),
        variants: &[(String, String)],
        params: &ParamValues,
    ) -> Option<Executable> {
        let checked = self.load_checked(path, shader_root, profile)?;
        let plan = self.plan_with(&checked, (profile, scene), variants, params)?;
        let chosen: BTreeMap<String, String> = plan.variants.iter().map(|v| (v.variant.clone(), v.option.clone())).collect();
        let mut modules = vec![];
        for pp in &plan.passes {
            let (i, _) = checked.pipeline.pass_chosen(&pp.name, &chosen)?;
            let version = checked.version(i, &chosen)?;
            modules.push(version.stages.iter().map(|st| st.module.clone()).collect());
        }
        Some(Executable {
            plan,
            modules,
            files: self.dependencies.clone(),
        })
    }

    /// Load and check a pipeline file across its configurations (what `lightbench check` does).
    pub fn check_file(&mut self, path: &Path, shader_root: Option<&Path>, profile: &Profile, scene: Option<&SceneFeatures>) {
        let Some((p, root)) = self.load_for_check(path, shader_root, profile) else {
            return;
        };
        let checked = self.check(p, &root, profile);
        if self.diags.has_errors() {
            // No configuration is planned, but what this profile cannot run is still said.
            crate::plan::unsupported_options(&checked.pipeline, profile, &mut self.diags);
            return;
        }
        self.check_configurations(&checked, profile, scene);
    }

    /// All diagnostics rendered rustc-style.
    pub fn render(&self) -> String {
        self.diags.list.iter().map(|d| d.render(&self.sources)).collect::<Vec<_>>().join("")
    }
}
