//! What the command-line tests share: the repository root, running the built binary there,
//! and output directories under cargo's per-target temporary directory, named by test
//! binary and tag (no process id) and emptied when a test starts, so that running the
//! suite again reuses them instead of leaving more behind.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// Run `lightbench ARGS` in the repository root: (exit code, stdout, stderr).
pub fn lightbench(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("run lightbench");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Run `lightbench ARGS` in `dir`: (exit code, stdout, stderr).
pub fn lightbench_in(dir: &Path, args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run lightbench");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

pub fn scratch(tag: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{}-{tag}", env!("CARGO_CRATE_NAME")));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The README and every page of the manual (`docs/*.md`), README first, pages by name.
pub fn manual_files() -> Vec<PathBuf> {
    let mut pages: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    pages.sort();
    std::iter::once(root().join("README.md")).chain(pages).collect()
}

/// `manual_files` as one text: what tests search for the examples the documentation shows.
pub fn manual() -> String {
    manual_files()
        .into_iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

/// Assert that the manual's first ```ron block starting with `opening` is the bundled file
/// `rel` without its leading comment lines: the example as written is the file tests run.
pub fn assert_readme_block_is(opening: &str, rel: &str) {
    let readme = manual();
    let block = readme
        .split("```ron\n")
        .skip(1)
        .filter_map(|b| b.split("```").next())
        .find(|b| b.starts_with(opening))
        .unwrap_or_else(|| panic!("a `{opening}` example in the manual (README or docs/)"));
    let file = std::fs::read_to_string(root().join(rel)).unwrap();
    let body: String = file.lines().filter(|l| !l.starts_with("//")).map(|l| format!("{l}\n")).collect();
    assert_eq!(block, body, "the manual's example and {rel} differ");
}
