//! Test output directories: under cargo's per-target temporary directory, named by test
//! binary and tag (no process id), emptied when a test starts, so that running the suite
//! again reuses them instead of leaving more behind.

#![allow(dead_code)]

use std::path::PathBuf;

pub fn scratch(tag: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{}-{tag}", env!("CARGO_CRATE_NAME")));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}
