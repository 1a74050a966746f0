//! The bundled pipelines, shaders and scenes, compiled into the binary (listed by
//! `build.rs`): what `render` runs when it is given no pipeline and `pipelines/deferred.ron` is
//! not on disk (an installed binary, another directory), and what `lightbench init` writes out
//! as the start of a user's own project.

use crate::error::{Error, Result};
use lightbench_compiler::vfs::MemoryVfs;
use lightbench_compiler::Workspace;
use std::path::{Path, PathBuf};
use std::sync::Arc;

include!(concat!(env!("OUT_DIR"), "/bundled.rs"));

/// Where the bundled files appear to the compiler (a name no real path has).
pub const ROOT: &str = "<bundled>";

/// The default pipeline's path relative to a project.
pub const DEFAULT_PIPELINE: &str = "pipelines/deferred.ron";

/// A workspace reading the bundled pipelines and shaders (text files) from memory.
pub fn workspace() -> Workspace {
    let vfs = Arc::new(MemoryVfs::new());
    for (path, bytes) in FILES {
        let text_dir = path.starts_with("pipelines/") || path.starts_with("shaders/");
        if let (true, Ok(text)) = (text_dir, std::str::from_utf8(bytes)) {
            vfs.write(Path::new(ROOT).join(path), text);
        }
    }
    Workspace::new(vfs)
}

/// The bundled default pipeline, as `workspace()` names it.
pub fn default_pipeline() -> PathBuf {
    Path::new(ROOT).join(DEFAULT_PIPELINE)
}

/// A bundled file's contents by the path `workspace()` gives it.
pub fn read(path: &Path) -> Option<Vec<u8>> {
    let rel = path.strip_prefix(ROOT).ok()?;
    let rel = rel.to_str()?.replace('\\', "/");
    FILES.iter().find(|(p, _)| *p == rel).map(|(_, b)| b.to_vec())
}

/// Write every bundled file below `dir` (created if needed). Nothing is overwritten: when any
/// of the files exists already, nothing is written and the error names it.
pub fn init(dir: &Path) -> Result<Vec<PathBuf>> {
    let targets: Vec<PathBuf> = FILES.iter().map(|(p, _)| dir.join(p)).collect();
    if let Some(existing) = targets.iter().find(|t| t.exists() || t.symlink_metadata().is_ok()) {
        return Err(Error::Usage(format!(
            "{} exists already; init writes into a fresh folder and overwrites nothing",
            existing.display()
        )));
    }
    for (t, (_, bytes)) in targets.iter().zip(FILES) {
        crate::io::write_atomic(t, bytes)?;
    }
    Ok(targets)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_pipeline_and_its_shaders_are_bundled() {
        let names: Vec<&str> = FILES.iter().map(|(p, _)| *p).collect();
        for f in [
            DEFAULT_PIPELINE,
            "pipelines/deferred_gi.lbp",
            "shaders/gbuffer.wgsl",
            "shaders/lib/frame.wgsl",
            "scenes/sun_only.ron",
        ] {
            assert!(names.contains(&f), "{f} is not bundled");
        }
        let on_disk = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(DEFAULT_PIPELINE)).unwrap();
        assert_eq!(FILES.iter().find(|(p, _)| *p == DEFAULT_PIPELINE).unwrap().1, on_disk.as_slice());
    }
}
