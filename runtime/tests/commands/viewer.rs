//! The viewer under Xvfb on lavapipe (CI installs `xvfb`): a scripted session that renders,
//! cycles through every buffer view, switches the cube-shadow variant, toggles, adds and
//! removes a light, calls for bloom,
//! changes a parameter through the widgets' code path (`Action::Param`) and takes
//! screenshots. Needs `xvfb-run`; fails (never skips) without it.

use crate::cli_common;

use cli_common::{root, scratch};
use std::path::Path;
use std::process::Command;

#[test]
fn a_scripted_viewer_session_under_xvfb() {
    let d = scratch("viewer");
    // Every view: the output, then each texture of the Plan.
    let plan = Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .args(["plan", "pipelines/deferred.ron", "--scene", "cornell", "--json"])
        .current_dir(root())
        .output()
        .unwrap();
    let plan: serde_json::Value = serde_json::from_slice(&plan.stdout).expect("plan JSON");
    let textures: Vec<String> = plan["resources"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["shape"].get("Texture").is_some())
        .map(|r| r["name"].as_str().unwrap().to_string())
        .collect();
    assert!(textures.len() >= 6, "{textures:?}");
    let mut script = String::from("frames 2\nscreenshot view0.png\n");
    for i in 1..=textures.len() {
        script += &format!("next-view\nframes 1\nscreenshot view{i}.png\n");
    }
    script += "variant cube_shadow=instanced\nframes 1\nlight 1\ntoggle-light\nframes 1\ntoggle-light\n";
    // Lights added and removed, an effect called for: each a new Plan at a frame boundary.
    script += "add-light Spot\nframes 1\neffect Bloom=true\nframes 1\nremove-light\nframes 1\n";
    script += "param exposure.ev=1\nparam exposure.automatic=false\nframes 1\nview output\nscreenshot last.png\n";
    // The path-traced view in place of the output, and back.
    script += "trace on\nframes 3\nscreenshot traced.png\ntrace off\nframes 1\n";
    std::fs::write(d.join("script.txt"), script).unwrap();
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24"])
        .arg(env!("CARGO_BIN_EXE_lightbench"))
        .args(["view", "--pipeline"])
        .arg(root().join("pipelines/deferred.ron"))
        .args(["--size", "64x64", "--script", "script.txt"])
        .current_dir(&d)
        .output()
        .expect("xvfb-run must be installed (apt-get install xvfb xauth; .ci/run does)");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let shot = |name: &str| image::open(d.join(name)).unwrap_or_else(|e| panic!("{name}: {e}\n{err}")).to_rgb8();
    let first = shot("view0.png");
    let uniform = |img: &image::RgbImage| img.pixels().all(|p| p == img.get_pixel(0, 0));
    assert!(!uniform(&first), "the output screenshot is not uniform");
    for i in 1..=textures.len() {
        shot(&format!("view{i}.png"));
    }
    assert_ne!(shot("view1.png").into_raw(), first.clone().into_raw(), "two buffer views differ");
    // Exposure fixed at +1 EV after the variant switch and the light toggled off and on.
    let last = shot("last.png");
    assert!(!uniform(&last));
    assert_ne!(last.clone().into_raw(), first.into_raw(), "the parameter change shows");
    let traced = shot("traced.png");
    assert!(!uniform(&traced), "the path-traced view is an image");
    assert_ne!(traced.into_raw(), last.into_raw(), "the path-traced view is not the raster output");
}

/// `lightbench view ARGS` under Xvfb, in `dir`: (exit code, stderr).
fn view_in(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24"])
        .arg(env!("CARGO_BIN_EXE_lightbench"))
        .arg("view")
        .arg("--pipeline")
        .arg(root().join("pipelines/deferred.ron"))
        .args(["--size", "48x48"])
        .args(args)
        .current_dir(dir)
        .output()
        .expect("xvfb-run must be installed (apt-get install xvfb xauth; .ci/run does)");
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// `--screenshot-after N` saves the shown image and closes; a bad script line is a usage error
/// (exit 2) naming the line, a missing script an error naming the file, and neither writes a
/// screenshot.
#[test]
fn screenshot_after_and_bad_scripts() {
    let d = scratch("viewer-args");
    let (code, err) = view_in(&d, &["--screenshot-after", "3", "--screenshot", "s.png"]);
    assert_eq!(code, Some(0), "{err}");
    let img = image::open(d.join("s.png")).unwrap().to_rgb8();
    assert!(img.pixels().any(|p| p != img.get_pixel(0, 0)), "a non-uniform screenshot");
    std::fs::write(d.join("bad.txt"), "frames 1\nfrobnicate 3\nscreenshot never.png\n").unwrap();
    let (code, err) = view_in(&d, &["--script", "bad.txt"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("bad.txt:2: script line `frobnicate 3`: no action `frobnicate`"),
        "{err}"
    );
    let (code, err) = view_in(&d, &["--script", "missing.txt"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("missing.txt"), "{err}");
    assert!(!d.join("never.png").exists(), "nothing written after the bad line");
}

/// Script hardening: a script of comments only ends (it is a script, not an interactive
/// session); a typo is refused before the window opens, at FILE:LINE with a suggestion; NaN
/// and huge camera moves are refused; a bad parameter reads as a sentence at its line, not
/// as Rust debug output.
#[test]
fn scripts_end_and_their_errors_are_located() {
    let d = scratch("viewer-scripts");
    std::fs::write(d.join("empty.txt"), "# nothing to do\n\n").unwrap();
    let (code, err) = view_in(&d, &["--script", "empty.txt"]);
    assert_eq!(code, Some(0), "{err}");
    for (script, msg) in [
        (
            "frames 1\nnxt-view\n",
            "s.txt:2: script line `nxt-view`: no action `nxt-view`; did you mean `next-view`?",
        ),
        (
            "move nan 0 0\n",
            "s.txt:1: script line `move nan 0 0`: `NaN` is not a number within ±1e6",
        ),
        ("look 3e38 0\n", "s.txt:1: script line `look 3e38 0`"),
        ("effect Blom=true\n", "no effect `Blom`; did you mean `Bloom`?"),
    ] {
        std::fs::write(d.join("s.txt"), script).unwrap();
        let (code, err) = view_in(&d, &["--script", "s.txt"]);
        assert_eq!(code, Some(2), "{script}: {err}");
        assert!(err.contains(msg), "{script}: {err}");
        assert!(!err.contains("adapter:"), "refused before the window opened: {err}");
    }
    std::fs::write(d.join("s.txt"), "frames 1\nparam exposure.evv=1\n").unwrap();
    let (code, err) = view_in(&d, &["--script", "s.txt"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("s.txt:2: script line `param exposure.evv=1`: no parameter `exposure.evv`; did you mean `exposure.ev`?"),
        "{err}"
    );
    assert!(!err.contains("Unknown {"), "{err}");
}
