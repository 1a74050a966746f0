//! The GPU-free commands as a user runs them: exit codes, output formats, messages.

use crate::cli_common;

use cli_common::{lightbench, root, scratch};
use std::path::PathBuf;

fn temp_project(tag: &str, pipeline: &str) -> PathBuf {
    let d = scratch(tag);
    std::fs::create_dir_all(d.join("shaders")).unwrap();
    std::fs::write(d.join("p.ron"), pipeline).unwrap();
    std::fs::write(
        d.join("shaders/fill.wgsl"),
        "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0);\n}\n",
    )
    .unwrap();
    d
}

#[test]
fn check_bundled_pipelines_succeeds() {
    let (code, _, err) = lightbench(&["check", "pipelines/"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("checked 6 pipeline file(s) against profile `vulkan`: 0 error(s), 0 warning(s)"),
        "{err}"
    );
    // The raster pipelines run everywhere (their ray-traced options fall back); the path
    // tracer needs ray queries, and says so.
    for profile in ["webgpu", "gl"] {
        for p in ["deferred.ron", "deferred.lbp", "deferred_gi.ron", "deferred_gi.lbp"] {
            let (code, _, err) = lightbench(&["check", "--profile", profile, &format!("pipelines/{p}")]);
            assert_eq!(code, 0, "{profile} {p}: {err}");
        }
        for p in ["pathtrace.ron", "pathtrace.lbp"] {
            let (code, _, err) = lightbench(&["check", "--profile", profile, &format!("pipelines/{p}")]);
            assert_eq!(code, 1, "{profile} {p}: {err}");
            assert!(
                err.contains("option `full` needs feature ExperimentalRayQuery") && err.contains(&format!("profile `{profile}` lacks")),
                "{profile} {p}: {err}"
            );
        }
    }
}

#[test]
fn check_reports_errors_rustc_style_and_exits_1() {
    let d = temp_project("err", "Pipeline(\n    name: \"x\",\n    resources: {\"out\": Texture(format: Rgba8Unorm)},\n    passes: [Fullscreen(name: \"f\", shader: \"fill.wgsl\", color: [\"outt\"])],\n    output: \"out\",\n)\n");
    let (code, _, err) = lightbench(&["check", d.join("p.ron").to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("error[unknown-resource]: no resource named `outt`"), "{err}");
    assert!(err.contains(&format!("┌─ {}:4:65", d.join("p.ron").display())), "{err}");
    assert!(err.contains("= did you mean `out`?"), "{err}");
}

#[test]
fn check_json_is_one_object_per_diagnostic() {
    let d = temp_project("json", "Pipeline(\n    name: \"x\",\n    resources: {\"out\": Texture(format: Rgba8Unorm)},\n    passes: [Fullscreen(name: \"f\", shader: \"fill.wgsl\", color: [\"out\"], colr: 1)],\n    output: \"out\",\n)\n");
    let (code, out, _) = lightbench(&["check", "--format", "json", d.join("p.ron").to_str().unwrap()]);
    assert_eq!(code, 1);
    let lines: Vec<serde_json::Value> = out.lines().map(|l| serde_json::from_str(l).expect("json line")).collect();
    assert_eq!(lines.len(), 1, "{out}");
    let d0 = &lines[0];
    assert_eq!(d0["severity"], "error");
    assert_eq!(d0["code"], "unknown-key");
    assert_eq!(d0["message"], "unknown key `colr` in pass `f`");
    assert_eq!((d0["line"].as_u64(), d0["column"].as_u64()), (Some(4), Some(73)));
    assert_eq!((d0["end"]["line"].as_u64(), d0["end"]["column"].as_u64()), (Some(4), Some(77)));
    assert!(d0["file"].as_str().unwrap().ends_with("p.ron"));
    // Secondary labels come with their own locations: the shader-side one of a binding error.
    std::fs::write(d.join("shaders/fill.wgsl"), "@group(2) @binding(0) var missing: texture_2d<f32>;\n@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return textureLoad(missing, vec2<i32>(0), 0);\n}\n").unwrap();
    std::fs::write(d.join("p.ron"), "Pipeline(\n    name: \"x\",\n    resources: {\"out\": Texture(format: Rgba8Unorm)},\n    passes: [Fullscreen(name: \"f\", shader: \"fill.wgsl\", color: [\"out\"])],\n    output: \"out\",\n)\n").unwrap();
    let (code, out, _) = lightbench(&["check", "--format", "json", d.join("p.ron").to_str().unwrap()]);
    assert_eq!(code, 1, "{out}");
    let d0: serde_json::Value = serde_json::from_str(out.lines().next().unwrap()).unwrap();
    assert_eq!(d0["code"], "binding-unsatisfied", "{d0}");
    let labels = d0["labels"].as_array().unwrap();
    let files: Vec<&str> = labels.iter().map(|l| l["file"].as_str().unwrap()).collect();
    assert!(
        files.iter().any(|f| f.ends_with("fill.wgsl")) && files.iter().any(|f| f.ends_with("p.ron")),
        "{d0}"
    );
    assert!(
        labels.iter().any(|l| l["primary"] == false && l["line"].as_u64() == Some(4)),
        "the pass is a secondary label: {d0}"
    );
}

#[test]
fn usage_errors_exit_2() {
    assert_eq!(lightbench(&["check", "--profile", "vulcan", "pipelines/"]).0, 2);
    let (code, _, err) = lightbench(&["check", "--profile", "vulcan", "pipelines/"]);
    assert!(err.contains("did you mean `vulkan`?"), "{err}");
    assert_eq!(code, 2);
    assert_eq!(lightbench(&["check", "does/not/exist"]).0, 2);
    assert_eq!(lightbench(&["check"]).0, 2);
    assert_eq!(lightbench(&["plan", "pipelines/deferred.ron", "--variant", "nonsense"]).0, 2);
    assert_eq!(lightbench(&["plan", "pipelines/deferred.ron", "--size", "12x"]).0, 2);
}

#[test]
fn plan_explain_names_culling_reasons() {
    let (code, out, err) = lightbench(&["plan", "pipelines/deferred.ron", "--scene", "scenes/sun_only.ron", "--explain"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("shadow_cube_classic        runs per Point light and the scene has none"),
        "{out}"
    );
    assert!(
        out.contains("shadow_cube_atlas          variant not chosen: `cube_shadow` is `classic`, this pass belongs to `instanced`"),
        "{out}"
    );
    assert!(out.contains("block `params`: 12 bytes, align 4"), "{out}");
}

/// A `--variant` name or option the pipeline does not have is a usage error (exit 2, as a
/// `--param` typo is), named on the command line's terms, with a suggestion — for `plan`
/// and `render` alike, before anything is rendered.
/// A `per_pixel` buffer is sized when the Plan is made: past the storage binding limit at the
/// size asked for, a located error at its declared size and exit 1 (fragment lists at 64
/// bytes per pixel fit up to about 2 million pixels).
#[test]
fn a_per_pixel_buffer_too_large_for_the_size_is_located() {
    let fits = [
        "plan",
        "pipelines/deferred.ron",
        "--scene",
        "panes",
        "--variant",
        "transparency=fragment_lists",
    ];
    let (code, _, err) = lightbench(&[&fits[..], &["--size", "1920x1080"]].concat());
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = lightbench(&[&fits[..], &["--size", "2048x1100"]].concat());
    assert_eq!(code, 1, "{err}");
    assert!(out.is_empty(), "{out}");
    assert!(
        err.contains("error[limit-exceeded]: `oit.nodes` is 144179200 bytes at 2048×1100 (64 per pixel), over the 134217728-byte limit of profile `vulkan`"),
        "{err}"
    );
    assert!(
        err.contains("pipelines/deferred.ron:74:35") && err.contains("limit: max_storage_buffer_binding_size"),
        "{err}"
    );
}

/// An option that jitters the camera (`aa = taa`, `jitter: true`) says so at the end of the
/// plan, as the README tells; the default does not jitter.
#[test]
fn plan_says_when_the_camera_jitters() {
    let line = "camera: jittered by a sub-pixel offset each frame (Halton 2, 3 over 16 frames)";
    let (code, out, err) = lightbench(&["plan", "pipelines/deferred.ron", "--variant", "aa=taa"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.trim_end().ends_with(line), "{out}");
    let (_, out, _) = lightbench(&["plan", "pipelines/deferred.ron"]);
    assert!(!out.contains("jittered"), "{out}");
}

#[test]
fn plan_unknown_variant_is_an_error_with_suggestion() {
    let (code, _, err) = lightbench(&["plan", "pipelines/deferred.ron", "--variant", "cube_shadows=classic"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("error: --variant: pipeline `deferred` has no variant `cube_shadows`; did you mean `cube_shadow`?"),
        "{err}"
    );
    let out = std::env::temp_dir().join(format!("lightbench-variant-typo-{}.png", std::process::id()));
    let (code, _, err) = lightbench(&[
        "render",
        "--size",
        "8x8",
        "--out",
        out.to_str().unwrap(),
        "--variant",
        "cube_shadow=classik",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--variant: variant `cube_shadow` has no option `classik`; did you mean `classic`?"),
        "{err}"
    );
    assert!(!out.exists());
}

/// `--variant k=option!` as the README writes it: where the profile cannot run the option,
/// an error naming what it lacks and exit 1, nothing planned; where it can, the option runs.
#[test]
fn a_forced_variant_option_refuses_to_fall_back() {
    let (code, out, err) = lightbench(&[
        "plan",
        "pipelines/deferred.ron",
        "--profile",
        "gl",
        "--variant",
        "cube_shadow=multiview!",
    ]);
    assert_eq!(code, 1, "{out}{err}");
    assert!(out.is_empty(), "{out}");
    assert!(
        err.contains("error[variant-unsupported]: variant `cube_shadow` option `multiview` was asked for without fallback (`multiview!`)"),
        "{err}"
    );
    let (code, out, err) = lightbench(&[
        "plan",
        "pipelines/deferred.ron",
        "--profile",
        "vulkan",
        "--variant",
        "cube_shadow=multiview!",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("cube_shadow = multiview"), "{out}");
}

#[test]
fn plan_dot_and_json() {
    let (code, out, _) = lightbench(&["plan", "pipelines/deferred.ron", "--dot"]);
    assert_eq!(code, 0);
    assert!(
        out.starts_with("digraph \"deferred\" {") && out.contains("\"pass:gbuffer\" -> \"res:gbuf.normal\";"),
        "{out}"
    );
    let (code, out, _) = lightbench(&[
        "plan",
        "pipelines/deferred.ron",
        "--json",
        "--size",
        "640x360",
        "--lights",
        "point=2",
    ]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["resolution"], serde_json::json!([640, 360]));
    let cube = v["resources"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["name"] == "shadow.cube")
        .unwrap();
    assert_eq!(cube["instances"], 2);
    // `area=N` plans N emissive meshes' lights: the RSMs run per directional and spot light
    // (kinds not named keep one each) and per emitter.
    let (code, out, err) = lightbench(&["plan", "pipelines/deferred_gi.lbp", "--json", "--lights", "spot=1,area=2"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let flux = v["resources"].as_array().unwrap().iter().find(|r| r["name"] == "rsm.flux").unwrap();
    assert_eq!(flux["instances"], 4);
}

#[test]
fn check_with_a_scene_file() {
    let (code, _, err) = lightbench(&["check", "--scene", "scenes/sun_only.ron", "pipelines/deferred.ron"]);
    assert_eq!(code, 0, "{err}");
    let d = temp_project("scene", "Pipeline(name: \"x\", passes: [], output: \"o\")");
    std::fs::write(d.join("bad_scene.ron"), "Scene(lights: [Pointt()])").unwrap();
    let (code, _, err) = lightbench(&[
        "check",
        "--scene",
        d.join("bad_scene.ron").to_str().unwrap(),
        "pipelines/deferred.ron",
    ]);
    assert_eq!(code, 1);
    assert!(
        err.contains("unknown light kind `Pointt`") && err.contains("did you mean `Point`?"),
        "{err}"
    );
}

#[test]
fn convert_and_fmt() {
    let d = scratch("convert");
    let lbp = d.join("deferred.lbp");
    let (code, _, err) = lightbench(&["convert", "pipelines/deferred.ron", "--to", "lbp", "-o", lbp.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    // The converted file is the shipped twin, comments included.
    assert_eq!(
        std::fs::read_to_string(&lbp).unwrap(),
        std::fs::read_to_string(root().join("pipelines/deferred.lbp")).unwrap()
    );
    let (code, ron_out, _) = lightbench(&["convert", lbp.to_str().unwrap(), "--to", "ron"]);
    assert_eq!(code, 0);
    assert!(
        ron_out.starts_with("// Deferred shading") && ron_out.contains("Pipeline(\n    name: \"deferred\","),
        "{ron_out}"
    );
    assert_eq!(lightbench(&["fmt", "--check", "pipelines/deferred.lbp"]).0, 0);
    // A pipeline that uses another converts too (what it prints is read back, `use` and all):
    // the twin but for the file it uses.
    let (code, gi, err) = lightbench(&["convert", "pipelines/deferred_gi.ron", "--to", "lbp"]);
    assert_eq!(code, 0, "{err}");
    let twin = std::fs::read_to_string(root().join("pipelines/deferred_gi.lbp")).unwrap();
    assert_eq!(gi, twin.replace("use \"deferred.lbp\"", "use \"deferred.ron\""));
    // A messy file is rewritten, and then it is formatted.
    let messy = d.join("messy.lbp");
    std::fs::write(
        &messy,
        "pipeline   m   // name\ntexture out:Rgba8Unorm   viewport\n\n\n\noutput out",
    )
    .unwrap();
    let (code, _, err) = lightbench(&["fmt", "--check", messy.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains(&format!("{}:1: not formatted", messy.display()))
            && err.contains("written: `pipeline   m   // name`")
            && err.contains("fmt:     `pipeline m`"),
        "{err}"
    );
    assert_eq!(lightbench(&["fmt", messy.to_str().unwrap()]).0, 0);
    assert_eq!(
        std::fs::read_to_string(&messy).unwrap(),
        "pipeline m\n\n// name\ntexture out: Rgba8Unorm viewport\n\noutput out\n"
    );
    assert_eq!(lightbench(&["fmt", "--check", messy.to_str().unwrap()]).0, 0);
    // Errors are located and exit 1; usage errors exit 2.
    std::fs::write(&messy, "pipeline m\ntexture out Rgba8Unorm viewport\noutput out\n").unwrap();
    let (code, _, err) = lightbench(&["fmt", messy.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(
        err.contains("error[lbp-syntax]: expected `:`") && err.contains("messy.lbp:2:13"),
        "{err}"
    );
    assert_eq!(lightbench(&["convert", "pipelines/deferred.ron", "--to", "yaml"]).0, 2);
    assert_eq!(lightbench(&["fmt", "pipelines/deferred.ron"]).0, 2);
}

#[test]
fn params_on_plan_and_check_are_typed_and_range_checked() {
    let (code, out, err) = lightbench(&["plan", "pipelines/deferred.ron", "--json", "--param", "exposure.ev=2.5"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("param exposure.ev = 2.5 (was 0)"), "{err}");
    let plan: serde_json::Value = serde_json::from_str(&out).unwrap();
    let ev = plan["params"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "exposure.ev")
        .unwrap();
    assert_eq!(ev["default"], serde_json::json!({"Float": 2.5}), "the Plan carries the value");
    assert_eq!(lightbench(&["check", "pipelines/", "--param", "exposure.ev=-3"]).0, 0);
    for (cmd, arg, msg) in [
        ("plan", "exposure.ev=31", "31 is above its max 30"),
        ("check", "exposure.ev=31", "31 is above its max 30"),
        (
            "check",
            "exposure.evv=1",
            "no checked pipeline has this parameter (did you mean `exposure.ev`?)",
        ),
        ("check", "shadow.pcf=maybe", "`maybe` is not `true` or `false`"),
        // Every component counted and every number a finite f32.
        ("check", "ambient.color=0.1,0.1,0.1,999", "alpha 999 is outside 0..1"),
        ("check", "ambient.color=0.1,0.1", "has 2 numbers; Color takes 3 (or 4, with alpha)"),
        ("check", "exposure.ev=1e39", "`1e39` is not a finite 32-bit number"),
        ("check", "exposure.ev=inf", "`inf` is not a finite 32-bit number"),
    ] {
        let target = if cmd == "plan" { "pipelines/deferred.ron" } else { "pipelines/" };
        let (code, _, err) = lightbench(&[cmd, target, "--param", arg]);
        assert_eq!(code, 2, "{cmd} {arg}: {err}");
        assert!(err.contains(msg), "{cmd} {arg}: {err}");
    }
}

/// The README's exit-code rule, command by command: 2 for the command line itself, 1 for an
/// input whose content cannot be used (and 0 for the controls).
#[test]
fn exit_codes_follow_one_rule() {
    let d = std::env::temp_dir().join(format!("lightbench-exit-codes-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let bad_lbp = d.join("bad.lbp");
    std::fs::write(
        &bad_lbp,
        "pipeline p\ntexture out:Rgba8Unorm viewport\nfullscreen f \"fill.wgsl\" { color out }\noutput oot\n",
    )
    .unwrap();
    let bad_scene = d.join("bad_scene.ron");
    std::fs::write(&bad_scene, "Scene(name: \"x\", builtin: \"cornell\", size: (0, 8))\n").unwrap();
    let bad_spec = d.join("bad_spec.ron");
    let spec = std::fs::read_to_string(root().join("sweeps/shadows.ron")).unwrap();
    std::fs::write(
        &bad_spec,
        spec.replace("frames: 5", "frames: 0")
            .replace("\"../", &format!("\"{}/", root().display())),
    )
    .unwrap();
    let png = d.join("o.png");
    let (o, l, sc, sp) = (
        png.to_str().unwrap(),
        bad_lbp.to_str().unwrap(),
        bad_scene.to_str().unwrap(),
        bad_spec.to_str().unwrap(),
    );
    let (refs, sweep_out) = (d.join("r"), d.join("s"));
    let (r, so) = (refs.to_str().unwrap(), sweep_out.to_str().unwrap());
    let cases: [(&[&str], i32); 18] = [
        (&["--bogus"], 2),
        (&["render", "--frames", "0", "--out", o], 2),
        (&["render", "--out", "x.jpg"], 2),
        (&["render", "--out", o, "--variant", "tonemap=filmic"], 2),
        (&["render", "--out", o, "--param", "exposure.evv=1"], 2),
        (&["render", "--out", o, "--dump", "gbuf.nrmal"], 2),
        (&["plan", "pipelines/deferred.ron", "--variant", "cube_shadw=classic"], 2),
        (&["check", "pipelines/", "--param", "nope=1"], 2),
        (&["reference", "--spp", "0", "--out", o], 2),
        (&["sweep", "sweeps/shadows.ron", "--shard", "3/2"], 2),
        (&["convert", "pipelines/deferred.ron", "--to", "yaml"], 2),
        (&["check", l], 1),
        (&["plan", l], 1),
        (&["render", "--scene", sc, "--out", o], 1),
        (&["reference", "--scene", sc, "--out", r], 1),
        (&["sweep", sp, "--out", so], 1),
        (&["check", "pipelines/deferred.ron"], 0),
        (&["plan", "pipelines/deferred.ron"], 0),
    ];
    for (args, want) in cases {
        let (code, _, err) = lightbench(args);
        assert_eq!(code, want, "{args:?}: {err}");
        if want != 0 {
            assert!(err.contains("error"), "{args:?}: an error is said: {err}");
            assert!(!err.contains("panicked"), "{args:?}: {err}");
        }
    }
    assert!(!png.exists(), "no refused command wrote its output");
    let _ = std::fs::remove_dir_all(&d);
}

/// Every command that takes `--scene` says in its help that a glTF model is a scene too, as
/// the README says and as it works (`plan` and `reference` on a bare model here).
#[test]
fn scene_help_names_gltf_models() {
    for cmd in ["render", "view", "reference", "plan", "diff"] {
        let (code, out, err) = lightbench(&[cmd, "--help"]);
        assert_eq!(code, 0, "{cmd}: {err}");
        // The option's line and, in long help, the line under it.
        let at = out.lines().position(|l| l.trim_start().starts_with("--scene")).expect("--scene");
        let text: Vec<&str> = out.lines().skip(at).take(2).collect();
        assert!(text.join(" ").contains("glTF model"), "{cmd} --help: {text:?}");
    }
    let (code, _, err) = lightbench(&["plan", "pipelines/deferred.ron", "--scene", "scenes/chair.gltf"]);
    assert_eq!(code, 0, "{err}");
    let out = scratch("gltf-reference");
    let args = [
        "reference",
        "--scene",
        "scenes/chair.gltf",
        "--size",
        "8x8",
        "--spp",
        "1",
        "--quiet",
        "--out",
    ];
    let (code, _, err) = lightbench(&[&args[..], &[out.to_str().unwrap()]].concat());
    assert_eq!(code, 0, "{err}");
}

/// The README's shader-folder rule: a pipeline in `pipelines/sub/deeper/` of an `init`ed
/// project finds the project's `shaders/`; one outside any `pipelines/` folder, with no
/// `shaders/` beside or above it, gets a shader-not-found that names the folders looked for.
#[test]
fn shaders_are_found_beside_the_enclosing_pipelines_folder() {
    let d = scratch("shader-search");
    assert_eq!(lightbench(&["init", d.to_str().unwrap()]).0, 0);
    let deeper = d.join("pipelines/sub/deeper");
    std::fs::create_dir_all(&deeper).unwrap();
    // The pipeline with its data file (the LTC table), which is read beside it.
    let table = "ltc_blinn_phong.json";
    std::fs::copy(d.join("pipelines/deferred.ron"), deeper.join("deferred.ron")).unwrap();
    std::fs::copy(d.join("pipelines").join(table), deeper.join(table)).unwrap();
    let (code, _, err) = lightbench(&["check", deeper.join("deferred.ron").to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let loose = d.join("loose/inner");
    std::fs::create_dir_all(&loose).unwrap();
    std::fs::copy(d.join("pipelines/deferred.ron"), loose.join("deferred.ron")).unwrap();
    std::fs::copy(d.join("pipelines").join(table), loose.join(table)).unwrap();
    let (code, _, err) = lightbench(&["check", loose.join("deferred.ron").to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    let looked = format!("`{}`", loose.join("shaders").display());
    assert!(
        err.contains("shader-not-found") && err.contains("no `shaders/` folder at") && err.contains(&looked),
        "{err}"
    );
    assert!(
        !err.contains(&format!("`{}`", d.join("shaders").display())),
        "no climb past loose/: {err}"
    );
    // `--shaders` names the folder outright.
    let (code, _, err) = lightbench(&[
        "check",
        loose.join("deferred.ron").to_str().unwrap(),
        "--shaders",
        d.join("shaders").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
}

/// Every flag a README synopsis shows is one the command's `--help` lists.
#[test]
fn readme_synopses_name_real_flags() {
    let readme = cli_common::manual();
    let mut checked = 0;
    let mut lines = readme.lines().peekable();
    while let Some(line) = lines.next() {
        let Some(rest) = line.strip_prefix("lightbench ") else { continue };
        let mut words: Vec<&str> = rest
            .split_whitespace()
            .take_while(|w| w.chars().all(|c| c.is_ascii_lowercase()))
            .collect();
        words.truncate(2);
        let mut text = line.to_string();
        while lines
            .peek()
            .is_some_and(|l| l.starts_with("    ") && l.trim_start().starts_with('['))
        {
            text.push_str(lines.next().unwrap());
        }
        let flags: Vec<&str> = text
            .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
            .filter(|w| w.starts_with("--") && w.len() > 2)
            .collect();
        let mut args = words.clone();
        args.push("--help");
        let (code, help, err) = lightbench(&args);
        if code != 0 {
            continue; // `lightbench sweep SPEC.ron`-like lines: the command word is not a subcommand
        }
        for f in flags {
            assert!(
                help.contains(f),
                "the manual: `{line}` shows {f}, which `lightbench {} --help` lacks:\n{help}{err}",
                words.join(" ")
            );
            checked += 1;
        }
    }
    assert!(checked > 50, "only {checked} flags checked");
}

/// Hints quote the syntax of the file they are about: an LBP pipeline reading `prev(acc)` of a
/// plain texture is told to add `history`, its RON twin `history: true`; a "declared here"
/// label over a declaration written on several lines ends at its first line.
#[test]
fn hints_speak_the_files_syntax_and_labels_end_at_their_line() {
    let lbp = "pipeline p\n\ntexture acc: Rgba16Float viewport\ntexture out: Rgba8Unorm viewport\n\nfullscreen f \"fill.wgsl\" {\n    reads prev(acc)\n    color out\n}\n\noutput out\n";
    let d = temp_project("hints", "");
    std::fs::write(d.join("p.lbp"), lbp).unwrap();
    let (code, _, err) = lightbench(&["check", d.join("p.lbp").to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("`prev(acc)` reads the previous frame") && err.contains("add `history` here"),
        "{err}"
    );
    assert!(
        !err.contains("history: true") && !err.contains("Prev("),
        "RON syntax in an LBP hint: {err}"
    );
    let ron = "Pipeline(\n    name: \"p\",\n    resources: {\n        \"acc\": Texture(\n            format: Rgba16Float,\n        ),\n        \"out\": Texture(format: Rgba8Unorm),\n    },\n    passes: [\n        Fullscreen(name: \"f\", shader: \"fill.wgsl\", reads: [Prev(\"acc\")], color: [\"out\"]),\n    ],\n    output: \"out\",\n)\n";
    std::fs::write(d.join("p.ron"), ron).unwrap();
    let (code, out, err) = lightbench(&["check", d.join("p.ron").to_str().unwrap(), "--format", "json"]);
    assert_eq!(code, 1, "{err}");
    let diag: serde_json::Value = out.lines().chain(err.lines()).find_map(|l| serde_json::from_str(l).ok()).unwrap();
    assert!(diag["message"].as_str().unwrap().contains("`Prev(\"acc\")`"), "{diag}");
    let label = diag["labels"].as_array().unwrap().iter().find(|l| l["primary"] == false).unwrap();
    assert_eq!(
        (label["line"].as_u64(), label["message"].as_str()),
        (Some(4), Some("add `history: true` here"))
    );
    let (_, _, human) = lightbench(&["check", d.join("p.ron").to_str().unwrap()]);
    assert!(
        !human.contains("format: Rgba16Float,"),
        "the label stops at its first line:\n{human}"
    );
}

/// `plan --memory` as the README quotes it: logical and physical memory of `deferred_gi` at
/// 1920×1080, and who lives in whose memory.
#[test]
fn plan_memory_shows_logical_and_aliased_memory() {
    let (code, out, err) = lightbench(&["plan", "pipelines/deferred_gi.lbp", "--memory", "--size", "1920x1080"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.starts_with("memory at 1920×1080: 192.26 MiB logical, 125.02 MiB physical with transient resources aliased (0.65×)"),
        "{out}"
    );
    let line = out.lines().find(|l| l.trim_start().starts_with("gi.indirect ")).unwrap();
    assert!(line.ends_with("shares `gbuf.emissive`"), "{line}");
    assert_eq!(out.lines().filter(|l| l.contains(" shares `")).count(), 5, "{out}");
    assert!(
        out.lines()
            .any(|l| l.trim_start().starts_with("ldr ") && l.ends_with("own (an output)")),
        "{out}"
    );
}

/// `view --help` names every action a `--script` may use (the README lists the same ones).
#[test]
fn view_help_names_every_script_action() {
    let (code, out, err) = lightbench(&["view", "--help"]);
    assert_eq!(code, 0, "{err}");
    let readme = cli_common::manual();
    for action in lightbench::viewer::state::ACTIONS.iter().chain(&["frames"]) {
        assert!(out.contains(action), "view --help omits `{action}`:\n{out}");
        assert!(readme.contains(&format!("`{action}")), "the manual omits `{action}`");
    }
}

/// The ray-traced options need ray queries: where the profile lacks `ExperimentalRayQuery`
/// (wgpu's GL backend, the WebGPU baseline) `plan` falls back to the raster option and says
/// why, and `rt!` refuses (exit 1); the Vulkan profile (lavapipe's) keeps them.
#[test]
fn ray_traced_options_fall_back_where_rays_are_missing() {
    // Each on a scene that calls for what it computes (and, for deferred_gi, for nothing that
    // needs 32-bit float targets, which GL cannot render).
    let options = [
        ("pipelines/deferred.ron", "cornell", "shadows", "rt", "maps"),
        ("pipelines/deferred_gi.lbp", "scenes/step.ron", "ao", "rtao", "gtao"),
        (
            "pipelines/deferred.lbp",
            "cornell_lamp",
            "area_lights",
            "rt_temporal",
            "ltc_shadowed",
        ),
    ];
    for (pipeline, scene, variant, option, fallback) in options {
        for profile in ["gl", "webgpu"] {
            let pick = format!("{variant}={option}");
            let args = [
                "plan",
                pipeline,
                "--scene",
                scene,
                "--profile",
                profile,
                "--variant",
                &pick,
                "--json",
            ];
            let (code, out, err) = lightbench(&args);
            assert_eq!(code, 0, "{err}");
            let plan: serde_json::Value = serde_json::from_str(&out).unwrap();
            let chosen = plan["variants"]
                .as_array()
                .unwrap()
                .iter()
                .find(|v| v["variant"] == variant)
                .unwrap();
            assert_eq!(chosen["option"], fallback, "{profile}: {chosen}");
            let why = chosen["reason"].as_str().unwrap();
            assert!(
                why.contains(&format!(
                    "`{option}` needs feature ExperimentalRayQuery, which profile `{profile}` lacks"
                )),
                "{why}"
            );
            let forced = format!("{pick}!");
            let (code, _, err) = lightbench(&["plan", pipeline, "--scene", scene, "--profile", profile, "--variant", &forced]);
            assert_eq!(code, 1, "{err}");
            assert!(err.contains("needs feature ExperimentalRayQuery"), "{err}");
        }
        let pick = format!("{variant}={option}!");
        let (code, out, err) = lightbench(&["plan", pipeline, "--scene", scene, "--profile", "vulkan", "--variant", &pick]);
        assert_eq!(code, 0, "{err}");
        assert!(out.contains(&format!("{variant} = {option}")), "{out}");
        assert!(out.contains("scene.accel"), "the Plan binds the acceleration structure: {out}");
    }
}
