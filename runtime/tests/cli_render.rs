//! `lightbench render` and `lightbench scene export` as a user runs them.

mod cli_common;

use cli_common::{lightbench as run, scratch as temp};

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
    // The table lists every executed pass with a GPU time.
    for pass in ["gbuffer", "shadow_cube_classic", "ambient", "light_point", "luminance", "tonemap"] {
        let line = out
            .lines()
            .find(|l| l.starts_with(pass))
            .unwrap_or_else(|| panic!("{pass} missing:\n{out}"));
        let gpu_ms: f64 = line
            .split_whitespace()
            .nth(2)
            .unwrap()
            .parse()
            .unwrap_or_else(|_| panic!("no GPU time: {line}"));
        assert!(gpu_ms >= 0.0);
    }
    assert!(!out.contains("shadow_map"), "culled passes are absent:\n{out}");
    let timings: serde_json::Value = serde_json::from_slice(&std::fs::read(d.join("timings.json")).unwrap()).unwrap();
    let frames = timings.as_array().unwrap();
    assert_eq!(frames.len(), 2, "one array per frame");
    assert!(frames.iter().all(|f| f.as_array().unwrap().len() == 6));
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
    let (code, _, err) = run(&["render", "--out", d.join("x.png").to_str().unwrap(), "--variant", "tonemap=filmic"]);
    assert_eq!(code, 1);
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
}
