//! The virtual file system a compilation reads through: the disk, or files held in memory
//! (tests, an editor's unsaved buffers). Paths are compared after lexical normalisation.

use crate::memo::Memo;
use std::collections::BTreeMap;
use std::io;
use std::path::{Component, Path, PathBuf};
use std::sync::RwLock;

pub trait Vfs: Send + Sync {
    fn read(&self, path: &Path) -> io::Result<String>;
    fn is_dir(&self, path: &Path) -> bool;
    /// A binary file (resource data): by default the text's bytes.
    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        self.read(path).map(String::into_bytes)
    }
    /// Whether `path`, once its symbolic links are resolved, still lies under `root`
    /// (resolved too): an [`OutsideRoot`] error if not. Files in memory have no links.
    fn within(&self, _root: &Path, _path: &Path) -> io::Result<()> {
        Ok(())
    }
}

/// A path that lies under its root as written but leaves it through a symbolic link.
#[derive(Debug)]
pub struct OutsideRoot(pub PathBuf);

impl std::fmt::Display for OutsideRoot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "leaves its root through a symbolic link (it resolves to {})", self.0.display())
    }
}

impl std::error::Error for OutsideRoot {}

/// `within` on the disk: both resolved; a path that does not exist yet, or is no regular
/// file, is not refused here (reading it fails as not found, or not a file).
pub fn within_on_disk(root: &Path, path: &Path) -> io::Result<()> {
    let (Ok(root), Ok(real)) = (std::fs::canonicalize(root), std::fs::canonicalize(path)) else {
        return Ok(());
    };
    // A device or FIFO is refused by the read itself (`not-a-file` says more).
    if real.starts_with(&root) || !real.is_file() {
        Ok(())
    } else {
        Err(io::Error::other(OutsideRoot(real)))
    }
}

/// The largest pipeline, scene or shader file read (a guard against `/dev/zero` and the like).
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// The real file system. Only regular files are read (a FIFO would block, a device never
/// end), at most [`MAX_FILE_BYTES`], and they must be UTF-8.
#[derive(Clone, Copy, Debug, Default)]
pub struct DiskVfs;

impl Vfs for DiskVfs {
    fn read(&self, path: &Path) -> io::Result<String> {
        utf8(read_bytes(path, MAX_FILE_BYTES)?)
    }
    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        read_bytes(path, MAX_FILE_BYTES)
    }
    fn is_dir(&self, path: &Path) -> bool {
        path.is_dir()
    }
    fn within(&self, root: &Path, path: &Path) -> io::Result<()> {
        within_on_disk(root, path)
    }
}

/// Refuse anything but a regular file of at most `limit` bytes, before it is opened.
/// Shared by every reader of user files (pipelines, shaders, scenes, models).
pub fn regular_file(path: &Path, limit: u64) -> io::Result<()> {
    let meta = std::fs::metadata(path)?;
    if meta.is_dir() {
        return Err(io::Error::new(io::ErrorKind::IsADirectory, "is a directory, not a file"));
    }
    if !meta.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "not a regular file (a device, pipe or socket)",
        ));
    }
    if meta.len() > limit {
        return Err(too_large(limit));
    }
    Ok(())
}

/// A regular file's bytes, at most `limit` (the read is capped too: a file may grow after
/// its metadata was read).
pub fn read_bytes(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    use std::io::Read;
    regular_file(path, limit)?;
    let file = std::fs::File::open(path)?;
    // Room for the size it has now (and the one byte that finds it grown past the limit):
    // read into at once, not grown by doubling and copying.
    let len = file.metadata()?.len().min(limit);
    let mut bytes = Vec::with_capacity(usize::try_from(len + 1).unwrap_or(usize::MAX));
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(limit));
    }
    Ok(bytes)
}

/// The error of a file over `limit` bytes.
pub fn too_large(limit: u64) -> io::Error {
    let msg = if limit >= 1 << 30 {
        format!("larger than the {} GiB limit", limit >> 30)
    } else {
        format!("larger than the {} MiB limit", limit >> 20)
    };
    io::Error::new(io::ErrorKind::FileTooLarge, msg)
}

/// Text from bytes, or an error naming the byte offset, line and column of the first invalid
/// sequence (an [`InvalidUtf8`] inside, so that a reader can point at it).
pub fn utf8(bytes: Vec<u8>) -> io::Result<String> {
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        // The bytes before it are valid: count lines and characters in them.
        let before = std::str::from_utf8(&e.as_bytes()[..at]).unwrap_or_default();
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().unwrap_or_default().chars().count() + 1;
        let text = String::from_utf8_lossy(e.as_bytes()).into_owned();
        io::Error::new(io::ErrorKind::InvalidData, InvalidUtf8 { at, line, column, text })
    })
}

/// Where a file stops being UTF-8, and its text with the bad bytes replaced (to show it).
#[derive(Debug)]
pub struct InvalidUtf8 {
    pub at: usize,
    pub line: usize,
    pub column: usize,
    pub text: String,
}

impl std::fmt::Display for InvalidUtf8 {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "not valid UTF-8 (invalid byte at offset {}, line {}, column {})",
            self.at, self.line, self.column
        )
    }
}

impl std::error::Error for InvalidUtf8 {}

/// The diagnostic code of a failed read.
pub fn read_error_code(e: &io::Error) -> crate::diag::Code {
    use crate::diag::Code;
    if e.get_ref().is_some_and(|inner| inner.is::<OutsideRoot>()) {
        return Code::OutsideRoot;
    }
    match e.kind() {
        io::ErrorKind::IsADirectory | io::ErrorKind::InvalidInput => Code::NotAFile,
        io::ErrorKind::FileTooLarge => Code::FileTooLarge,
        io::ErrorKind::InvalidData => Code::InvalidUtf8,
        _ => Code::FileNotFound,
    }
}

/// One run's view of another file system: each file read once, each link check made once,
/// for every compilation of the run (`Workspace::check_files`: the pipelines of one `check`
/// read the same shaders and includes). Only successes are kept; a failed read or check is
/// asked again, so each compilation reports it. Drop it at the end of the run: a
/// long-running process must see edits.
pub struct Snapshot {
    inner: std::sync::Arc<dyn Vfs>,
    texts: Memo<PathBuf, String>,
    bytes: Memo<PathBuf, Vec<u8>>,
    within: Memo<(PathBuf, PathBuf), ()>,
}

impl Snapshot {
    pub fn new(inner: std::sync::Arc<dyn Vfs>) -> Self {
        Snapshot {
            inner,
            texts: Default::default(),
            bytes: Default::default(),
            within: Default::default(),
        }
    }
}

impl Vfs for Snapshot {
    fn read(&self, path: &Path) -> io::Result<String> {
        self.texts.kept(path.to_path_buf(), || self.inner.read(path))
    }
    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        self.bytes.kept(path.to_path_buf(), || self.inner.read_bytes(path))
    }
    fn is_dir(&self, path: &Path) -> bool {
        self.inner.is_dir(path)
    }
    fn within(&self, root: &Path, path: &Path) -> io::Result<()> {
        self.within
            .kept((root.to_path_buf(), path.to_path_buf()), || self.inner.within(root, path))
    }
}

/// Files held in memory, keyed by normalised path.
#[derive(Debug, Default)]
pub struct MemoryVfs {
    files: RwLock<BTreeMap<PathBuf, String>>,
}

impl MemoryVfs {
    pub fn new() -> Self {
        Self::default()
    }

    /// Add or replace a file.
    pub fn write(&self, path: impl AsRef<Path>, text: impl Into<String>) {
        if let Ok(mut f) = self.files.write() {
            f.insert(normalize(path.as_ref()), text.into());
        }
    }

    pub fn remove(&self, path: impl AsRef<Path>) {
        if let Ok(mut f) = self.files.write() {
            f.remove(&normalize(path.as_ref()));
        }
    }
}

impl Vfs for MemoryVfs {
    fn read(&self, path: &Path) -> io::Result<String> {
        let files = self.files.read().map_err(|_| io::Error::other("file table poisoned"))?;
        files
            .get(&normalize(path))
            .cloned()
            .ok_or_else(|| io::Error::new(io::ErrorKind::NotFound, "no such file (in memory)"))
    }
    fn is_dir(&self, path: &Path) -> bool {
        let dir = normalize(path);
        self.files
            .read()
            .map(|f| f.keys().any(|k| k.starts_with(&dir) && *k != dir))
            .unwrap_or(false)
    }
}

/// Files held in memory over the disk: an editor's unsaved documents, or a host program's
/// own pipeline and shaders beside the bundled ones (a pipeline in memory may `use` one on
/// disk). A path held here is read from memory (at most [`MAX_FILE_BYTES`], as on disk);
/// every other path, and whether a path leaves its root, from the disk.
#[derive(Debug, Default)]
pub struct Overlay {
    open: RwLock<BTreeMap<PathBuf, String>>,
}

impl Overlay {
    /// Hold `text` at `path`, in place of what the disk has there.
    pub fn set(&self, path: &Path, text: String) {
        if let Ok(mut o) = self.open.write() {
            o.insert(normalize(path), text);
        }
    }
    /// Stop holding `path`: the disk's file is read again.
    pub fn close(&self, path: &Path) {
        if let Ok(mut o) = self.open.write() {
            o.remove(&normalize(path));
        }
    }
    pub fn get(&self, path: &Path) -> Option<String> {
        self.open.read().ok()?.get(&normalize(path)).cloned()
    }
    pub fn open_paths(&self) -> Vec<PathBuf> {
        self.open.read().map(|o| o.keys().cloned().collect()).unwrap_or_default()
    }
}

impl Vfs for Overlay {
    fn read(&self, path: &Path) -> io::Result<String> {
        match self.get(path) {
            // The same limit as a file on disk: an editor can hold more than a check reads.
            Some(t) if t.len() as u64 > MAX_FILE_BYTES => Err(io::Error::new(
                io::ErrorKind::FileTooLarge,
                format!("larger than the {} MiB limit (the text held in memory)", MAX_FILE_BYTES >> 20),
            )),
            Some(t) => Ok(t),
            None => DiskVfs.read(path),
        }
    }
    fn read_bytes(&self, path: &Path) -> io::Result<Vec<u8>> {
        self.read(path).map(String::into_bytes).or_else(|_| DiskVfs.read_bytes(path))
    }
    fn is_dir(&self, path: &Path) -> bool {
        DiskVfs.is_dir(path)
    }
    fn within(&self, root: &Path, path: &Path) -> io::Result<()> {
        within_on_disk(root, path)
    }
}

/// Remove `.` and `dir/..` pairs lexically so diagnostics show `shaders/x.wgsl`, not
/// `pipelines/../shaders/x.wgsl` (no file system access, symlinks untouched).
pub fn normalize(p: &Path) -> PathBuf {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_files_normalise_paths_and_know_their_directories() {
        let m = MemoryVfs::new();
        m.write("p/../shaders/a.wgsl", "x");
        assert_eq!(m.read(Path::new("./shaders/a.wgsl")).unwrap(), "x");
        assert!(m.is_dir(Path::new("shaders")));
        assert!(!m.is_dir(Path::new("shaders/a.wgsl")));
        m.remove("shaders/a.wgsl");
        assert!(m.read(Path::new("shaders/a.wgsl")).is_err());
    }

    #[test]
    fn an_overlay_reads_what_it_holds_and_the_disk_for_the_rest() {
        let dir = std::env::temp_dir().join(format!("lightbench-overlay-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a.lbp");
        std::fs::write(&file, "on disk").unwrap();
        let o = Overlay::default();
        assert_eq!(o.read(&file).unwrap(), "on disk");
        o.set(&dir.join("./a.lbp"), "in memory".into());
        o.set(&dir.join("b.lbp"), "only in memory".into());
        assert_eq!(o.read(&file).unwrap(), "in memory");
        assert_eq!(o.read(&dir.join("b.lbp")).unwrap(), "only in memory");
        o.close(&file);
        assert_eq!(o.read(&file).unwrap(), "on disk");
        o.set(&file, "x".repeat(MAX_FILE_BYTES as usize + 1));
        assert_eq!(o.read(&file).unwrap_err().kind(), io::ErrorKind::FileTooLarge);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
