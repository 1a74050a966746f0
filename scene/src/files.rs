//! Writing files users own, safely: atomically (a temporary beside the target, then a
//! rename, so a crash never leaves half a file), through symlinks (the link's target is
//! rewritten, the link stays), keeping an existing file's mode, cleaning temporaries that a
//! killed run left behind, and refusing to replace a file that changed while we worked.

use crate::error::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

/// Temporaries are named `.NAME.lightbench-PID.tmp`; this is the part after NAME.
const TMP_TAG: &str = ".lightbench-";

/// What a file looked like when it was read, to notice a change before replacing it.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    bytes: Vec<u8>,
    modified: Option<SystemTime>,
}

impl Snapshot {
    pub fn of(path: &Path) -> std::io::Result<Snapshot> {
        let modified = std::fs::metadata(path)?.modified().ok();
        Ok(Snapshot {
            bytes: std::fs::read(path)?,
            modified,
        })
    }

    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }
}

/// Whether two paths name one file (following symlinks; `b` need not exist yet).
pub fn same_file(a: &Path, b: &Path) -> bool {
    let canon = |p: &Path| {
        std::fs::canonicalize(p).ok().or_else(|| {
            let dir = p.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
            Some(std::fs::canonicalize(dir).ok()?.join(p.file_name()?))
        })
    };
    matches!((canon(a), canon(b)), (Some(x), Some(y)) if x == y)
}

/// Whether a file may be written at `path` (following links): a new name or a regular file.
/// A device, FIFO or socket is not ours to replace (renaming over /dev/null would make it a
/// regular file; writing into a FIFO would wait for a reader), nor is a directory.
pub fn replaceable(path: &Path) -> std::result::Result<(), &'static str> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err("is a directory"),
        Ok(m) if !m.is_file() => Err("is not a regular file (a device, pipe or socket): not replaced"),
        _ => Ok(()),
    }
}

/// Write `bytes` to `path` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write(path, &[bytes], None)
}

/// `write_atomic` of `parts` one after another, without joining them in memory first (a
/// header and a large body).
pub fn write_atomic_parts(path: &Path, parts: &[&[u8]]) -> Result<()> {
    write(path, parts, None)
}

/// Replace `path`, which was read as `before`: refused if it changed since.
pub fn replace(path: &Path, bytes: &[u8], before: &Snapshot) -> Result<()> {
    write(path, &[bytes], Some(before))
}

fn write(path: &Path, parts: &[&[u8]], before: Option<&Snapshot>) -> Result<()> {
    let staged = stage(path, parts)?;
    staged.commit(before)
}

/// Write several files, all or none: every one is written to its temporary first, and only
/// when all are written are they renamed into place (a glTF file and its buffer: a full disk
/// leaves neither, not a buffer without its file).
pub fn write_atomic_all(files: &[(&Path, &[u8])]) -> Result<()> {
    let mut staged = Vec::with_capacity(files.len());
    for (path, bytes) in files {
        // A failure drops (removes) the temporaries staged so far.
        staged.push(stage(path, &[bytes])?);
    }
    staged.into_iter().try_for_each(|s| s.commit(None))
}

/// A file written to its temporary beside the target, not yet renamed into place; dropped
/// uncommitted, the temporary is removed.
struct Staged {
    path: PathBuf,
    target: PathBuf,
    tmp: PathBuf,
}

fn stage(path: &Path, parts: &[&[u8]]) -> Result<Staged> {
    let target = resolve_links(path)?;
    let dir = target.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let name = target
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| Error::io(path, "not a file path"))?;
    replaceable(&target).map_err(|e| Error::io(path, e))?;
    clean_stale(dir);
    // The process and a count: two threads writing one file (two loads keeping the same
    // texture) each write their own temporary.
    static WRITES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let staged = Staged {
        tmp: dir.join(format!(".{name}{TMP_TAG}{}-{n}.tmp", std::process::id())),
        path: path.to_path_buf(),
        target,
    };
    let mode = std::fs::metadata(&staged.target).ok().map(|m| m.permissions());
    let written = (|| {
        let mut f = std::fs::File::create(&staged.tmp)?;
        parts.iter().try_for_each(|p| f.write_all(p))?;
        f.sync_all()?;
        if let Some(p) = mode {
            std::fs::set_permissions(&staged.tmp, p)?;
        }
        Ok(())
    })();
    written.map_err(|e: std::io::Error| Error::io(path, format!("cannot write: {e}")))?;
    Ok(staged)
}

impl Staged {
    /// Rename the temporary into place; refused if the target was read as `before` and has
    /// changed since.
    fn commit(mut self, before: Option<&Snapshot>) -> Result<()> {
        if let Some(before) = before {
            if Snapshot::of(&self.target).ok().as_ref() != Some(before) {
                return Err(Error::io(
                    &self.path,
                    "cannot write: the file changed while lightbench worked on it; it was not replaced",
                ));
            }
        }
        std::fs::rename(&self.tmp, &self.target).map_err(|e| Error::io(&self.path, format!("cannot write: {e}")))?;
        self.tmp = PathBuf::new(); // renamed: nothing left to remove
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        // The temporary of a write that failed or was not committed.
        if !self.tmp.as_os_str().is_empty() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// The file a path finally names, following symlinks (a dangling link's target is created).
fn resolve_links(path: &Path) -> Result<PathBuf> {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let to = std::fs::read_link(&p).map_err(|e| Error::io(&p, e))?;
                p = match p.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            _ => return Ok(p),
        }
    }
    Err(Error::io(path, "too many levels of symbolic links"))
}

/// An exclusive advisory lock on a folder (`DIR/.lightbench.lock`, flock on Unix), held
/// until dropped: writers that read, change and rewrite a file there take it, so that two
/// runs into one folder do not lose each other's work. Elsewhere than Unix: no lock.
pub struct DirLock {
    _file: std::fs::File,
}

pub fn lock_dir(dir: &Path) -> Result<DirLock> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let path = dir.join(".lightbench.lock");
    // A FIFO put there would block the open: regular files (or a new name) only.
    replaceable(&path).map_err(|e| Error::io(&path, e))?;
    let file = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(&path)
        .map_err(|e| Error::io(&path, e))?;
    #[cfg(unix)]
    {
        use std::os::fd::AsRawFd;
        // SAFETY: flock on a descriptor this function owns; blocks until the lock is ours.
        if unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX) } != 0 {
            return Err(Error::io(&path, std::io::Error::last_os_error()));
        }
    }
    Ok(DirLock { _file: file })
}

/// Remove the temporaries that dead runs left beside the file `path` names (following links),
/// as a write there would: for a command that found nothing to write.
pub fn clean_stale_beside(path: &Path) {
    if let Ok(target) = resolve_links(path) {
        clean_stale(target.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new(".")));
    }
}

/// Remove the temporaries in `dir` left by runs that no longer exist (killed mid-write),
/// whatever file they were for.
fn clean_stale(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let file = e.file_name();
        let Some(pid) = file
            .to_str()
            .filter(|f| f.starts_with('.'))
            .and_then(|f| f.rsplit_once(TMP_TAG))
            .and_then(|(_, r)| r.strip_suffix(".tmp"))
            .map(|r| r.split_once('-').map_or(r, |(pid, _)| pid))
        else {
            continue;
        };
        let Ok(pid) = pid.parse::<u32>() else { continue };
        if pid != std::process::id() && !alive(pid, &e.path()) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Whether the process that owns a temporary may still be writing it: on Linux, whether it
/// exists; elsewhere, whether the file was touched in the last hour.
fn alive(pid: u32, tmp: &Path) -> bool {
    if Path::new("/proc/self").exists() {
        return Path::new("/proc").join(pid.to_string()).exists();
    }
    let age = std::fs::metadata(tmp)
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| t.elapsed().ok());
    age.is_none_or(|a| a < Duration::from_secs(3600))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(tag: &str) -> PathBuf {
        let d = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../target/tmp/files-{tag}"));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[cfg(unix)]
    #[test]
    fn writes_through_symlinks_keeping_the_mode() {
        use std::os::unix::fs::PermissionsExt;
        let d = temp("link");
        let real = d.join("real.lbp");
        std::fs::write(&real, "old").unwrap();
        std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o640)).unwrap();
        let link = d.join("link.lbp");
        std::os::unix::fs::symlink("real.lbp", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(
            std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(),
            "the link stays a link"
        );
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
        assert_eq!(std::fs::metadata(&real).unwrap().permissions().mode() & 0o777, 0o640);
    }

    #[test]
    fn refuses_to_replace_a_file_that_changed() {
        let d = temp("changed");
        let f = d.join("p.lbp");
        std::fs::write(&f, "one").unwrap();
        let snap = Snapshot::of(&f).unwrap();
        std::fs::write(&f, "two, written by an editor").unwrap();
        let err = replace(&f, b"formatted", &snap).unwrap_err().to_string();
        assert!(err.contains("changed while"), "{err}");
        assert_eq!(std::fs::read_to_string(&f).unwrap(), "two, written by an editor");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1, "no temporary left");
    }

    /// A dead run's temporaries go at the next write in their folder, whatever file they
    /// were for; other files (and our own run's) stay.
    #[test]
    fn stale_temporaries_of_dead_runs_are_removed() {
        let d = temp("stale");
        // PID 0 is never a user process: a run that no longer exists.
        let stale = d.join(format!(".out.png{TMP_TAG}0.tmp"));
        let other_name = d.join(format!(".manifest.json{TMP_TAG}0-7.tmp"));
        let foreign = d.join(".out.png.other.tmp");
        let live = d.join(format!(".x.exr{TMP_TAG}{}-3.tmp", std::process::id()));
        for f in [&stale, &other_name, &foreign, &live] {
            std::fs::write(f, "half").unwrap();
        }
        write_atomic(&d.join("out.png"), b"png").unwrap();
        assert!(!stale.exists() && !other_name.exists(), "a dead run's temporaries are cleaned");
        assert!(foreign.exists() && live.exists(), "files of other naming, and ours, are left alone");
        let _ = std::fs::remove_dir_all(&d);
    }

    /// Threads of one process writing the same file at once each write their own temporary:
    /// every write succeeds and the file is one of them, whole.
    #[test]
    fn threads_writing_one_file_each_succeed() {
        let d = temp("threads");
        let f = d.join("entry.bin");
        let bodies: Vec<Vec<u8>> = (0..8u8).map(|k| vec![k; 1 << 16]).collect();
        std::thread::scope(|s| {
            for b in &bodies {
                let f = &f;
                s.spawn(move || write_atomic(f, b).unwrap());
            }
        });
        let got = std::fs::read(&f).unwrap();
        assert!(bodies.contains(&got), "one write, whole");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1, "no temporary left");
        let _ = std::fs::remove_dir_all(&d);
    }

    /// Devices and FIFOs are refused, never replaced by a regular file (nor written into),
    /// whether named directly or through a symlink.
    #[cfg(unix)]
    #[test]
    fn devices_and_fifos_are_not_replaced() {
        let d = temp("device");
        let link = d.join("null-link");
        std::os::unix::fs::symlink("/dev/null", &link).unwrap();
        let fifo = d.join("f.png");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        for p in [Path::new("/dev/null"), &link, &fifo] {
            let err = write_atomic(p, b"x").unwrap_err().to_string();
            assert!(err.contains("not a regular file"), "{}: {err}", p.display());
        }
        use std::os::unix::fs::FileTypeExt;
        assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
        assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        // A FIFO as a folder's lock file is refused, not opened (which would wait for a reader).
        let locked = d.join("locked");
        std::fs::create_dir_all(&locked).unwrap();
        assert!(std::process::Command::new("mkfifo")
            .arg(locked.join(".lightbench.lock"))
            .status()
            .unwrap()
            .success());
        let err = lock_dir(&locked).err().expect("refused").to_string();
        assert!(err.contains("not a regular file"), "{err}");
        let _ = std::fs::remove_dir_all(&d);
    }
}
