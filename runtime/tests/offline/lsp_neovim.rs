//! `lightbench lsp` with a real client: headless Neovim (Debian's `neovim`, which `.ci/run`
//! installs) started with the manual's snippet `editors/neovim/lightbench.lua` as written,
//! opens two pipelines, one using the other which has a typo, reads the client's diagnostics
//! (one per mistake), hovers a parameter, jumps to its definition and to an entry point's, and
//! completes a half-typed dotted name (`lsp_neovim.lua` does the editor's part).

use crate::cli_common;

use cli_common::{root, scratch};
use serde_json::Value;
use std::process::Command;

#[test]
fn neovim_shows_one_diagnostic_per_mistake_jumps_and_completes() {
    let dir = scratch("neovim");
    for sub in ["pipelines", "shaders"] {
        assert!(Command::new("cp")
            .arg("-r")
            .arg(root().join(sub))
            .arg(&dir)
            .status()
            .unwrap()
            .success());
    }
    let file = dir.join("pipelines/deferred.lbp");
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(
        &file,
        text.replacen("reads gbuf.albedo, gbuf.emissive", "reads gbuf.albdo, gbuf.emissive", 1),
    )
    .unwrap();
    let bin_dir = std::path::Path::new(env!("CARGO_BIN_EXE_lightbench"))
        .parent()
        .unwrap()
        .to_path_buf();
    let path = format!("{}:{}", bin_dir.display(), std::env::var("PATH").unwrap_or_default());
    let out = dir.join("out.json");
    let status = Command::new("nvim")
        .args(["--headless", "-i", "NONE", "-n", "-u"])
        .arg(root().join("editors/neovim/lightbench.lua"))
        .arg("-c")
        .arg(format!("luafile {}", root().join("runtime/tests/offline/lsp_neovim.lua").display()))
        .env("PATH", path)
        .env("LB_DIR", &dir)
        .env("LB_OUT", &out)
        .status()
        .expect("Neovim (`nvim`, Debian's `neovim`; .ci/run installs it)");
    assert!(status.success());
    let got: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    // One diagnostic for the typo, though deferred_gi.lbp's check finds it too.
    let typo: Vec<&Value> = got["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["code"] == "unknown-resource")
        .collect();
    assert_eq!(typo.len(), 1, "{got}");
    let d = typo[0];
    assert_eq!(d["message"], "no resource named `gbuf.albdo`\ndid you mean `gbuf.albedo`?");
    let line = text.lines().position(|l| l.contains("reads gbuf.albedo, gbuf.emissive")).unwrap();
    assert_eq!((d["lnum"].as_u64(), d["col"].as_u64()), (Some(line as u64), Some(10)));
    assert!(
        got["hover"].as_str().unwrap().starts_with("**parameter** `ambient.color`: Color"),
        "{got}"
    );
    let decl = text.lines().position(|l| l.starts_with("param ambient.color")).unwrap();
    assert_eq!(got["definition"]["range"]["start"]["line"].as_u64(), Some(decl as u64), "{got}");
    assert!(got["definition"]["uri"].as_str().unwrap().ends_with("pipelines/deferred.lbp"));
    // An entry point: the function in the shader.
    let entry = &got["entry_definition"];
    assert!(entry["uri"].as_str().unwrap().ends_with("shaders/gbuffer.wgsl"), "{got}");
    let shader = std::fs::read_to_string(dir.join("shaders/gbuffer.wgsl")).unwrap();
    let fn_line = shader.lines().position(|l| l.starts_with("fn fs_fat_position(")).unwrap();
    assert_eq!(entry["range"]["start"]["line"].as_u64(), Some(fn_line as u64), "{got}");
    // Completion after `gbuf.alb`: the prefix is the dotted word, `gbuf.albedo` is offered
    // first (the only match) and replaces it.
    assert_eq!(got["prefix"], "gbuf.alb", "{got}");
    assert_eq!(got["words"], serde_json::json!(["gbuf.albedo"]), "{got}");
    assert!(
        got["completed"].as_str().unwrap().ends_with("reads gbuf.albedo, gbuf.emissive"),
        "{got}"
    );
}
