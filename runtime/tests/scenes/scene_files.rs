//! Scene files as users write them: the README's example and every bundled scene render
//! from the command line; bad values are located errors from `render`, `check` and `plan`
//! alike; scenes with extreme but accepted values render without a non-finite pixel.

use crate::cli_common;
use crate::gpu_common;
use crate::mutate;

use cli_common::scratch as temp;
use gpu_common::*;
use lightbench::gpu::Executor;
use lightbench::scene;
use lightbench_compiler::diag::Diagnostics;
use lightbench_compiler::span::SourceMap;
use lightbench_compiler::Workspace;
use mutate::{mutate, mutation};
use std::path::PathBuf;
use std::process::Command;

/// `lightbench ARGS`: exit code and standard error.
fn lightbench(args: &[&str]) -> (i32, String) {
    let (code, _, err) = cli_common::lightbench(args);
    (code, err)
}

fn bundled() -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("ron"))
        .collect();
    out.sort();
    out
}

/// The README's scene block is `scenes/room.ron` without its leading comment, so rendering
/// the file renders the example as written.
#[test]
fn readme_scene_example_is_the_bundled_room() {
    cli_common::assert_readme_block_is("Scene(", "scenes/room.ron");
}

#[test]
fn bundled_scenes_render_lit_and_finite_from_the_command_line() {
    let d = temp("bundled");
    let files = bundled();
    assert!(files.len() >= 2, "{files:?}");
    for f in files {
        let rel = f.strip_prefix(root()).unwrap().to_str().unwrap().to_string();
        let out = d.join(format!("{}.exr", f.file_stem().unwrap().to_str().unwrap()));
        let (code, err) = lightbench(&[
            "render",
            "--scene",
            &rel,
            "--out",
            out.to_str().unwrap(),
            "--dump",
            "hdr",
            "--dump-dir",
            d.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{rel}: {err}");
        let img = image::open(&out).unwrap().to_rgba32f();
        assert!(img.pixels().all(|p| p.0.iter().all(|v| v.is_finite())), "{rel}: non-finite output");
        let mean: f32 = img.pixels().map(|p| (p.0[0] + p.0[1] + p.0[2]) / 3.0).sum::<f32>() / (img.width() * img.height()) as f32;
        assert!(mean > 0.05, "{rel}: the scene's lights light it (mean {mean})");
        let hdr = image::open(d.join("hdr.exr")).unwrap().to_rgba32f();
        assert!(hdr.pixels().all(|p| p.0.iter().all(|v| v.is_finite())), "{rel}: non-finite HDR");
        for cmd in [
            vec!["check", "pipelines/deferred.ron", "--scene", &rel],
            vec!["plan", "pipelines/deferred.ron", "--scene", &rel],
        ] {
            let (code, err) = lightbench(&cmd);
            assert_eq!(code, 0, "{cmd:?}: {err}");
        }
    }
    // sun_only switches its point light off: the cube shadow passes are culled for it.
    let out = Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .args(["plan", "pipelines/deferred.ron", "--scene", "scenes/sun_only.ron"])
        .current_dir(root())
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("lights: 1 Directional") && !text.contains("Point"), "{text}");
}

#[test]
fn scene_errors_are_located_in_every_command() {
    let d = temp("bad");
    let bad = d.join("bad.ron");
    std::fs::write(
        &bad,
        "Scene(\n    builtin: \"cornell\",\n    lights: [Spot(direction: (0.0, 0.0, 0.0))],\n)\n",
    )
    .unwrap();
    let at = format!("{}:3:19", bad.display());
    let p = bad.to_str().unwrap();
    let out = d.join("x.png");
    for cmd in [
        vec!["render", "--scene", p, "--out", out.to_str().unwrap()],
        vec!["check", "pipelines/deferred.ron", "--scene", p],
        vec!["plan", "pipelines/deferred.ron", "--scene", p],
    ] {
        let (code, err) = lightbench(&cmd);
        assert_eq!(code, 1, "{cmd:?}: {err}");
        assert!(
            err.contains("error[value-out-of-range]: `direction` of light 1 (spot) is the zero vector"),
            "{cmd:?}: {err}"
        );
        assert!(err.contains(&at), "{cmd:?} should point at {at}: {err}");
    }
    assert!(!out.exists(), "no image for a bad scene");
    // `check DIR` checks scene files among pipelines as scenes.
    let (code, err) = lightbench(&["check", d.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains(&at) && err.contains("checked 0 pipeline file(s) and 1 scene file(s)"),
        "{err}"
    );
    let (code, err) = lightbench(&["check", "scenes/", "pipelines/"]);
    assert_eq!(code, 0, "{err}");
    // Every scene file below scenes/ (the hard-case suite included) is checked as a scene.
    let scenes = lightbench_compiler::pipeline_files(&root().join("scenes")).unwrap().len();
    let pipelines = lightbench_compiler::pipeline_files(&root().join("pipelines")).unwrap().len();
    assert!(
        err.contains(&format!("checked {pipelines} pipeline file(s) and {scenes} scene file(s)")),
        "{err}"
    );
    // A model that cannot be loaded is reported at its path, by check as by render.
    let missing = d.join("missing.ron");
    std::fs::write(&missing, "Scene(\n    models: [(path: \"nope.gltf\")],\n)\n").unwrap();
    let (code, err) = lightbench(&["check", "pipelines/deferred.ron", "--scene", missing.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("error[model-load]: cannot load model `nope.gltf`"), "{err}");
    assert!(err.contains(&format!("{}:2:21", missing.display())), "{err}");
    // Built-in names are scenes wherever a scene is accepted.
    for cmd in [
        ["check", "pipelines/deferred.ron", "--scene", "colonnade"],
        ["plan", "pipelines/deferred.ron", "--scene", "many_lights"],
    ] {
        let (code, err) = lightbench(&cmd);
        assert_eq!(code, 0, "{cmd:?}: {err}");
    }
    let (code, err) = lightbench(&["check", "pipelines/deferred.ron", "--scene", "cornel"]);
    assert_eq!(code, 1);
    assert!(err.contains("did you mean `cornell`?"), "{err}");
}

/// Each number of each bundled scene replaced by other values: what the front end rejects
/// is rejected with a location; what it accepts with a huge or tiny value renders (two
/// frames, so animations move) without a NaN or Inf in the output or the HDR buffer.
#[test]
fn extreme_accepted_values_render_finite() {
    const VALUES: [&str; 5] = ["1e30", "1e-30", "0", "-3.5", "NaN"];
    const RENDERED: [&str; 4] = ["1e30", "1e-30", "0", "-3.5"];
    let g = gpu();
    let ws = Workspace::disk();
    let (mut rendered, mut rejected) = (0, 0);
    let mut executor: Option<Executor> = None;
    for file in bundled() {
        let text = std::fs::read_to_string(&file).unwrap();
        let mut seen = std::collections::BTreeSet::new();
        for (start, end) in numbers(&text) {
            for v in VALUES {
                let mutated = format!("{}{v}{}", &text[..start], &text[end..]);
                let (mut sources, mut diags) = (SourceMap::new(), Diagnostics::default());
                let Some(mut desc) = lightbench_compiler::scene::load_text(&file, mutated, &mut sources, &mut diags) else {
                    assert!(
                        diags.errors().all(|d| d.location(&sources).is_some()),
                        "unlocated: {:?}",
                        diags.list
                    );
                    rejected += 1;
                    continue;
                };
                desc.size = (32, 32);
                if !RENDERED.contains(&v) || !seen.insert(format!("{desc:?}")) {
                    continue;
                }
                let scene = scene::instantiate(&desc, &mut diags).expect("models load");
                render_finite(
                    &g,
                    &ws,
                    &mut executor,
                    &scene,
                    &format!("{} with `{v}` at byte {start}", file.display()),
                );
                rendered += 1;
            }
        }
    }
    eprintln!("rendered {rendered} accepted mutants, {rejected} rejected");
    assert!(
        rendered > 20 && rejected > 20,
        "both outcomes exercised: {rendered} rendered, {rejected} rejected"
    );
}

/// Render two frames of `scene` (32×32 or as set) through one executor shared by the calls —
/// a scene swap keeps its pipelines, as a viewer's would — and assert that neither the
/// output nor the HDR buffer holds NaN or Inf. `what` names the case in failures.
fn render_finite(g: &lightbench::gpu::Gpu, ws: &Workspace, executor: &mut Option<Executor>, scene: &lightbench::scene::Scene, what: &str) {
    let (exe, _) = lightbench::render::compile_in(ws, g, &deferred(), None, scene, &[]).unwrap_or_else(|e| panic!("{e}\n{what}"));
    let ex = match executor {
        None => executor.insert(Executor::new(g, &exe, scene).unwrap()),
        Some(ex) => {
            ex.replace_scene(g, &exe, scene).unwrap_or_else(|e| panic!("{e}\n{what}"));
            ex
        }
    };
    for f in 0..2 {
        let inputs = ex.inputs(f as f32 / 60.0);
        ex.render_frame(g, &inputs).unwrap_or_else(|e| panic!("{e}\n{what}"));
    }
    for res in ["hdr", "ldr"] {
        assert_eq!(ex.read_texture(g, res, 0, 0).unwrap().non_finite(), 0, "{res} has NaN/Inf: {what}");
    }
}

/// Byte ranges of the numbers in a scene file (outside comments).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let mut out = vec![];
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split("//").next().unwrap_or("");
        let b = code.as_bytes();
        let mut i = 0;
        while i < b.len() {
            let starts = (b[i].is_ascii_digit() || b[i] == b'-') && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'));
            if starts {
                let s = i;
                i += 1;
                while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.' || b[i] == b'e') {
                    i += 1;
                }
                out.push((offset + s, offset + i));
            } else {
                i += 1;
            }
        }
        offset += line.len();
    }
    out
}

/// Mutations of the bundled scene files (byte flips, token deletions and duplications,
/// swapped lines, numbers replaced by NaN/Inf/huge/negative values), 3,000 cases from a fixed
/// seed: never a panic, every rejection located (syntax, values, models), and every
/// accepted scene renders two frames without a non-finite pixel in the output or HDR buffer.
#[test]
fn mutated_scene_files_are_rejected_with_a_location_or_render_finite() {
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    let files: Vec<(PathBuf, String)> = bundled()
        .into_iter()
        .map(|p| (p.clone(), std::fs::read_to_string(&p).unwrap()))
        .collect();
    let config = Config {
        cases: 3000,
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha));
    let accepted = std::cell::RefCell::new(std::collections::BTreeMap::new());
    let strategy = (0..files.len(), proptest::collection::vec(mutation(), 1..4));
    runner
        .run(&strategy, |(which, ms)| {
            let (path, original) = &files[which];
            let mut text = original.clone();
            for m in &ms {
                text = String::from_utf8_lossy(&mutate(&text, m)).into_owned();
            }
            let (mut sources, mut diags) = (SourceMap::new(), Diagnostics::default());
            let scene = lightbench_compiler::scene::load_text(path, text.clone(), &mut sources, &mut diags)
                .and_then(|d| scene::instantiate(&d, &mut diags).map(|s| (d, s)));
            for d in diags.errors() {
                proptest::prop_assert!(d.location(&sources).is_some(), "unlocated: {} in\n{text}", d.message);
            }
            match scene {
                None => proptest::prop_assert!(diags.has_errors()),
                Some((desc, scene)) => {
                    accepted.borrow_mut().entry(format!("{desc:?}")).or_insert((text, scene));
                }
            }
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    let accepted = accepted.into_inner();
    eprintln!("{} distinct accepted mutants", accepted.len());
    assert!(
        accepted.len() > 20,
        "mutations that keep a scene valid are exercised: {}",
        accepted.len()
    );
    let (g, ws) = (gpu(), Workspace::disk());
    let mut executor: Option<Executor> = None;
    for (text, mut scene) in accepted.into_values() {
        scene.size = (32, 32);
        render_finite(&g, &ws, &mut executor, &scene, &text);
    }
}
