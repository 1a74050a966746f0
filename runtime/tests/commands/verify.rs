//! `lightbench verify` as a user runs it: every bundled pipeline × every variant option ×
//! every hard-case scene stays finite, and a deliberate NaN is traced to its pass and light.

use crate::cli_common;

use cli_common::{lightbench, root, scratch};

/// `verify --format json` output as its lines, after checking that no configuration had a
/// problem and the run exited 0.
fn clean_run((code, out, err): (i32, &str, &str)) -> Vec<serde_json::Value> {
    let lines: Vec<serde_json::Value> = out.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    let problems: Vec<&serde_json::Value> = lines
        .iter()
        .filter(|l| !l["problem"].is_null() && l.get("summary").is_none())
        .collect();
    assert!(problems.is_empty(), "{problems:#?}\n{err}");
    assert_eq!(code, 0, "{err}");
    lines
}

/// Every bundled pipeline (`pipelines/`) × every variant option × every hard-case scene
/// (`scenes/hard/`), 2 frames (history read back once) at 24×24 at most: no value of any resource is NaN or Inf.
/// Pipelines and scenes added later are picked up by the directories.
#[test]
fn bundled_pipelines_stay_finite_on_every_hard_case() {
    let hard = root().join("scenes/hard");
    let scenes = std::fs::read_dir(&hard)
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension().is_some_and(|x| x == "ron"))
        .count();
    assert!(scenes >= 20, "the hard-case suite has {scenes} scenes");
    for f in std::fs::read_dir(&hard).unwrap() {
        let p = f.unwrap().path();
        if p.extension().is_some_and(|x| x == "ron") {
            let text = std::fs::read_to_string(&p).unwrap();
            assert!(
                text.starts_with("// Hazard: "),
                "{} starts with a comment naming its hazard",
                p.display()
            );
        }
    }
    // Each bundled pipeline once: its `.lbp` twin is the same IR (the LBP tests hold that).
    let mut pipelines: Vec<String> = std::fs::read_dir(root().join("pipelines"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .map(|p| p.display().to_string())
        .collect();
    pipelines.sort();
    assert!(pipelines.len() >= 2, "{pipelines:?}");
    let mut args: Vec<&str> = vec!["verify"];
    args.extend(pipelines.iter().map(String::as_str));
    let (code, out, err) = lightbench(
        &[
            &args[..],
            &[
                "--scenes",
                hard.to_str().unwrap(),
                "--size",
                "24x24",
                "--frames",
                "2",
                "--format",
                "json",
            ],
        ]
        .concat(),
    );
    let lines = clean_run((code, &out, &err));
    let summary = &lines.last().unwrap()["summary"];
    // Each pipeline with the defaults and the options that do not fall back to them.
    assert!(
        summary["configurations"].as_u64().unwrap() >= 3 * (pipelines.len() * scenes) as u64,
        "{summary}"
    );
}

/// Blended surfaces: both bundled pipelines × every variant option (every transparency and
/// anti-aliasing option among them) on `scenes/panes_inside.ron` — the camera among panes that
/// pass through each other, several layers per pixel — for 2 frames: every value of every
/// resource (fragment lists, peeled layers, TAA's history) finite and within its range.
#[test]
fn every_option_stays_finite_among_interpenetrating_panes() {
    let pipelines = ["pipelines/deferred.ron", "pipelines/deferred_gi.ron"].map(|p| root().join(p).display().to_string());
    let scene = root().join("scenes/panes_inside.ron");
    let (code, out, err) = lightbench(&[
        "verify",
        &pipelines[0],
        &pipelines[1],
        "--scenes",
        scene.to_str().unwrap(),
        "--size",
        "32x32",
        "--frames",
        "2",
        "--format",
        "json",
    ]);
    let lines = clean_run((code, &out, &err));
    let variants: Vec<String> = lines
        .iter()
        .filter_map(|l| l["variants"].as_array())
        .flatten()
        .filter_map(|v| v.as_str().map(String::from))
        .collect();
    for option in ["transparency=fragment_lists", "transparency=depth_peeling", "aa=taa", "aa=fxaa"] {
        assert!(variants.iter().any(|v| v == option), "{option} not verified: {variants:?}");
    }
}

const LIT: &str = "#include \"lib/frame.wgsl\"

struct Params { poison: u32 };
@group(2) @binding(0) var<uniform> params: Params;

// Each light's share; with `poison` on, light 1's is sqrt(-1) = NaN.
@fragment
fn fs_main() -> @location(0) vec4<f32> {
    let bad = params.poison != 0u && instance.light == 1u;
    let v = select(0.25, sqrt(-f32(params.poison)), bad);
    return vec4<f32>(v, f32(instance.light), 0.0, 0.0);
}
";

const SUM: &str = "@group(2) @binding(0) var shade: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(shade, vec2<i32>(pos.xy), 0);
}
";

const CLEAR: &str = "@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return vec4<f32>(0.0);
}
";

const POISON: &str = "pipeline poison
param poison: Bool = false \"Make light 1's share NaN\"

texture shade: Rgba16Float viewport per_light(Point)
texture out: Rgba16Float viewport

fullscreen clear \"clear.wgsl\" {
    color out
}

fullscreen lit \"lit.wgsl\" {
    per_light(Point)
    color shade
    params poison
}

fullscreen sum \"sum.wgsl\" {
    per_light(Point)
    reads shade
    color out load blend Add
}

output out
";

const TWO_LIGHTS: &str = "Scene(
    name: \"two_lights\",
    size: (16, 16),
    lights: [Point(position: (0.0, 1.0, 0.0)), Point(position: (1.0, 1.0, 0.0))],
)
";

/// A NaN made in a middle pass for the second light only: the pass, the light instance and
/// the pixel are named, exit 1; with the parameter off, exit 0.
#[test]
fn a_deliberate_nan_is_traced_to_its_pass_and_light() {
    let d = scratch("poison");
    std::fs::create_dir_all(d.join("shaders/lib")).unwrap();
    std::fs::copy(root().join("shaders/lib/frame.wgsl"), d.join("shaders/lib/frame.wgsl")).unwrap();
    for (f, t) in [
        ("shaders/lit.wgsl", LIT),
        ("shaders/sum.wgsl", SUM),
        ("shaders/clear.wgsl", CLEAR),
        ("poison.lbp", POISON),
        ("two.ron", TWO_LIGHTS),
    ] {
        std::fs::write(d.join(f), t).unwrap();
    }
    let (p, s, sh) = (d.join("poison.lbp"), d.join("two.ron"), d.join("shaders"));
    let base = [
        "verify",
        p.to_str().unwrap(),
        "--scenes",
        s.to_str().unwrap(),
        "--shaders",
        sh.to_str().unwrap(),
    ];
    let (code, out, err) = lightbench(&base);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("verified 1 configuration(s): 0 with problems"), "{out}");
    let (code, out, err) = lightbench(&[&base[..], &["--param", "poison=true"]].concat());
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        out.contains("first produced by pass `lit` in frame 1: `shade` (light instance 1) = NaN at pixel (0, 0) channel 0"),
        "{out}"
    );
    assert!(out.contains("non-finite `out`: NaN"), "the NaN spread to the output: {out}");
    let (code, out, _) = lightbench(&[&base[..], &["--param", "poison=true", "--format", "json"]].concat());
    assert_eq!(code, 1);
    let first: serde_json::Value = serde_json::from_str(out.lines().next().unwrap()).unwrap();
    let o = &first["problem"]["non_finite"]["first"];
    assert_eq!(o["pass"], "lit");
    assert_eq!(o["output"]["part"]["instance"], 1);
    assert_eq!(o["output"]["value"], "NaN");

    // A declared range: `shade` holds the light index in green, so light 1's share is
    // outside `valid 0..0.5`.
    std::fs::write(
        &p,
        POISON.replace(
            "texture shade: Rgba16Float viewport per_light(Point)",
            "texture shade: Rgba16Float viewport per_light(Point) valid 0..0.5",
        ),
    )
    .unwrap();
    let (code, out, err) = lightbench(&base);
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        out.contains("out of range 0..0.5 `shade` (light instance 1): 1 at pixel (0, 0) channel 1"),
        "{out}"
    );
    assert!(out.contains("first produced by pass `lit` in frame 1"), "{out}");
}

/// Bad arguments are refused before any GPU work (exit 2); a scene or parameter that does
/// not fit a configuration is a located failure of that configuration (exit 1).
#[test]
fn bad_verify_arguments_are_refused() {
    let deferred = root().join("pipelines/deferred.ron");
    let p = deferred.to_str().unwrap();
    for (args, msg) in [
        (vec!["verify", p, "--frames", "0"], "--frames must be at least 1"),
        (vec!["verify", p, "--size", "0x3"], "out of range"),
        (vec!["verify", "no/such/dir"], "no/such/dir"),
        (
            vec!["verify", p, "--param", "exposure.ev"],
            "invalid --param `exposure.ev`: expected NAME=VALUE",
        ),
        (
            vec!["verify", p, "--variants", "all", "--vary", "cube_shadows"],
            "--vary `cube_shadows`: no checked pipeline has this variant (did you mean `cube_shadow`?)",
        ),
    ] {
        let (code, _, err) = lightbench(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(msg), "{args:?}: {err}");
    }
    let (code, out, _) = lightbench(&["verify", p, "--scenes", "cornell", "--param", "exposure.evv=1"]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("failed: --param `exposure.evv`: the pipeline has no such parameter (did you mean `exposure.ev`?)"),
        "{out}"
    );
    let (code, out, _) = lightbench(&["verify", p, "--scenes", "no_such_scene.ron"]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("no_such_scene.ron") && out.contains("failed:"), "{out}");
    // JSON lists failed configurations as lines too, then the summary counting them.
    let (code, out, _) = lightbench(&["verify", p, "--scenes", "no_such_scene.ron", "--format", "json"]);
    assert_eq!(code, 1, "{out}");
    let lines: Vec<serde_json::Value> = out.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    assert_eq!(lines.len(), 2, "{out}");
    assert!(
        lines[0]["problem"]["failed"].as_str().unwrap().contains("no_such_scene.ron"),
        "{out}"
    );
    assert_eq!(lines[1]["summary"]["problems"], 1, "{out}");
}
