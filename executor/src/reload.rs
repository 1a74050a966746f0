//! Stage `reload`: hot reload while rendering. The pipeline file, every shader and include
//! the compiler read for it, and the scene file with its models and the files they refer to
//! (buffers, images) are watched (`notify`, debounced); after a change the pipeline is
//! compiled again (unchanged shader modules come from the workspace's
//! cache) and the new Plan replaces the running one at a frame boundary. A compile error, or a
//! shader wgpu rejects when building pipelines, leaves the last good Plan rendering and is
//! reported; the next good save recovers.
//!
//! The folders holding the files are watched, not the files: editors that write a temporary
//! file and rename it over, or delete and create, replace the file's inode, which a watch on
//! the file itself would lose. A folder can be replaced the same way (`git checkout`, an
//! editor's project sync): each poll compares every watched folder's file id with the one
//! watched, and watches a replaced folder anew, its files counting as changed.

use crate::error::{Error, Result};
use crate::{Executor, Gpu, ReloadReport};
use lightbench_compiler::plan::ParamValues;
use lightbench_compiler::{Executable, Workspace};
use lightbench_scene::Scene;
use notify_debouncer_full::file_id::{get_file_id, FileId};
use notify_debouncer_full::notify::{RecommendedWatcher, RecursiveMode};
use notify_debouncer_full::{new_debouncer, DebounceEventResult, Debouncer, RecommendedCache};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// Quiet time after the last event before a change counts (editors write in bursts).
pub const DEBOUNCE: Duration = Duration::from_millis(30);

/// How often the debouncer looks for changes whose quiet time has passed, so a change is
/// delivered up to this long after it. Its default, a quarter of the quiet time, added up to
/// 7.5 ms to each reload; 3 ms costs a wake-up every 3 ms while watching.
const TICK: Duration = Duration::from_millis(3);

/// An absolute, normalised path (`..` and `.` resolved textually; symlinks as written).
fn absolute(p: &Path) -> PathBuf {
    let joined = if p.is_absolute() {
        p.to_path_buf()
    } else {
        std::env::current_dir().unwrap_or_default().join(p)
    };
    lightbench_compiler::vfs::normalize(&joined)
}

/// Watched files and the folders watched for them.
struct Watch {
    debouncer: Debouncer<RecommendedWatcher, RecommendedCache>,
    rx: Receiver<DebounceEventResult>,
    files: BTreeSet<PathBuf>,
    /// Each folder with the id of the folder watched there (`None`: none is, it was missing).
    dirs: BTreeMap<PathBuf, Option<FileId>>,
    /// Files of a folder watched anew, reported as changed by the next `changed`.
    pending: Option<(BTreeSet<PathBuf>, Instant)>,
}

/// A folder's id while it is one (`None` when it is gone or is no folder).
fn folder_id(d: &Path) -> Option<FileId> {
    d.is_dir().then(|| get_file_id(d).ok()).flatten()
}

impl Watch {
    fn new() -> Result<Watch> {
        let (tx, rx) = std::sync::mpsc::channel();
        let debouncer = new_debouncer(DEBOUNCE, Some(TICK), tx).map_err(|e| Error::Request(format!("cannot watch files: {e}")))?;
        Ok(Watch {
            debouncer,
            rx,
            files: BTreeSet::new(),
            dirs: BTreeMap::new(),
            pending: None,
        })
    }

    /// Watch these files (and no others): their folders join the watched ones.
    fn set_files(&mut self, files: impl IntoIterator<Item = PathBuf>) -> Result<()> {
        self.files = files.into_iter().map(|f| absolute(&f)).collect();
        let dirs: BTreeSet<PathBuf> = self.files.iter().filter_map(|f| f.parent().map(Path::to_path_buf)).collect();
        for d in dirs {
            if !self.dirs.contains_key(&d) {
                let id = self.watch_dir(&d)?;
                self.dirs.insert(d, id);
            }
        }
        Ok(())
    }

    /// Watch the folder at `d` if there is one; its id.
    fn watch_dir(&mut self, d: &Path) -> Result<Option<FileId>> {
        let Some(id) = folder_id(d) else { return Ok(None) };
        self.debouncer
            .watch(d, RecursiveMode::NonRecursive)
            .map_err(|e| Error::io(d, format!("cannot watch: {e}")))?;
        Ok(Some(id))
    }

    /// Watch anew every folder that is no longer the one watched (moved away or deleted, and
    /// made again); its watched files count as changed. The folders watched anew.
    fn rewatch_replaced(&mut self) -> Result<Vec<PathBuf>> {
        let replaced: Vec<PathBuf> = (self.dirs.iter())
            .filter(|(d, id)| folder_id(d) != **id)
            .map(|(d, _)| d.clone())
            .collect();
        let mut again = vec![];
        for d in replaced {
            if self.dirs[&d].is_some() {
                // The old folder's watch (it may still exist elsewhere, or be gone already).
                let _ = self.debouncer.unwatch(&d);
            }
            // A folder that cannot be watched is reported once, not at every poll.
            let id = self.watch_dir(&d).inspect_err(|_| _ = self.dirs.insert(d.clone(), folder_id(&d)))?;
            self.dirs.insert(d.clone(), id);
            if id.is_some() {
                let files = self.files.iter().filter(|f| f.parent() == Some(d.as_path())).cloned();
                let (pending, _) = self.pending.get_or_insert_with(|| (BTreeSet::new(), Instant::now()));
                pending.extend(files);
                again.push(d);
            }
        }
        Ok(again)
    }

    /// The watched files that changed, and when the first change happened; waits up to
    /// `timeout` for one.
    fn changed(&mut self, timeout: Duration) -> Option<(BTreeSet<PathBuf>, Instant)> {
        let (mut changed, mut first) = match self.pending.take() {
            Some((files, since)) => (files, Some(since)),
            None => (BTreeSet::new(), None),
        };
        // A folder watched anew has changes already: take what else is there, without waiting.
        let wait = if first.is_some() { Duration::ZERO } else { timeout };
        let have_pending = first.is_some();
        let mut take = |r: DebounceEventResult, changed: &mut BTreeSet<PathBuf>| {
            // Reads and closes change nothing (an editor or the compiler reading the file).
            for ev in r.unwrap_or_default().into_iter().filter(|e| !e.event.kind.is_access()) {
                for p in &ev.event.paths {
                    let p = absolute(p);
                    if self.files.contains(&p) {
                        changed.insert(p);
                        first = Some(first.map_or(ev.time, |f| f.min(ev.time)));
                    }
                }
            }
        };
        match self.rx.recv_timeout(wait) {
            Ok(r) => take(r, &mut changed),
            Err(RecvTimeoutError::Timeout | RecvTimeoutError::Disconnected) if !have_pending => return None,
            Err(_) => {}
        }
        while let Ok(r) = self.rx.try_recv() {
            take(r, &mut changed);
        }
        first.map(|t| (changed, t))
    }
}

/// What a change led to.
#[derive(Debug)]
pub enum Outcome {
    /// The new Plan runs from the next frame. `latency`: from the first change to the swap;
    /// `compile`: of that, compiling and planning.
    Reloaded {
        // Boxed: the report is the largest part of an outcome by far.
        report: Box<ReloadReport>,
        latency: Duration,
        compile: Duration,
        files: Vec<PathBuf>,
        /// The scene loaded again, where its file or a model changed (what the executor now
        /// renders, with its textures still on the CPU: a viewer's path-traced view needs
        /// them).
        scene: Option<Box<Scene>>,
    },
    /// The last good Plan keeps rendering; `message` is the diagnostic (as `check` prints it)
    /// or the GPU's error.
    Failed { message: String, files: Vec<PathBuf> },
    /// These watched folders were replaced (moved away or deleted, and made again) and are
    /// watched anew; their files count as changed, so the next poll reloads from them.
    Rewatched { folders: Vec<PathBuf> },
}

/// What a watcher says when folders were watched anew (a line each).
pub fn rewatched(folders: &[PathBuf]) -> String {
    let lines: Vec<String> = (folders.iter())
        .map(|f| format!("watching {} again: the folder was replaced; reloading from its files", f.display()))
        .collect();
    lines.join("\n")
}

/// What a running pipeline was compiled from, and the watch over it.
pub struct Reloader {
    ws: Workspace,
    pipeline: PathBuf,
    shaders: Option<PathBuf>,
    variants: Vec<(String, String)>,
    params: ParamValues,
    scene_file: Option<PathBuf>,
    /// Every file the scene is read from (`scene_file`, its models and the files they refer
    /// to): a change to any reloads the scene.
    scene_files: Vec<PathBuf>,
    /// The size rendered at: a reloaded scene file keeps it (it may be the caller's, not the
    /// file's).
    size: (u32, u32),
    features: lightbench_compiler::scene::SceneFeatures,
    /// Effects a reloaded scene file calls for besides its own (the caller's, `add_effects`).
    added_effects: Vec<lightbench_compiler::ir::Effect>,
    watch: Watch,
    /// The models of the scene's last load, kept for the next (`keep_models`).
    models: lightbench_scene::model_cache::ModelCache,
    /// The last failure, until a reload succeeds.
    pub last_error: Option<String>,
}

impl Reloader {
    /// Compile the pipeline for the scene and start watching what it read (and `scene_file`).
    pub fn new(
        gpu: &Gpu,
        (pipeline, shaders): (&Path, Option<&Path>),
        (scene, scene_file): (&Scene, Option<&Path>),
        variants: &[(String, String)],
    ) -> Result<(Reloader, Executable)> {
        Self::in_workspace(Workspace::disk(), gpu, (pipeline, shaders), (scene, scene_file), variants)
    }

    /// `new` compiling in a workspace the caller already compiled in (its shader modules are
    /// not validated again).
    pub fn in_workspace(
        ws: Workspace,
        gpu: &Gpu,
        (pipeline, shaders): (&Path, Option<&Path>),
        (scene, scene_file): (&Scene, Option<&Path>),
        variants: &[(String, String)],
    ) -> Result<(Reloader, Executable)> {
        let mut r = Reloader {
            ws,
            pipeline: pipeline.to_path_buf(),
            shaders: shaders.map(Path::to_path_buf),
            variants: variants.to_vec(),
            params: ParamValues::new(),
            scene_file: scene_file.map(absolute),
            scene_files: vec![],
            size: scene.size,
            features: scene.features(),
            added_effects: vec![],
            watch: Watch::new()?,
            models: lightbench_scene::model_cache::ModelCache::keeping(),
            last_error: None,
        };
        let exe = r.compile(gpu).map_err(Error::Compile)?;
        r.scene_files = r.read_scene_files();
        r.watch_files(&exe)?;
        Ok((r, exe))
    }

    /// Compile with these variant choices from now on (a viewer switched one).
    pub fn set_variants(&mut self, variants: &[(String, String)]) {
        self.variants = variants.to_vec();
    }

    /// Plan with these values of parameters the Plan fixes from now on (a viewer set one).
    pub fn set_params(&mut self, params: &ParamValues) {
        self.params = params.clone();
    }

    /// A reloaded scene file calls for these effects too (the caller's, besides its own).
    pub fn add_effects(&mut self, effects: &[lightbench_compiler::ir::Effect]) {
        self.added_effects.extend(effects.iter().copied());
    }

    /// The models the caller loaded the scene with (`ModelCache::keeping`): a reload parses
    /// again only those whose files change. Without them the first reload parses every model.
    pub fn keep_models(&mut self, models: lightbench_scene::model_cache::ModelCache) {
        self.models = models;
    }

    /// Plan for this scene from now on (a viewer toggled a light).
    pub fn set_scene(&mut self, scene: &Scene) {
        self.features = scene.features();
    }

    fn watch_files(&mut self, exe: &Executable) -> Result<()> {
        let mut files: Vec<PathBuf> = exe.files.iter().cloned().collect();
        files.push(self.pipeline.clone());
        files.extend(self.scene_files.iter().cloned());
        self.watch.set_files(files)
    }

    /// The files the scene file is read from now (its models may have changed).
    fn read_scene_files(&self) -> Vec<PathBuf> {
        let Some(f) = &self.scene_file else { return vec![] };
        let mut files: Vec<PathBuf> = lightbench_scene::load::files_of(&f.display().to_string())
            .iter()
            .map(|p| absolute(p))
            .collect();
        if !files.contains(f) {
            files.insert(0, f.clone());
        }
        files
    }

    /// Compile and plan again; `Err` holds the diagnostics as `check` renders them.
    fn compile(&self, gpu: &Gpu) -> std::result::Result<Executable, String> {
        let mut s = self.ws.session();
        let exe = s.executable_with(
            &self.pipeline,
            self.shaders.as_deref(),
            (&gpu.profile, &self.features),
            &self.variants,
            &self.params,
        );
        exe.ok_or_else(|| s.render())
    }

    /// Wait up to `timeout` for a change to what the running Plan was built from; on one,
    /// rebuild and swap it into `ex` (or keep the old and report why not).
    pub fn poll(&mut self, gpu: &Gpu, ex: &mut Executor, timeout: Duration) -> Option<Outcome> {
        match self.watch.rewatch_replaced() {
            Ok(folders) if !folders.is_empty() => return Some(Outcome::Rewatched { folders }),
            Ok(_) => {}
            Err(e) => return Some(self.failed(e.to_string(), vec![])),
        }
        let (changed, since) = self.watch.changed(timeout)?;
        let files: Vec<PathBuf> = changed.iter().cloned().collect();
        let scene_changed = self.scene_files.iter().any(|f| changed.contains(f));
        let mut models_kept = None;
        let scene = match self.scene_file.as_ref().filter(|_| scene_changed) {
            Some(f) => match lightbench_scene::load::load_with(&f.display().to_string(), &mut self.models) {
                Ok(mut s) => {
                    s.size = self.size;
                    s.effects.extend(self.added_effects.iter().copied());
                    models_kept = Some(self.models.last());
                    Some(s)
                }
                Err(e) => return Some(self.failed(e.to_string(), files)),
            },
            None => None,
        };
        if let Some(s) = &scene {
            self.features = s.features();
            // The scene may name other models now.
            self.scene_files = self.read_scene_files();
        }
        let start = Instant::now();
        let exe = match self.compile(gpu) {
            Ok(exe) => exe,
            Err(message) => return Some(self.failed(message, files)),
        };
        let compile = start.elapsed();
        // Files the new Plan reads may differ (an include added or removed).
        if let Err(e) = self.watch_files(&exe) {
            return Some(self.failed(e.to_string(), files));
        }
        let swapped = match &scene {
            Some(s) => ex.replace_scene(gpu, &exe, s),
            None => ex.replace(gpu, &exe),
        };
        match swapped {
            Ok(mut report) => {
                self.last_error = None;
                if let Some(k) = report.scene_kept.as_mut() {
                    k.models = models_kept;
                }
                Some(Outcome::Reloaded {
                    report: Box::new(report),
                    latency: since.elapsed(),
                    compile,
                    files,
                    scene: scene.map(Box::new),
                })
            }
            Err(e) => Some(self.failed(e.to_string(), files)),
        }
    }

    fn failed(&mut self, message: String, files: Vec<PathBuf>) -> Outcome {
        self.last_error = Some(message.clone());
        Outcome::Failed { message, files }
    }
}
