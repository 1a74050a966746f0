//! The command line against hostile or careless use: files users own are never damaged,
//! directory walks end, arguments that cannot mean anything are refused before any work,
//! and no run leaves temporaries behind.

use crate::cli_common;

use cli_common::{lightbench, root, scratch as temp};
use std::path::{Path, PathBuf};

/// Every file below `dir` that looks like a temporary (ours: `.NAME.lightbench-PID.tmp`).
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    let mut out = vec![];
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(temporaries(&p));
        } else if p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.ends_with(".tmp")) {
            out.push(p);
        }
    }
    out
}

const MESSY: &str =
    "pipeline m\ntexture out:Rgba8Unorm   viewport\nfullscreen f \"fill.wgsl\" { color out clear (-0.0, 0.0, 0.0, 1.0) }\noutput out\n";

#[cfg(unix)]
#[test]
fn fmt_rewrites_through_symlinks_keeps_the_mode_and_is_idempotent() {
    use std::os::unix::fs::PermissionsExt;
    let d = temp("fmt");
    let real = d.join("real.lbp");
    std::fs::write(&real, MESSY).unwrap();
    std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o600)).unwrap();
    let link = d.join("link.lbp");
    std::os::unix::fs::symlink("real.lbp", &link).unwrap();
    let (code, _, err) = lightbench(&["fmt", link.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(),
        "the link is still a link"
    );
    let once = std::fs::read_to_string(&real).unwrap();
    assert!(once.contains("clear(0, 0, 0, 1)"), "-0.0 prints as 0: {once}");
    assert_eq!(std::fs::metadata(&real).unwrap().permissions().mode() & 0o777, 0o600, "mode kept");
    let (code, _, err) = lightbench(&["fmt", "--check", link.to_str().unwrap()]);
    assert_eq!(code, 0, "formatting is idempotent: {err}");
    assert!(temporaries(&d).is_empty(), "{:?}", temporaries(&d));
}

#[test]
fn convert_never_overwrites_its_input_or_contradicts_to() {
    let d = temp("convert");
    let input = d.join("p.lbp");
    std::fs::write(&input, MESSY).unwrap();
    let (code, _, err) = lightbench(&["convert", input.to_str().unwrap(), "--to", "lbp", "-o", input.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("is the input file"), "{err}");
    let (code, _, err) = lightbench(&[
        "convert",
        input.to_str().unwrap(),
        "--to",
        "ron",
        "-o",
        d.join("p.lbp.txt").to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("the name says `.txt` but --to is `ron`"), "{err}");
    assert_eq!(std::fs::read_to_string(&input).unwrap(), MESSY, "the input is untouched");
    let out = d.join("p.ron");
    assert_eq!(
        lightbench(&["convert", input.to_str().unwrap(), "--to", "ron", "-o", out.to_str().unwrap()]).0,
        0
    );
    // The round trip parses: what RON wrote converts back.
    let (code, _, err) = lightbench(&["convert", out.to_str().unwrap(), "--to", "lbp"]);
    assert_eq!(code, 0, "{err}");
    // RON's `inf` cannot be spelled in LBP: refused at the number, not written.
    std::fs::write(
        &out,
        "Pipeline(name: \"p\", resources: {\"o\": Texture(format: Rgba8Unorm, size: Viewport(inf))}, passes: [], output: \"o\")",
    )
    .unwrap();
    let (code, _, err) = lightbench(&[
        "convert",
        out.to_str().unwrap(),
        "--to",
        "lbp",
        "-o",
        d.join("q.lbp").to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert!(
        err.contains("error[non-finite]: `inf` is not a finite number") && err.contains("p.ron:1:81"),
        "{err}"
    );
    assert!(!d.join("q.lbp").exists());
}

#[test]
fn invalid_utf8_and_deep_nesting_are_located_errors_in_every_command() {
    let d = temp("utf8");
    let bad = d.join("p.lbp");
    std::fs::write(&bad, b"pipeline p\n// caf\xe9\noutput o\n").unwrap();
    let nested = d.join("n.lbp");
    let text = format!("pipeline p\ntexture out: Rgba8Unorm viewport\nfullscreen f \"fill.wgsl\" {{\n    color out\n    when {}reflective\n}}\noutput out\n", "not ".repeat(9000));
    std::fs::write(&nested, text).unwrap();
    for (file, code, msg) in [
        (
            &bad,
            "invalid-utf8",
            "not valid UTF-8 (invalid byte at offset 17, line 2, column 7)",
        ),
        (&nested, "nesting-too-deep", "n.lbp:5:262"),
    ] {
        let f = file.to_str().unwrap();
        for cmd in [vec!["check", f], vec!["plan", f], vec!["convert", f, "--to", "ron"], vec!["fmt", f]] {
            let (exit, _, err) = lightbench(&cmd);
            assert_eq!(exit, 1, "{cmd:?}: {err}");
            assert!(err.contains(&format!("error[{code}]")) && err.contains(msg), "{cmd:?}: {err}");
        }
    }
}

#[cfg(unix)]
#[test]
fn check_walks_symlink_loops_once() {
    let d = temp("loops");
    std::fs::create_dir_all(d.join("a/b")).unwrap();
    std::fs::copy(root().join("pipelines/deferred.lbp"), d.join("a/b/p.lbp")).unwrap();
    std::fs::copy(root().join("pipelines/ltc_blinn_phong.json"), d.join("a/b/ltc_blinn_phong.json")).unwrap();
    std::fs::create_dir_all(d.join("shaders")).unwrap();
    std::os::unix::fs::symlink(root().join("shaders"), d.join("a/shaders")).unwrap();
    // Two loops: a link to an ancestor, and two links pointing at each other's directory.
    std::os::unix::fs::symlink("..", d.join("a/b/up")).unwrap();
    std::fs::create_dir_all(d.join("x")).unwrap();
    std::os::unix::fs::symlink(d.join("a"), d.join("x/to_a")).unwrap();
    std::os::unix::fs::symlink(d.join("x"), d.join("a/to_x")).unwrap();
    let (code, _, err) = lightbench(&["check", "--shaders", root().join("shaders").to_str().unwrap(), d.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("checked 1 pipeline file(s)"), "each pipeline once: {err}");
}

#[test]
fn arguments_that_cannot_mean_anything_are_refused_before_rendering() {
    let d = temp("args");
    let out = d.join("x.png");
    let o = out.to_str().unwrap();
    let (same, glb, bin) = (d.join("./x.png"), d.join("c.glb"), d.join("c.bin"));
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["render", "--out", o, "--frames", "0"], "--frames"),
        (
            vec!["render", "--out", o, "--variant", "tonemap=simple", "--variant", "tonemap=reinhard"],
            "--variant `tonemap` is given twice",
        ),
        (
            vec!["render", "--out", o, "--manifest", o],
            "--out and --manifest name the same file",
        ),
        (
            vec!["render", "--out", o, "--timings-json", same.to_str().unwrap()],
            "--out and --timings-json name the same file",
        ),
        (
            vec!["render", "--out", o, "--input", "noise"],
            "invalid --input `noise`: expected NAME=FILE",
        ),
        (
            vec!["plan", "pipelines/deferred.ron", "--lights", "point=4294967296"],
            "expected a whole number from 0 to 4096",
        ),
        (
            vec!["plan", "pipelines/deferred.ron", "--lights", "point=5000"],
            "expected a whole number from 0 to 4096",
        ),
        (
            vec!["plan", "pipelines/deferred.ron", "--lights", "point=2,point=3"],
            "--lights names `point` twice",
        ),
        (
            vec!["plan", "pipelines/deferred.ron", "--lights", "sun=1"],
            "unknown light kind `sun`: expected directional, spot, point or area (an emissive mesh)",
        ),
        (vec!["plan", "pipelines/deferred.ron", "--size", "0x10"], "out of range"),
        (
            vec!["scene", "export", "cornell", glb.to_str().unwrap()],
            "scene export writes .gltf",
        ),
        (
            vec!["scene", "export", "cornell", bin.to_str().unwrap()],
            "scene export writes .gltf",
        ),
    ];
    for (args, msg) in cases {
        let (code, _, err) = lightbench(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(msg), "{args:?}: {err}");
    }
    assert!(
        std::fs::read_dir(&d).unwrap().next().is_none(),
        "nothing written: {:?}",
        std::fs::read_dir(&d).unwrap().collect::<Vec<_>>()
    );
}

#[test]
fn a_killed_runs_temporaries_are_cleaned_and_none_are_left() {
    let d = temp("tmp");
    // What a render killed while writing leaves: a temporary of a PID that is gone.
    let stale = d.join(".frame.png.lightbench-0.tmp");
    std::fs::write(&stale, b"half a png").unwrap();
    let frame = d.join("frame.png");
    let manifest = d.join("manifest.json");
    let (code, _, err) = lightbench(&[
        "render",
        "--out",
        frame.to_str().unwrap(),
        "--manifest",
        manifest.to_str().unwrap(),
        "--size",
        "32x32",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(frame.is_file() && manifest.is_file());
    assert!(temporaries(&d).is_empty(), "{:?}", temporaries(&d));
}

/// `render --out` a FIFO and `--manifest` a device (through a symlink, as in a reference
/// cache): refused before any work (exit 2, nothing written), both left as they were.
#[cfg(unix)]
#[test]
fn render_refuses_to_replace_devices_and_fifos() {
    use std::os::unix::fs::FileTypeExt;
    let d = temp("devices");
    let fifo = d.join("f.png");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let null = d.join("n");
    std::os::unix::fs::symlink("/dev/null", &null).unwrap();
    let png = d.join("o.png");
    for (args, flag) in [
        (vec!["--out", fifo.to_str().unwrap()], "--out"),
        (
            vec!["--out", png.to_str().unwrap(), "--manifest", null.to_str().unwrap()],
            "--manifest",
        ),
    ] {
        let mut a = vec!["render", "--size", "8x8"];
        a.extend(args);
        let (code, _, err) = lightbench(&a);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(flag) && err.contains("not a regular file"), "{err}");
    }
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
    assert!(!png.exists(), "nothing rendered before the refusal");
    assert!(temporaries(&d).is_empty());
}

/// `check` of a FIFO (or a device) is refused in those words, exit 2, without opening it (a
/// FIFO would wait for a writer); under `--format json` as one JSON object on stdout.
#[cfg(unix)]
#[test]
fn check_refuses_fifos_in_the_format_asked_for() {
    let d = temp("check-fifo");
    let fifo = d.join("ff.lbp");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let (code, _, err) = lightbench(&["check", fifo.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("ff.lbp is not a regular file or a directory (a device, pipe or socket)"),
        "{err}"
    );
    let (code, out, _) = lightbench(&["check", fifo.to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 2);
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap_or_else(|e| panic!("{e}: {out}"));
    assert_eq!((v["severity"].as_str(), v["code"].as_str()), (Some("error"), Some("usage")));
    assert!(v["message"].as_str().unwrap().contains("not a regular file or a directory"), "{v}");
    let (code, out, _) = lightbench(&["check", d.join("none.lbp").to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 2);
    assert!(
        out.contains("\"code\":\"usage\"") && out.contains("no such file or directory"),
        "{out}"
    );
    // The other usage errors of `check` alike: an unknown profile, a `--param` no pipeline has.
    let deferred = root().join("pipelines/deferred.lbp");
    for extra in [["--profile", "nope"], ["--param", "no.such=1"]] {
        let mut args = vec!["check", deferred.to_str().unwrap(), "--format", "json"];
        args.extend(extra);
        let (code, out, _) = lightbench(&args);
        assert_eq!(code, 2, "{out}");
        let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap_or_else(|e| panic!("{e}: {out}"));
        assert_eq!(v["code"].as_str(), Some("usage"), "{v}");
    }
}

/// `lightbench check . 2>&1 | head -1`: the reader goes away before the diagnostics are
/// written. The run ends quietly (killed by SIGPIPE, as other tools are, or done first),
/// never with a panic (exit 101).
#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_the_run_quietly() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};
    let d = temp("pipe");
    let (code, _, err) = cli_common::lightbench_in(&d, &["init", "proj"]);
    assert_eq!(code, 0, "{err}");
    // A broken spec: check has diagnostics to write.
    let spec = d.join("proj/sweeps/shadows.ron");
    std::fs::write(
        &spec,
        std::fs::read_to_string(&spec)
            .unwrap()
            .replace("scenes: [\"cornell\"]", "scenes: []"),
    )
    .unwrap();
    for _ in 0..3 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_lightbench"))
            .args(["check", "."])
            .current_dir(d.join("proj"))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        drop(child.stderr.take());
        let status = child.wait().unwrap();
        assert!(
            status.signal() == Some(libc_sigpipe()) || status.code() == Some(1),
            "{status:?}: a closed pipe must not panic"
        );
    }
}

/// SIGPIPE's number (13 on every Unix lightbench builds for).
#[cfg(unix)]
fn libc_sigpipe() -> i32 {
    13
}

/// `init` then `check .`: the sweep specs `init` writes are recognised and checked as specs
/// (they were `unknown-kind` pipelines), and a broken one is an error located in it.
#[test]
fn check_reads_sweep_specs_as_specs() {
    let d = temp("check-sweeps");
    let (code, _, err) = cli_common::lightbench_in(&d, &["init", "proj"]);
    assert_eq!(code, 0, "{err}");
    let proj = d.join("proj");
    let (code, _, err) = cli_common::lightbench_in(&proj, &["check", "."]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("sweep spec(s)") && err.contains(" 0 error(s)"), "{err}");
    let spec = proj.join("sweeps/shadows.ron");
    let text = std::fs::read_to_string(&spec).unwrap();
    std::fs::write(&spec, text.replace("scenes: [\"cornell\"]", "scenes: []")).unwrap();
    let line = text.lines().position(|l| l.contains("scenes: [")).unwrap() + 1;
    let (code, _, err) = cli_common::lightbench_in(&proj, &["check", "."]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("error[sweep-spec]") && err.contains(&format!("sweeps/shadows.ron:{line}:")),
        "{err}"
    );
}

/// Run `lightbench ARGS` in the repository root, killed after 30 s: (exit code or None when
/// it had to be killed, stderr).
fn lightbench_timed(args: &[&str]) -> (Option<i32>, String) {
    use std::io::Read;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .args(args)
        .current_dir(root())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    let code = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s.code();
        }
        if start.elapsed() > std::time::Duration::from_secs(30) {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    let mut err = String::new();
    child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
    (code, err)
}

/// Inputs read through the guarded reader: a FIFO (which would hang a plain read) or
/// /dev/zero (which would eat memory) named as a view script or a sweep spec is refused at
/// once, naming the file.
#[cfg(unix)]
#[test]
fn fifos_and_devices_as_inputs_are_refused_not_read() {
    let d = temp("inputs");
    let fifo = d.join("script.txt");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let f = fifo.to_str().unwrap();
    for args in [
        vec!["view", "--script", f],
        vec!["view", "--script", "/dev/zero"],
        vec!["sweep", f, "--out", d.join("out").to_str().unwrap()],
        vec!["sweep", "/dev/zero", "--out", d.join("out").to_str().unwrap()],
    ] {
        let (code, err) = lightbench_timed(&args);
        // Bad input (a file that cannot be read), not bad usage: exit 1, as a missing one.
        assert_eq!(code, Some(1), "{args:?}: {err}");
        assert!(err.contains("not a regular file"), "{args:?}: {err}");
    }
    assert!(!d.join("out").exists());
}
