//! The tutorial (`docs/tutorial.md`) and the README's first project, run as written: each
//! file the text shows (`File `PATH`:` before a code block) is written, each `sh` line is run
//! in order (`cd` moves), and every command must succeed.

use crate::cli_common;

use cli_common::{lightbench_in, root, scratch};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Run a Markdown text's files and `sh` blocks in `dir`; returns how many commands ran.
fn run_as_written(text: &str, dir: &Path) -> usize {
    let mut cwd: PathBuf = dir.to_path_buf();
    let mut ran = 0;
    let mut lines = text.lines();
    let mut file: Option<String> = None;
    while let Some(line) = lines.next() {
        if let Some(name) = line.strip_prefix("File `").and_then(|l| l.strip_suffix("`:")) {
            file = Some(name.to_string());
            continue;
        }
        if !line.starts_with("```") {
            continue;
        }
        let block: Vec<&str> = lines.by_ref().take_while(|l| !l.starts_with("```")).collect();
        if let Some(name) = file.take() {
            let path = cwd.join(&name);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, block.join("\n") + "\n").unwrap();
        } else if line == "```sh" {
            for cmd in block.iter().map(|l| l.trim()).filter(|l| !l.is_empty() && !l.starts_with('#')) {
                let words: Vec<&str> = cmd.split_whitespace().collect();
                if let ["cd", to] = words.as_slice() {
                    cwd = cwd.join(to);
                    continue;
                }
                assert_eq!(words[0], "lightbench", "a command the test cannot run: {cmd}");
                let out = Command::new(env!("CARGO_BIN_EXE_lightbench"))
                    .args(&words[1..])
                    .current_dir(&cwd)
                    .output()
                    .unwrap();
                assert!(
                    out.status.success(),
                    "`{cmd}` failed:\n{}{}",
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                );
                ran += 1;
            }
        }
    }
    ran
}

#[test]
fn the_tutorial_runs_as_written() {
    let d = scratch("tutorial");
    let text = std::fs::read_to_string(root().join("docs/tutorial.md")).unwrap();
    assert_eq!(run_as_written(&text, &d), 9);
    let project = d.join("tutorial");
    for made in [
        "cornell.png",
        "warm.png",
        "diff-warm/report.md",
        "diff-warm/ldr.side.png",
        "ref",
        "sweep-warm/report.md",
        "sweep-warm/results.csv",
    ] {
        assert!(project.join(made).exists(), "the tutorial says it makes {made}");
    }
    // The warm pipeline is what it says: a warmer image than the default's (automatic
    // exposure evens out the brightness).
    let red_over_blue = |f: &str| {
        let img = lightbench::io::Image::load_png(&project.join(f)).unwrap();
        let (mut r, mut b) = (0.0, 0.0);
        for y in 0..img.height {
            for x in 0..img.width {
                let p = img.pixel(x, y);
                (r, b) = (r + p[0], b + p[2]);
            }
        }
        r / b
    };
    let (warm, default) = (red_over_blue("warm.png"), red_over_blue("cornell.png"));
    assert!(warm > 1.05 * default, "the warm room is warmer: red/blue {warm} vs {default}");
    // The sweep measured both settings.
    let csv = std::fs::read_to_string(project.join("sweep-warm/results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 3, "a header and two points:\n{csv}");
}

#[test]
fn the_readmes_first_project_runs_as_written() {
    let d = scratch("readme-first-project");
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let section = readme.split("## A first project").nth(1).expect("the section");
    let section = section.split("\n## ").next().unwrap();
    assert_eq!(run_as_written(section, &d), 5);
    assert!(d.join("my-lighting/spot.png").is_file() && d.join("my-lighting/room.png").is_file());
    // As it says: without `--effect` the room's indirect light and occlusion are culled (the
    // image is shadows and direct light alone), with it they render.
    let project = d.join("my-lighting");
    let args = ["render", "--pipeline", "pipelines/deferred_gi.lbp", "--scene", "scenes/room.ron"];
    let (code, _, err) = lightbench_in(&project, &[&args[..], &["--size", "128x128", "--out", "plain.png"]].concat());
    assert_eq!(code, 0, "{err}");
    let load = |f: &str| lightbench::io::Image::load_png(&project.join(f)).unwrap();
    let e = lightbench::io::rmse(&load("room.png"), &load("plain.png")).unwrap();
    assert!(e > 0.01, "--effect changes the room: RMSE {e}");
}
