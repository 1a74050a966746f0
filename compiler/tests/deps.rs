//! The compiler must build and run where no GPU stack exists: it never depends on wgpu.

use std::process::Command;

#[test]
fn compiler_does_not_depend_on_wgpu() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args([
            "tree",
            "-p",
            "lightbench-compiler",
            "--edges",
            "normal,build",
            "--prefix",
            "none",
            "--offline",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("run cargo tree");
    let tree = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "cargo tree failed: {}", String::from_utf8_lossy(&out.stderr));
    assert!(tree.lines().any(|l| l.starts_with("naga ")), "naga expected in:\n{tree}");
    assert!(
        !tree.lines().any(|l| l.starts_with("wgpu")),
        "wgpu found in the compiler's dependencies:\n{tree}"
    );
}
