//! Build step: the bundled pipelines, shaders, scenes and sweep specs (`../pipelines`,
//! `../shaders`, `../scenes`, `../sweeps`) listed for `include_bytes!`, so that the binary runs its default pipeline from
//! any directory and `lightbench init` can write them out (see `src/bundled.rs`).

use std::fmt::Write;
use std::path::{Path, PathBuf};

fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        let hidden = p.file_name().and_then(|n| n.to_str()).is_none_or(|n| n.starts_with('.'));
        if hidden {
            continue;
        }
        if p.is_dir() {
            walk(&p, out);
        } else {
            out.push(p);
        }
    }
}

fn main() {
    // Read when the script runs, not when it was compiled: a build script compiled for a
    // checkout elsewhere (a moved or copied target directory) would list nothing.
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR")).join("..");
    let mut files = vec![];
    for dir in ["pipelines", "shaders", "scenes", "sweeps"] {
        println!("cargo:rerun-if-changed={}", root.join(dir).display());
        walk(&root.join(dir), &mut files);
    }
    let mut code =
        String::from("/// (path relative to the repository root, contents), in path order.\npub static FILES: &[(&str, &[u8])] = &[\n");
    for f in &files {
        println!("cargo:rerun-if-changed={}", f.display());
        let rel = f.strip_prefix(&root).expect("below the root").to_string_lossy().replace('\\', "/");
        let abs = std::fs::canonicalize(f).expect("a readable file");
        let _ = writeln!(code, "    ({rel:?}, include_bytes!({:?})),", abs.display().to_string());
    }
    code.push_str("];\n");
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("OUT_DIR")).join("bundled.rs");
    std::fs::write(out, code).expect("write bundled.rs");
}
