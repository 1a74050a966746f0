//! Language server (`lightbench lsp`): the compiler's knowledge of pipeline files, scene
//! files and the shaders they use, over the Language Server Protocol on stdio. Open
//! documents are an overlay on the disk, so unsaved text is what is checked.
//!
//! Protocol scaffolding is `lsp-server` (rust-analyzer's: synchronous, no async runtime).
//! Edits are debounced adaptively ([`Quiet`]): diagnostics are published once no edit has
//! come for a quarter of the time the last check took (at most [`MAX_QUIET`]); requests are
//! answered at once, from the last text that lowered, and do not move the deadline.

mod complete;
mod diagnostics;
mod handlers;
pub mod index;
mod merge;
mod shader;
pub mod text;
mod transport;
mod words;

use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::{file_kind, FileKind};
use lightbench_compiler::vfs::Overlay;
use lightbench_compiler::vfs::Vfs;
use lightbench_compiler::Workspace;
use lsp_server::{Connection, Message, Notification};
use lsp_types::notification::{self as note, Notification as _};
use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};
use text::path_of;

/// The longest quiet time after an edit before the files it touches are checked again.
pub const MAX_QUIET: Duration = Duration::from_millis(25);

/// The shortest: edits that come together (one keystroke as several changes) are one check.
pub const MIN_QUIET: Duration = Duration::from_millis(5);

/// How long to wait after an edit: a quarter of the time the last check took, within
/// [`MIN_QUIET`] and the most. Keystrokes closer together than that are checked once; a
/// longer wait would only add latency, since edits that come while a check runs queue and
/// are checked together after it (so the server never falls more than one check behind).
pub struct Quiet {
    most: Duration,
    last_check: Duration,
}

impl Quiet {
    pub fn new(most: Duration) -> Quiet {
        Quiet { most, last_check: most }
    }
    pub fn wait(&self) -> Duration {
        (self.last_check / 4).clamp(MIN_QUIET.min(self.most), self.most)
    }
    pub fn checked(&mut self, took: Duration) {
        self.last_check = took;
    }
}

/// `lightbench lsp`: serve on stdin/stdout until the client says `exit`.
pub fn run() -> Result<(), String> {
    let (connection, io_threads) = transport::stdio();
    let served = serve(&connection, MAX_QUIET);
    drop(connection);
    // The reader's protocol error, when there is one, is why serving stopped.
    io_threads.join().and(served)
}

/// The whole conversation on one connection: the handshake, then messages until `exit` (or
/// until the client goes away). After `shutdown` every request is an error and `exit` ends
/// it well; `exit` without `shutdown` is an error (exit code 1), as the protocol says.
/// Diagnostics wait for a quiet time after the last edit of at most `most_quiet` ([`Quiet`]).
pub fn serve(connection: &Connection, most_quiet: Duration) -> Result<(), String> {
    let capabilities = serde_json::to_value(handlers::capabilities()).map_err(|e| e.to_string())?;
    let init = connection.initialize(capabilities).map_err(|e| e.to_string())?;
    let mut server = Server::new(roots(&init));
    let mut quiet = Quiet::new(most_quiet);
    // When the pending edits are checked: set by edits only, so requests do not delay it.
    let mut due: Option<Instant> = None;
    let mut shut_down = false;
    loop {
        let received = match due {
            None => connection.receiver.recv().map_err(|_| None),
            Some(at) => connection.receiver.recv_deadline(at).map_err(|e| e.is_timeout().then_some(())),
        };
        let msg = match received {
            Ok(m) => m,
            Err(Some(())) => {
                let started = Instant::now();
                server.flush(connection);
                quiet.checked(started.elapsed());
                due = None;
                continue;
            }
            Err(None) => return Ok(()),
        };
        match msg {
            Message::Request(req) if shut_down => {
                let e = lsp_server::ErrorCode::InvalidRequest as i32;
                let response = lsp_server::Response::new_err(req.id, e, "the server is shut down: only `exit` is expected".into());
                let _ = connection.sender.send(response.into());
            }
            Message::Request(req) if req.method == "shutdown" => {
                shut_down = true;
                let _ = connection.sender.send(lsp_server::Response::new_ok(req.id, ()).into());
            }
            Message::Request(req) => {
                let response = handlers::answer(&mut server, req);
                let _ = connection.sender.send(response.into());
            }
            Message::Notification(n) if n.method == note::Exit::METHOD => {
                return match shut_down {
                    true => Ok(()),
                    false => Err("`exit` came without `shutdown`".into()),
                };
            }
            Message::Notification(n) => {
                if server.notified(n) {
                    due = Some(Instant::now() + quiet.wait());
                }
            }
            Message::Response(_) => {}
        }
    }
}

/// The folders the client opened (pipelines below them are checked when a shader they use
/// is edited before they were).
fn roots(init: &serde_json::Value) -> Vec<PathBuf> {
    let Ok(params) = serde_json::from_value::<lsp_types::InitializeParams>(init.clone()) else {
        return vec![];
    };
    let folders = params.workspace_folders.unwrap_or_default();
    folders.iter().filter_map(|f| path_of(&f.uri)).collect()
}

/// The manual's diagnostics page (`docs/diagnostics.md`, the table of codes) of the repository
/// this binary was built from, if it is still there.
fn manual() -> Option<lsp_types::Uri> {
    let page = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()?
        .join("docs/diagnostics.md");
    text::uri_of(&page).filter(|_| page.is_file())
}

pub struct Server {
    overlay: Arc<Overlay>,
    workspace: Workspace,
    roots: Vec<PathBuf>,
    profile: Profile,
    /// Documents edited since their last check.
    dirty: BTreeSet<PathBuf>,
    /// Per checked pipeline, every file its last check read.
    deps: HashMap<PathBuf, BTreeSet<PathBuf>>,
    /// Per checked file, its last diagnostics by the file they are located in.
    published: HashMap<PathBuf, diagnostics::ByFile>,
    /// Per pipeline document, the text it was last indexed from and the index.
    indexes: HashMap<PathBuf, (String, index::Index)>,
    /// The manual's table of diagnostic codes, when the manual is on this machine (a build
    /// from the repository): each diagnostic's code links there.
    manual: Option<lsp_types::Uri>,
    /// Per checked pipeline, what each pass does on the default scene with default options.
    default_runs: HashMap<PathBuf, std::collections::BTreeMap<String, String>>,
}

impl Server {
    fn new(roots: Vec<PathBuf>) -> Self {
        let overlay = Arc::new(Overlay::default());
        Server {
            workspace: Workspace::new(overlay.clone()),
            overlay,
            roots,
            profile: Profile::vulkan(),
            dirty: BTreeSet::new(),
            deps: HashMap::new(),
            published: HashMap::new(),
            indexes: HashMap::new(),
            default_runs: HashMap::new(),
            manual: manual(),
        }
    }

    /// Document notifications update the overlay; anything malformed is ignored. Whether a
    /// document changed (its files are to be checked again).
    fn notified(&mut self, n: Notification) -> bool {
        let changed = match n.method.as_str() {
            note::DidOpenTextDocument::METHOD => serde_json::from_value::<lsp_types::DidOpenTextDocumentParams>(n.params)
                .ok()
                .and_then(|p| Some((path_of(&p.text_document.uri)?, Some(p.text_document.text)))),
            // Full-document sync: the last change holds the whole text.
            note::DidChangeTextDocument::METHOD => serde_json::from_value::<lsp_types::DidChangeTextDocumentParams>(n.params)
                .ok()
                .and_then(|p| Some((path_of(&p.text_document.uri)?, Some(p.content_changes.into_iter().last()?.text)))),
            note::DidCloseTextDocument::METHOD => serde_json::from_value::<lsp_types::DidCloseTextDocumentParams>(n.params)
                .ok()
                .and_then(|p| Some((path_of(&p.text_document.uri)?, None))),
            // Saved: the text is the open one; checked again (files it reads may differ now).
            note::DidSaveTextDocument::METHOD => serde_json::from_value::<lsp_types::DidSaveTextDocumentParams>(n.params)
                .ok()
                .and_then(|p| path_of(&p.text_document.uri))
                .map(|path| {
                    let text = self.overlay.get(&path);
                    (path, text)
                }),
            _ => None,
        };
        if let Some((path, text)) = changed {
            match text {
                Some(t) => self.overlay.set(&path, t),
                None => {
                    // Closed: its text and what was derived from it go (rebuilt from the file
                    // on disk if something needs them again).
                    self.overlay.close(&path);
                    self.indexes.remove(&path);
                    self.default_runs.remove(&path);
                }
            }
            self.dirty.insert(path);
            return true;
        }
        false
    }

    /// Check what the pending edits touch and publish the diagnostics that changed.
    /// The edited files are checked first, so their own diagnostics come before those of
    /// the pipelines that use them.
    fn flush(&mut self, connection: &Connection) {
        let changed = std::mem::take(&mut self.dirty);
        let mut files: Vec<PathBuf> = self.to_check(&changed).into_iter().collect();
        files.sort_by_key(|f| !changed.contains(f));
        self.publish(&files, |params| {
            let n = Notification::new(note::PublishDiagnostics::METHOD.to_string(), params);
            let _ = connection.sender.send(n.into());
        });
    }

    /// A document's text: the editor's, else the file's, read as every user file is (regular
    /// files only, at most 16 MiB, UTF-8).
    fn text(&self, path: &Path) -> Option<String> {
        self.overlay.read(path).ok()
    }

    /// Whether there is a document or a file at `path`.
    fn exists(&self, path: &Path) -> bool {
        self.overlay.get(path).is_some() || path.is_file()
    }

    /// Pipelines the server knows of: open ones, and those below the workspace folders'
    /// `pipelines/` directories.
    fn known_pipelines(&self) -> BTreeSet<PathBuf> {
        let open = self.overlay.open_paths().into_iter();
        let below = self
            .roots
            .iter()
            .flat_map(|r| lightbench_compiler::pipeline_files(&r.join("pipelines")).unwrap_or_default());
        open.chain(below)
            .filter(|p| {
                // A RON file is a scene or sweep file when its first item says so.
                let text = self.text(p);
                file_kind(p, text.as_deref()) == FileKind::Pipeline
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::{Quiet, MAX_QUIET};
    use std::time::Duration;

    #[test]
    fn the_quiet_time_is_a_quarter_of_the_last_check_within_its_bounds() {
        let ms = Duration::from_millis;
        let mut q = Quiet::new(MAX_QUIET);
        // Before any check: a quarter of the most.
        assert_eq!(q.wait(), MAX_QUIET / 4);
        for (took, wait) in [(ms(4), ms(5)), (ms(40), ms(10)), (ms(400), ms(25))] {
            q.checked(took);
            assert_eq!(q.wait(), wait, "after a check of {took:?}");
        }
        // No quiet time at all (benches, generated streams).
        let mut none = Quiet::new(Duration::ZERO);
        none.checked(ms(40));
        assert_eq!(none.wait(), Duration::ZERO);
    }
}
