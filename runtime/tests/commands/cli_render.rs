//! `lightbench render` and `lightbench scene export` as a user runs them.

use crate::cli_common;

use cli_common::{lightbench as run, lightbench_in, root, scratch as temp};

#[test]
fn render_writes_image_dumps_timings_and_manifest() {
    let d = temp("full");
    let s = |p: &str| d.join(p).display().to_string();
    let (code, out, err) = run(&[
        "render",
        "--out",
        &s("frame.png"),
        "--frames",
        "2",
        "--timings",
        "--timings-json",
        &s("timings.json"),
        "--manifest",
        &s("manifest.json"),
        "--dump",
        "gbuf.normal,shadow.cube,lum",
        "--dump-dir",
        &s("dump"),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("adapter: "), "{err}");
    let img = image::open(d.join("frame.png")).unwrap();
    assert_eq!((img.width(), img.height()), (128, 128));
    // The table lists every executed pass with a GPU time; the static scene's passes ran only
    // in the cold first frame (then were reused), which the table marks and explains.
    for pass in [
        "gbuffer",
        "shadow_cube_classic",
        "ambient",
        "light_point",
        "luminance_tiles",
        "luminance",
        "tonemap",
    ] {
        let line = out
            .lines()
            .find(|l| l.split_whitespace().next() == Some(pass))
            .unwrap_or_else(|| panic!("{pass} missing:\n{out}"));
        let cell = line.split_whitespace().nth(2).unwrap();
        let gpu_ms: f64 = cell
            .strip_suffix('*')
            .unwrap_or_else(|| panic!("not marked cold: {line}"))
            .parse()
            .unwrap_or_else(|_| panic!("no GPU time: {line}"));
        assert!(gpu_ms >= 0.0);
        assert!(line.ends_with("1/2"), "{line}");
    }
    assert!(
        out.contains("* ran only in the first frame (cold: first use), then reused"),
        "{out}"
    );
    assert!(!out.contains("shadow_map"), "culled passes are absent:\n{out}");
    let timings: serde_json::Value = serde_json::from_slice(&std::fs::read(d.join("timings.json")).unwrap()).unwrap();
    let frames = timings.as_array().unwrap();
    assert_eq!(frames.len(), 2, "one array per frame");
    assert!(frames.iter().all(|f| f.as_array().unwrap().len() == 7));
    let manifest: serde_json::Value = serde_json::from_slice(&std::fs::read(d.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["scene"], "cornell");
    assert!(manifest["adapter"]["name"].as_str().unwrap().len() > 2);
    let files = manifest["files"].as_array().unwrap();
    assert!(files.iter().any(|f| f["file"].as_str().unwrap().ends_with("deferred.ron")));
    assert!(files.iter().any(|f| f["file"].as_str().unwrap().ends_with("lib/frame.wgsl")));
    assert!(files.iter().all(|f| f["fnv1a64"].as_str().unwrap().len() == 16));
    assert!(d.join("dump/gbuf.normal.exr").is_file());
    for face in 0..6 {
        assert!(d.join(format!("dump/shadow.cube.light0.layer{face}.exr")).is_file());
    }
    let lum: Vec<f32> = serde_json::from_slice(&std::fs::read(d.join("dump/lum.json")).unwrap()).unwrap();
    assert!(lum[0] > 0.0 && lum[1] >= lum[0], "{lum:?}");
    // With --no-reuse every pass runs every frame: warm means, nothing marked.
    let (code, out, err) = run(&["render", "--out", &s("warm.png"), "--frames", "2", "--timings", "--no-reuse"]);
    assert_eq!(code, 0, "{err}");
    let rows: Vec<&str> = out.lines().filter(|l| l.ends_with("/2")).collect();
    assert_eq!(rows.len(), 7, "{out}");
    assert!(rows.iter().all(|l| l.ends_with("2/2")) && !out.contains('*'), "{out}");
}

/// PNG dumps of one-channel textures are grey; buffer dumps are reported like textures.
#[test]
fn png_dumps_of_single_channel_textures_are_grey() {
    let d = temp("grey");
    let dump = d.join("dump");
    let (code, _, err) = run(&[
        "render",
        "--out",
        d.join("x.png").to_str().unwrap(),
        "--dump",
        "gbuf.depth,lum",
        "--dump-format",
        "png",
        "--dump-dir",
        dump.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains(&format!("dumped {}", dump.join("lum.json").display())), "{err}");
    let depth = image::open(dump.join("gbuf.depth.png")).unwrap().to_rgba8();
    assert!(depth.pixels().all(|p| p.0[0] == p.0[1] && p.0[1] == p.0[2]), "grey, not red");
    assert!(depth.pixels().any(|p| p.0[0] > 100), "depth values show");
}

#[test]
fn render_exr_output_and_bad_arguments() {
    let d = temp("exr");
    let (code, _, err) = run(&["render", "--out", d.join("frame.exr").to_str().unwrap(), "--size", "64x48"]);
    assert_eq!(code, 0, "{err}");
    let img = image::open(d.join("frame.exr")).unwrap();
    assert_eq!((img.width(), img.height()), (64, 48));
    assert_eq!(run(&["render", "--out", d.join("frame.jpg").to_str().unwrap()]).0, 2);
    assert_eq!(run(&["render", "--pipeline", "nope.ron"]).0, 2);
    // A bad --dump name is a usage error found before any frame is rendered or written.
    let (code, _, err) = run(&["render", "--out", d.join("x.png").to_str().unwrap(), "--dump", "gbuf.nrmal"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("`gbuf.nrmal` is not a resource of this plan (did you mean `gbuf.normal`?"),
        "{err}"
    );
    assert!(!d.join("x.png").exists(), "nothing is written when --dump is wrong");
    // A parameter renamed when its unit changed (docs/effects.md): the old name is refused,
    // the new one suggested.
    let (code, _, err) = run(&["render", "--out", d.join("x.png").to_str().unwrap(), "--param", "cube.bias=0.002"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("did you mean `cube.bias_texels`?"), "{err}");
    // A --variant typo is a usage error, as a --param typo is.
    let (code, _, err) = run(&["render", "--out", d.join("x.png").to_str().unwrap(), "--variant", "tonemap=filmic"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("variant `tonemap` has no option `filmic`"), "{err}");
}

#[test]
fn scene_export_writes_gltf_and_bin() {
    let d = temp("export");
    for name in ["cornell", "colonnade", "many_lights"] {
        let out = d.join(format!("{name}.gltf"));
        let (code, _, err) = run(&["scene", "export", name, out.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
        assert!(out.is_file() && d.join(format!("{name}.bin")).is_file());
    }
    assert_eq!(run(&["scene", "export", "sponza", d.join("s.gltf").to_str().unwrap()]).0, 2);
    // Emission past glTF's 0..1 factors goes out as a strength and comes back as it was.
    let lamp = d.join("cornell_lamp.gltf");
    assert_eq!(run(&["scene", "export", "cornell_lamp", lamp.to_str().unwrap()]).0, 0);
    let text = std::fs::read_to_string(&lamp).unwrap();
    assert!(text.contains("KHR_materials_emissive_strength"), "{text}");
    let back = lightbench::scene::load::load_sized(lamp.to_str().unwrap(), None, &[]).unwrap();
    let emissive: Vec<[f32; 3]> = back
        .materials
        .iter()
        .map(|m| m.emissive)
        .filter(|e| e.iter().any(|c| *c > 0.0))
        .collect();
    assert_eq!(emissive.len(), 1, "{emissive:?}");
    assert!(
        emissive[0].iter().zip([17.0, 12.0, 4.0]).all(|(a, b)| (a - b).abs() < 1e-4),
        "{emissive:?}"
    );
}

/// A write that fails half-way (a file-size limit stands in for a full disk: the buffer fits,
/// the glTF file does not) leaves neither file, no temporary, and an earlier export as it was.
#[cfg(unix)]
#[test]
fn scene_export_that_cannot_finish_leaves_nothing() {
    let d = temp("export-full");
    let export = || {
        // SIGXFSZ ignored: a write past the limit fails with EFBIG instead of killing.
        std::process::Command::new("bash")
            .arg("-c")
            .arg(format!(
                "trap '' XFSZ; ulimit -f 8; exec {} scene export cornell e.gltf",
                env!("CARGO_BIN_EXE_lightbench")
            ))
            .current_dir(&d)
            .output()
            .unwrap()
    };
    let out = export();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("e.gltf: cannot write"), "{err}");
    let left: Vec<_> = std::fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert!(left.is_empty(), "nothing left behind: {left:?}");
    // Over earlier files: both stay as they were.
    std::fs::write(d.join("e.gltf"), "earlier glTF").unwrap();
    std::fs::write(d.join("e.bin"), "earlier buffer").unwrap();
    assert_eq!(export().status.code(), Some(1));
    assert_eq!(std::fs::read_to_string(d.join("e.gltf")).unwrap(), "earlier glTF");
    assert_eq!(std::fs::read_to_string(d.join("e.bin")).unwrap(), "earlier buffer");
    assert_eq!(std::fs::read_dir(&d).unwrap().count(), 2, "no temporary left");
}

/// A write killed before its rename leaves `.NAME.lightbench-PID.tmp`; the next run of any
/// writing command in that folder removes it (its process is gone), for every command that
/// writes files: fmt, scene export, render's EXR, reference.
#[test]
fn a_killed_writes_temporary_goes_at_the_next_run_in_its_folder() {
    let dead = {
        let mut c = std::process::Command::new("true").spawn().unwrap();
        c.wait().unwrap();
        c.id()
    };
    let d = temp("stale");
    std::fs::copy(root().join("pipelines/deferred.lbp"), d.join("p.lbp")).unwrap();
    let runs: [&[&str]; 4] = [
        &["fmt", "p.lbp"],
        &["scene", "export", "cornell", "e.gltf"],
        &["render", "--size", "16x16", "--out", "r.exr"],
        &[
            "reference",
            "--scene",
            "cornell",
            "--size",
            "8x8",
            "--spp",
            "1",
            "--terms",
            "direct",
            "--out",
            ".",
            "--quiet",
        ],
    ];
    for args in runs {
        let stale = d.join(format!(".killed.png.lightbench-{dead}-0.tmp"));
        std::fs::write(&stale, "half a file").unwrap();
        let (code, _, err) = lightbench_in(&d, args);
        assert_eq!(code, 0, "{args:?}: {err}");
        assert!(!stale.exists(), "{args:?} left a dead run's temporary");
    }
    let left: Vec<_> = (std::fs::read_dir(&d).unwrap())
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// README command 1 from a folder with no checkout: the bundled default pipeline renders.
#[test]
fn render_works_outside_a_checkout() {
    let d = temp("no-checkout");
    let (code, _, err) = lightbench_in(&d, &["render"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("rendering the one bundled in lightbench"), "{err}");
    let img = image::open(d.join("lightbench.png")).unwrap().to_rgb8();
    let first = img.get_pixel(0, 0);
    let differing = img.pixels().filter(|p| p != &first).count();
    assert!(differing > 1000, "a non-uniform image: {differing} pixels differ from the first");
}

/// `init` writes the bundled project into a fresh folder, refuses to overwrite anything, and
/// what it wrote renders.
#[test]
fn init_writes_the_bundled_project_and_overwrites_nothing() {
    let d = temp("init");
    let (code, _, err) = lightbench_in(&d, &["init", "proj"]);
    assert_eq!(code, 0, "{err}");
    let proj = d.join("proj");
    for f in [
        "pipelines/deferred.ron",
        "pipelines/deferred_gi.lbp",
        "shaders/lib/frame.wgsl",
        "scenes/sun_only.ron",
        "scenes/chair.gltf",
    ] {
        assert_eq!(std::fs::read(proj.join(f)).unwrap(), std::fs::read(root().join(f)).unwrap(), "{f}");
    }
    std::fs::write(proj.join("shaders/tonemap.wgsl"), "// mine\n").unwrap();
    let (code, _, err) = lightbench_in(&d, &["init", "proj"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("exists already; init writes into a fresh folder and overwrites nothing"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(proj.join("shaders/tonemap.wgsl")).unwrap(), "// mine\n");
    std::fs::remove_file(proj.join("shaders/tonemap.wgsl")).unwrap();
    std::fs::copy(root().join("shaders/tonemap.wgsl"), proj.join("shaders/tonemap.wgsl")).unwrap();
    let (code, _, err) = lightbench_in(&proj, &["render", "--scene", "scenes/sun_only.ron", "--size", "32x32"]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("bundled"), "the project's own files are used: {err}");
}

/// A `render --watch` child's output once it exits; killed (and the test failed) if it has not
/// within `secs`, so a reload that never comes fails instead of hanging.
fn finish_within(mut child: std::process::Child, secs: u64) -> std::process::Output {
    let started = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed().as_secs() > secs {
            child.kill().unwrap();
            let out = child.wait_with_output().unwrap();
            panic!("no reload within {secs} s: {}", String::from_utf8_lossy(&out.stderr));
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

/// `render --watch` as the README writes it: a running render reloads a saved shader edit,
/// reports a broken save and keeps going, and rewrites `--out` after each reload.
/// A project `init` writes under a folder named `tag`, and `render --watch` started in it to
/// stop after `reloads` reloads: (the project, the child, its first frame's file bytes).
fn watching(tag: &str, reloads: &str) -> (std::path::PathBuf, std::process::Child, Vec<u8>) {
    watching_with(tag, reloads, &[])
}

/// `watching`, `render` given `more` arguments too.
fn watching_with(tag: &str, reloads: &str, more: &[&str]) -> (std::path::PathBuf, std::process::Child, Vec<u8>) {
    let d = temp(tag);
    let (code, _, err) = lightbench_in(&d, &["init", "proj"]);
    assert_eq!(code, 0, "{err}");
    let proj = d.join("proj");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .args(["render", "--watch", "--watch-reloads", reloads, "--size", "32x32", "--out", "w.png"])
        .args(more)
        .current_dir(&proj)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while !proj.join("w.png").is_file() {
        assert!(started.elapsed().as_secs() < 60, "no first frame");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let first = std::fs::read(proj.join("w.png")).unwrap();
    (proj, child, first)
}

#[test]
fn render_watch_reloads_and_reports() {
    // After the first frame, save an edit and a broken file.
    let (proj, child, first) = watching("watch", "2");
    let tonemap = proj.join("shaders/tonemap.wgsl");
    let text = std::fs::read_to_string(&tonemap).unwrap();
    std::fs::write(&tonemap, text.replace("vec3<f32>(1.0)), 1.0);", "vec3<f32>(1.0)) * 0.5, 1.0);")).unwrap();
    std::thread::sleep(std::time::Duration::from_millis(500));
    std::fs::write(&tonemap, "fn broken(").unwrap();
    let out = finish_within(child, 120);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(
        err.contains("reloaded: first new frame") && err.contains("ms after the change"),
        "{err}"
    );
    assert!(
        err.contains("reload failed: still rendering the last good pipeline") && err.contains("error["),
        "{err}"
    );
    assert_ne!(
        std::fs::read(proj.join("w.png")).unwrap(),
        first,
        "--out rewritten after the reload"
    );
}

/// `render --watch` after its shader folder is swapped for another (as a checkout does): it
/// says it watches the folder again and reloads from the new files.
#[test]
fn render_watch_follows_a_replaced_folder() {
    let (proj, child, first) = watching("watch-replaced", "1");
    // The new folder made beside, then swapped in.
    let (shaders, new) = (proj.join("shaders"), proj.join("shaders.new"));
    for d in ["", "lib"] {
        std::fs::create_dir(new.join(d)).unwrap();
        for e in std::fs::read_dir(shaders.join(d)).unwrap().map(Result::unwrap) {
            if e.file_type().unwrap().is_file() {
                std::fs::copy(e.path(), new.join(d).join(e.file_name())).unwrap();
            }
        }
    }
    let tonemap = new.join("tonemap.wgsl");
    let text = std::fs::read_to_string(&tonemap).unwrap();
    std::fs::write(&tonemap, text.replace("vec3<f32>(1.0)), 1.0);", "vec3<f32>(1.0)) * 0.5, 1.0);")).unwrap();
    std::fs::rename(&shaders, proj.join("shaders.old")).unwrap();
    std::fs::rename(&new, &shaders).unwrap();
    let out = finish_within(child, 120);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(err.contains("shaders again: the folder was replaced"), "{err}");
    assert!(err.contains("reloaded: first new frame"), "{err}");
    assert_ne!(std::fs::read(proj.join("w.png")).unwrap(), first, "rendered from the new folder");
}

/// `render --watch` of a scene file: an edit of one of its models (the ground's colour) reloads
/// the scene — that model parsed again, the other (the chair) taken as it was — and says what
/// stayed on the GPU: every mesh, since no geometry changed.
#[test]
fn render_watch_reloads_an_edited_model_keeping_its_meshes_resident() {
    let (proj, child, first) = watching_with("watch-model", "1", &["--scene", "scenes/sun_only.ron"]);
    let ground = proj.join("scenes/ground.gltf");
    let mut doc: serde_json::Value = serde_json::from_slice(&std::fs::read(&ground).unwrap()).unwrap();
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = serde_json::json!([0.05, 0.05, 0.05, 1.0]);
    std::fs::write(&ground, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    let out = finish_within(child, 120);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    // The line docs/commands.md quotes: the ground and the chair, no textures.
    assert!(
        err.contains("; scene reloaded (1 of 2 models as they were), kept resident: 2 of 2 meshes, 0 of 0 textures\n"),
        "{err}"
    );
    assert_ne!(std::fs::read(proj.join("w.png")).unwrap(), first, "the darker ground rendered");
}

/// `--watch` needs files on disk to watch, and `--watch-reloads` needs `--watch`: usage errors.
#[test]
fn render_watch_bad_arguments() {
    let d = temp("watch-bad");
    let (code, _, err) = lightbench_in(&d, &["render", "--watch"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--watch needs pipeline files on disk to watch"), "{err}");
    assert!(!d.join("lightbench.png").exists(), "nothing written");
    let (code, _, err) = lightbench_in(&d, &["render", "--watch-reloads", "2"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--watch"), "{err}");
}

/// A model given on its own calls for shadows only: `deferred_gi` culls its indirect passes
/// and says so once, naming the flag; `--effect IndirectDiffuse` runs them (the README's
/// command); an unknown effect is a usage error with a suggestion.
#[test]
fn effect_adds_to_a_model_given_on_its_own_and_culled_effects_are_noted() {
    let d = temp("effect");
    let out = d.join("gi.png").display().to_string();
    let model = root().join("scenes/chair.gltf").display().to_string();
    let gi = root().join("pipelines/deferred_gi.ron").display().to_string();
    let base = [
        "render",
        "--pipeline",
        &gi,
        "--scene",
        &model,
        "--size",
        "48x48",
        "--out",
        &out,
        "--timings",
    ];
    let (code, stdout, err) = run(&base);
    assert_eq!(code, 0, "{err}");
    let notes: Vec<&str> = err.lines().filter(|l| l.starts_with("note: deferred_gi: the passes for")).collect();
    assert_eq!(notes.len(), 1, "{err}");
    assert!(
        notes[0].contains("IndirectDiffuse") && notes[0].contains("--effect IndirectDiffuse"),
        "{err}"
    );
    assert!(!stdout.lines().any(|l| l.starts_with("indirect_diffuse")), "{stdout}");
    let (code, stdout, err) = run(&[&base[..], &["--effect", "IndirectDiffuse"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(stdout.lines().any(|l| l.starts_with("indirect_diffuse")), "{stdout}");
    assert!(!err.contains("IndirectDiffuse"), "no longer noted: {err}");
    let bad = d.join("bad.png").display().to_string();
    let mut args = base.to_vec();
    let at = args.iter().position(|a| *a == out.as_str()).unwrap();
    args[at] = &bad;
    let (code, _, err) = run(&[&args[..], &["--effect", "IndirectDifuse"]].concat());
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("unknown effect `IndirectDifuse`") && err.contains("did you mean `IndirectDiffuse`?"),
        "{err}"
    );
    assert!(!d.join("bad.png").exists(), "a usage error writes nothing");
}

/// The Cornell box lit by its point light calls for indirect light that `deferred_gi`'s RSM
/// options cannot give (they gather from directional and spot lights and emissive meshes):
/// `render` says so, naming the pass and why (docs/commands.md), where it would otherwise add
/// a silent 0; the ray-traced option serves it.
#[test]
fn an_effect_no_kept_pass_serves_is_noted() {
    let d = temp("unserved");
    let out = d.join("lamp.png").display().to_string();
    let gi = root().join("pipelines/deferred_gi.lbp").display().to_string();
    let base = [
        "render",
        "--pipeline",
        &gi,
        "--scene",
        "cornell",
        "--effect",
        "IndirectDiffuse",
        "--size",
        "32x32",
        "--out",
        &out,
    ];
    let (code, _, err) = run(&base);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("note: deferred_gi: the scene `cornell` calls for IndirectDiffuse, but every pass serving it is culled: `rsm` runs per Directional, Spot or Area light and the scene has none"),
        "{err}"
    );
    let (code, _, err) = run(&[&base[..], &["--variant", "indirect_diffuse=rt"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("calls for IndirectDiffuse"), "{err}");
}

/// The README's `--param tonemap.by_luminance=true` and `--param lengths.world=true`, as typed:
/// the luminance pass records the rule it metered by (the fifth word of `lum`); a value of
/// the wrong type is an error that writes nothing.
#[test]
fn the_readme_exposure_and_length_params_render() {
    let d = temp("rule-params");
    let s = |p: &str| d.join(p).display().to_string();
    let gi = root().join("pipelines/deferred_gi.ron").display().to_string();
    let scene = root().join("scenes/cornell_spot.ron").display().to_string();
    for (rule, expected) in [("false", 0.0), ("true", 1.0)] {
        let dump = s(&format!("dump-{rule}"));
        let (code, _, err) = run(&[
            "render",
            "--pipeline",
            &gi,
            "--scene",
            &scene,
            "--size",
            "32x32",
            "--out",
            &s("x.png"),
            "--param",
            &format!("tonemap.by_luminance={rule}"),
            "--param",
            "lengths.world=true",
            "--dump",
            "lum",
            "--dump-dir",
            &dump,
        ]);
        assert_eq!(code, 0, "{err}");
        let lum: Vec<f32> = serde_json::from_slice(&std::fs::read(d.join(format!("dump-{rule}/lum.json"))).unwrap()).unwrap();
        assert_eq!(lum[4], expected, "{lum:?}");
    }
    let (code, _, err) = run(&["render", "--pipeline", &gi, "--out", &s("bad.png"), "--param", "lengths.world=2"]);
    assert_ne!(code, 0, "{err}");
    assert!(err.contains("lengths.world"), "{err}");
    assert!(!d.join("bad.png").exists());
}

/// The README's `--param bloom_up.strength=0.5`: a per-pass value set like a parameter. Less
/// strength in the up-sample pass adds less bloom to the HDR image (threshold lowered so the
/// small Cornell box blooms at all); the manifest records the value; typos, non-numbers and
/// values past f32 are usage errors naming the value; `check` knows the name too.
#[test]
fn per_pass_values_are_set_like_parameters() {
    let d = temp("pass-values");
    let s = |p: &str| d.join(p).display().to_string();
    let deferred = root().join("pipelines/deferred.ron").display().to_string();
    let render = |strength: &str, out: &str| {
        run(&[
            "render",
            "--pipeline",
            &deferred,
            "--effect",
            "Bloom",
            "--size",
            "32x32",
            "--param",
            "bloom.threshold=0.05",
            "--param",
            &format!("bloom_up.strength={strength}"),
            "--out",
            &s(out),
            "--manifest",
            &s(&format!("{out}.json")),
        ])
    };
    let mut sums = vec![];
    for (strength, out) in [("0", "s0.exr"), ("0.5", "s05.exr"), ("1", "s1.exr")] {
        let (code, _, err) = render(strength, out);
        assert_eq!(code, 0, "{err}");
        let img = image::open(d.join(out)).unwrap().into_rgb32f();
        let sum: f64 = img.pixels().flat_map(|p| p.0).map(f64::from).sum();
        assert!(sum.is_finite());
        sums.push(sum);
        let manifest = std::fs::read_to_string(d.join(format!("{out}.json"))).unwrap();
        let m: serde_json::Value = serde_json::from_str(&manifest).unwrap();
        let recorded = m["params"].as_array().unwrap().iter().find(|p| p["name"] == "bloom_up.strength");
        assert_eq!(
            recorded.unwrap()["value"]["Float"].as_f64(),
            Some(strength.parse().unwrap()),
            "{manifest}"
        );
    }
    assert!(
        sums[0] < sums[1] && sums[1] < sums[2],
        "more up-sample strength, more bloom: {sums:?}"
    );
    for (value, msg) in [
        ("bloom_up.strenght=1", "did you mean `bloom_up.strength`?"),
        ("bloom_up.strength=much", "bloom_up.strength"),
        ("bloom_up.strength=1e39", "`1e39` is not a finite 32-bit number"),
    ] {
        let (code, _, err) = run(&[
            "render",
            "--pipeline",
            &deferred,
            "--effect",
            "Bloom",
            "--param",
            value,
            "--out",
            &s("bad.png"),
        ]);
        assert_eq!(code, 2, "{value}: {err}");
        assert!(err.contains(msg), "{value}: {err}");
    }
    assert!(!d.join("bad.png").exists(), "a usage error writes nothing");
    // `check` addresses the same names: a blur's direction is a vec2.
    let gi = root().join("pipelines/deferred_gi.ron").display().to_string();
    assert_eq!(run(&["check", &deferred, &gi, "--param", "bloom_up.strength=0.5"]).0, 0);
    assert_eq!(run(&["check", &gi, "--param", "ao_blur_h.dir=0,1"]).0, 0);
    let (code, _, err) = run(&["check", &gi, "--param", "ao_blur_h.dir=0,1,0"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("ao_blur_h.dir"), "{err}");
}

/// `render --alias`: the same image in less memory, and no dump of a resource that shares
/// memory (exit 2, naming the other).
#[test]
fn render_alias_renders_the_same_image_and_refuses_shared_dumps() {
    let dir = temp("alias");
    let args = |out: &std::path::Path| -> Vec<String> {
        [
            "render",
            "--pipeline",
            "pipelines/deferred_gi.lbp",
            "--scene",
            "scenes/cornell_spot.ron",
            "--out",
        ]
        .iter()
        .map(|s| s.to_string())
        .chain([out.display().to_string()])
        .collect()
    };
    let (own, aliased) = (dir.join("own.png"), dir.join("aliased.png"));
    let a: Vec<String> = args(&own);
    let (code, _, err) = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    let mut b = args(&aliased);
    b.push("--alias".into());
    let (code, _, err) = run(&b.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("resources: 6.45 MiB with transient memory aliased (6.52 MiB each its own)"),
        "{err}"
    );
    assert_eq!(std::fs::read(&own).unwrap(), std::fs::read(&aliased).unwrap());
    b.extend(["--dump".to_string(), "gbuf.emissive".to_string()]);
    let (code, _, err) = run(&b.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 2);
    assert!(
        err.contains("`gbuf.emissive` shares memory with `gi.indirect` under --alias"),
        "{err}"
    );
}

/// Ray-traced shadows as a user asks for them: on wgpu's GL backend (no ray queries) `render`
/// says why it falls back to shadow maps and renders the image the maps give; on a scene with
/// nothing to trace it refuses with exit 1, naming the scene and what to do, and writes nothing.
#[test]
fn ray_traced_shadows_fall_back_on_gl_and_refuse_an_empty_scene() {
    let dir = temp("rt-render");
    let (rt, maps) = (dir.join("rt.png"), dir.join("maps.png"));
    let render = |out: &std::path::Path, variant: &[&str]| {
        let mut args = vec!["render", "--backend", "gl", "--size", "32x32", "--out", out.to_str().unwrap()];
        args.extend(variant);
        run(&args)
    };
    let (code, _, err) = render(&rt, &["--variant", "shadows=rt"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("variant shadows = maps (`rt` needs feature ExperimentalRayQuery") && err.contains("falling back to `maps`)"),
        "{err}"
    );
    let (code, _, err) = render(&maps, &[]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        std::fs::read(&rt).unwrap(),
        std::fs::read(&maps).unwrap(),
        "the fallback renders what the maps render"
    );
    let empty = dir.join("empty.ron");
    let scene = "Scene(name: \"empty\", size: (16, 16), lights: [Directional(direction: (0.3, -1.0, -0.4), intensity: 3.0)])\n";
    std::fs::write(&empty, scene).unwrap();
    let out = dir.join("empty.png");
    let args = [
        "render",
        "--scene",
        empty.to_str().unwrap(),
        "--variant",
        "shadows=rt",
        "--out",
        out.to_str().unwrap(),
    ];
    let (code, _, err) = run(&args);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("scene `empty` has no triangles to trace rays against"), "{err}");
    assert!(!out.exists());
}
