//! The executor's examples as the README runs them: `headless` renders what `lightbench
//! render` renders; `embed` opens a window under Xvfb, renders through the library into its
//! swap-chain image and exits after the frames asked for. The reference's `ltc_fit` refuses bad
//! output paths before fitting.

use crate::cli_common;

use cli_common::{lightbench, root, scratch};
use std::path::PathBuf;
use std::process::Command;

/// An example's binary: `cargo test --workspace` builds the examples beside the tests; a run
/// of this crate's tests alone (`cargo test -p lightbench`) builds the one asked for, once, in
/// a target folder of its own (so that it does not wait on the build running the tests).
fn example(name: &str) -> PathBuf {
    let deps = std::env::current_exe().unwrap().parent().unwrap().to_path_buf();
    let exe = deps.parent().unwrap().join("examples").join(name);
    if exe.is_file() {
        return exe;
    }
    static BUILDING: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _one_at_a_time = BUILDING.lock().unwrap_or_else(|e| e.into_inner());
    let target = root().join("target/examples-check");
    let built = target.join("debug/examples").join(name);
    let krate = ["executor", "reference"]
        .into_iter()
        .find(|k| root().join(k).join("examples").join(format!("{name}.rs")).is_file())
        .unwrap_or_else(|| panic!("no example `{name}` in executor/ or reference/"));
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.args(["build", "--example", name, "--target-dir"]).arg(&target);
    cmd.args(["-p", &format!("lightbench-{krate}")]);
    if krate == "executor" {
        cmd.args(["--features", "reload"]);
    }
    let out = cmd.current_dir(root()).output().unwrap();
    assert!(
        out.status.success(),
        "building example {name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(built.is_file(), "{} is missing after building it", built.display());
    built
}

#[test]
fn headless_renders_what_lightbench_render_renders() {
    let d = scratch("example-headless");
    let (ours, theirs) = (d.join("headless.png"), d.join("render.png"));
    let out = Command::new(example("headless"))
        .arg(&ours)
        .arg("64x64")
        .current_dir(root())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (code, _, err) = lightbench(&[
        "render",
        "--pipeline",
        "pipelines/deferred.lbp",
        "--size",
        "64x64",
        "--out",
        theirs.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let load = |p: &PathBuf| lightbench::io::Image::load_png(p).unwrap();
    let e = lightbench::io::rmse(&load(&ours), &load(&theirs)).unwrap();
    assert!(e <= 1e-6, "RMSE {e}");
    // A size that is not one, or no output named: usage errors, nothing written.
    std::fs::remove_file(&ours).unwrap();
    for args in [vec![ours.to_str().unwrap(), "64by64"], vec![]] {
        let out = Command::new(example("headless")).args(&args).current_dir(root()).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        assert!(!ours.exists(), "{args:?}: nothing written");
    }
}

/// `host_loop` (docs/embedding.md, "A host program"): its own camera, a parameter and a
/// variant switched while running end on what `lightbench render` renders with that
/// camera, parameter and variant, but where the host's pass draws the picture the host wrote
/// into its external texture (a progress bar, one eighth long on the first frame, full on the
/// last); the host's own submit gets GPU timings; bad FRAMES is a usage error.
#[test]
fn host_loop_ends_where_lightbench_render_does() {
    let d = scratch("example-host-loop");
    let (first, last, theirs) = (d.join("first.png"), d.join("last.png"), d.join("render.png"));
    let out = Command::new(example("host_loop"))
        .arg(&first)
        .arg(&last)
        .current_dir(root())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("frame 4: tonemap = simple"), "{stdout}");
    assert!(stdout.contains("exposure.ev = 1"), "{stdout}");
    // The last frame, recorded into the host's encoder and submitted by the host, is timed.
    let gbuffer = stdout
        .lines()
        .find(|l| l.starts_with("pass gbuffer "))
        .unwrap_or_else(|| panic!("{stdout}"));
    let ms: f64 = gbuffer
        .split("GPU ")
        .nth(1)
        .and_then(|r| r.split(" ms").next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{gbuffer}"));
    assert!(ms > 0.0 && ms.is_finite(), "{gbuffer}");
    let (code, _, err) = lightbench(&[
        "render",
        "--size",
        "64x64",
        "--variant",
        "tonemap=simple",
        "--param",
        "exposure.automatic=false",
        "--param",
        "exposure.ev=1",
        "--out",
        theirs.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let load = |p: &PathBuf| lightbench::io::Image::load_png(p).unwrap();
    let (ours, first, theirs) = (load(&last), load(&first), load(&theirs));
    // The bar: the bottom 6 rows, as long as the share of frames rendered.
    let (bar, w) = (58, 64);
    let bar_color = [32.0 / 255.0, 200.0 / 255.0, 1.0, 1.0];
    let mut above = 0.0;
    for y in 0..64 {
        for x in 0..w {
            let (a, b) = (ours.pixel(x, y), theirs.pixel(x, y));
            if y >= bar {
                assert_eq!(a, bar_color, "the host's bar at ({x}, {y}) on the last frame");
                let in_first = first.pixel(x, y) == bar_color;
                assert_eq!(in_first, x < w / 8, "the first frame's bar is 1/8 long: ({x}, {y})");
            } else {
                above += (0..3).map(|c| ((a[c] - b[c]) as f64).powi(2)).sum::<f64>();
            }
        }
    }
    let e = (above / (3.0 * 64.0 * bar as f64)).sqrt();
    assert!(e <= 1e-3, "above the bar, RMSE {e} to lightbench render");
    let e = lightbench::io::rmse(&first, &theirs).unwrap();
    assert!(e > 0.01, "the first frame is another camera and tone mapping: RMSE {e}");
    // Too few frames, or no outputs named: usage errors, nothing written.
    let (a, b) = (d.join("a.png"), d.join("b.png"));
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    for args in [vec![a, b, "1"], vec![a], vec![]] {
        let out = Command::new(example("host_loop")).args(&args).current_dir(root()).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(if args.len() == 3 { "FRAMES `1`" } else { "usage: host_loop" }),
            "{err}"
        );
        assert!(!d.join("a.png").exists() && !d.join("b.png").exists(), "{args:?}: nothing written");
    }
}

/// docs/embedding.md's host program: each line of its code is a line of the examples' shared
/// device code or of `host_loop.rs`, in order, and its `Cargo.toml` asks for the versions this
/// workspace builds with.
#[test]
fn the_host_program_in_the_docs_is_the_example() {
    let docs = std::fs::read_to_string(root().join("docs/embedding.md")).unwrap();
    let section = docs
        .split("### A host program")
        .nth(1)
        .expect("docs/embedding.md: ### A host program");
    let block = |fence: &str| {
        let rest = section.split(fence).nth(1).unwrap_or_else(|| panic!("no {fence} block"));
        rest.split("```").next().unwrap().to_string()
    };
    let read = |f: &str| std::fs::read_to_string(root().join("executor/examples").join(f)).unwrap();
    let (common, example) = (read("common/mod.rs"), read("host_loop.rs"));
    // The docs' lines in order, each in one of the two files: those of the device first.
    let mut lines = common.lines().chain(example.lines()).map(str::trim);
    for want in block("```rust\n")
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with("//"))
    {
        assert!(
            lines.any(|l| l == want),
            "not in common/mod.rs then host_loop.rs (in this order): {want}"
        );
    }
    let workspace = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let toml = block("```toml\n");
    let versions = toml.lines().filter_map(|l| l.split_once(" = ")).filter(|(_, v)| v.starts_with('"'));
    for (krate, version) in versions {
        let line = format!("{krate} = {version}");
        let ours = (workspace.lines())
            .find(|l| l.starts_with(&format!("{krate} = ")))
            .unwrap_or_else(|| panic!("{krate} is no workspace dependency"));
        assert!(
            ours.contains(&format!("version = {version}")) || ours.ends_with(&format!("= {version}")),
            "{line} vs {ours}"
        );
    }
}

/// `embed`'s options are checked before any window opens: exit 2, named.
#[test]
fn embed_refuses_bad_options() {
    for (args, says) in [(["--frames", "many"], "--frames many"), (["--fast", "1"], "unknown option --fast")] {
        let out = Command::new(example("embed")).args(args).current_dir(root()).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
}

#[test]
fn embed_renders_into_its_window_under_xvfb() {
    let d = scratch("example-embed");
    let shot = d.join("swapchain.png");
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1024x768x24"])
        .arg(example("embed"))
        .args(["--frames", "3", "--screenshot"])
        .arg(&shot)
        .current_dir(root())
        .output()
        .expect("xvfb-run must be installed (apt-get install xvfb xauth; .ci/run does)");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let img = image::open(&shot).unwrap_or_else(|e| panic!("{e}\n{err}")).to_rgb8();
    assert!(
        img.pixels().any(|p| p != img.get_pixel(0, 0)),
        "the swap-chain image is not uniform"
    );
}

/// `ltc_fit`'s bad inputs, refused before the fit: extra arguments or an option (exit 2), an
/// output that is a device or a directory (exit 1, nothing replaced).
#[test]
fn ltc_fit_refuses_bad_outputs_before_fitting() {
    let run = |args: &[&str]| Command::new(example("ltc_fit")).args(args).current_dir(root()).output().unwrap();
    for args in [&["a.json", "b.json"][..], &["--size"]] {
        let out = run(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("usage: ltc_fit [OUT.json]"));
    }
    let d = scratch("ltc-fit");
    for (path, why) in [("/dev/null", "is not a regular file"), (d.to_str().unwrap(), "is a directory")] {
        let out = run(&[path]);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(1), "{path}: {err}");
        assert!(err.contains(why) && out.stdout.is_empty(), "{path}: {err}");
    }
}
