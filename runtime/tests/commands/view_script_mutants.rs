//! The mutation run of view scripts: 1,000 mutants of a script using every action go
//! through `view --script` as the window runs it — the syntax of every line checked first,
//! then each step against one viewer on lavapipe (the window's own `script::run_line` and
//! frames; only the presentation is left out). Never a panic or a hang, every rejection said
//! at `FILE:LINE`, and the image stays finite.

use crate::cli_common;
use crate::gpu_common;
use crate::mutate;

use cli_common::{root, scratch};
use gpu_common::gpu;
use lightbench::viewer::script::{self, Step};
use lightbench::viewer::state::Viewer;
use lightbench_compiler::Workspace;
use mutate::{mutate, mutation};
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

const SCRIPT: &str = "# every action once
frames 1
next-view
prev-view
view hdr
next-slice
prev-slice
view output
light 1
toggle-light
toggle-light
rotate-light 30 -10
move 0.1 0.2 -0.3
look 15 5
param exposure.ev=1.5
param ambient.color=0.1,0.1,0.12
variant cube_shadow=instanced
add-light Spot
effect Bloom=true
param bloom_up.strength=0.5
frames 2
remove-light
screenshot shot.png
frames 1
";

#[test]
fn mutated_view_scripts_are_rejected_with_a_location_or_run() {
    let dir = scratch("view-mutants");
    // Screenshots a mutant names land in the scratch folder.
    std::env::set_current_dir(&dir).unwrap();
    let g = gpu();
    let mut scene = lightbench::scene::builtin::cornell();
    scene.size = (32, 32); // the bloom chain needs 16×16 at half size
    let pipeline = root().join("pipelines/deferred.ron");
    let lights = scene.lights.clone();
    let mut viewer = Viewer::new(&g, (Workspace::disk(), &pipeline, None), scene, &[]).unwrap();
    // The script as written runs to the end.
    for step in script::parse(SCRIPT, "s.txt").unwrap() {
        match step {
            Step::Frames(n) => (0..n).try_for_each(|_| viewer.frame(&g)),
            Step::Line(line, at) => script::run_line(&mut viewer, &g, &line, &at),
        }
        .unwrap_or_else(|e| panic!("{e}"));
    }
    let config = Config {
        cases: 1000,
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha));
    let counts = std::cell::Cell::new((0, 0, 0)); // (ran to the end, syntax, run-time)
    let viewer = std::cell::RefCell::new(&mut viewer);
    runner
        .run(&proptest::collection::vec(mutation(), 1..4), |ms| {
            let mut text = SCRIPT.to_string();
            for m in &ms {
                text = String::from_utf8_lossy(&mutate(&text, m)).into_owned();
            }
            let (mut ran, syntax, mut late) = counts.get();
            let steps = match script::parse(&text, "s.txt") {
                Ok(s) => s,
                Err(e) => {
                    let msg = e.to_string();
                    proptest::prop_assert!(msg.starts_with("s.txt:"), "unlocated: {msg}\n{text}");
                    counts.set((ran, syntax + 1, late));
                    return Ok(());
                }
            };
            let mut v = viewer.borrow_mut();
            reset_lights(&mut v, &g, &lights);
            let mut failed = false;
            for step in steps {
                let result = match step {
                    // Frames as asked, at most 2 a step (a script asking for a million renders
                    // a million, which is not a hang).
                    Step::Frames(n) => (0..n.min(2)).try_for_each(|_| v.frame(&g)),
                    Step::Line(line, at) => script::run_line(&mut v, &g, &line, &at),
                };
                if let Err(e) = result {
                    let msg = e.to_string();
                    proptest::prop_assert!(msg.contains("s.txt:"), "unlocated: {msg}\n{text}");

                    failed = true;
                    break;
                }
            }
            v.frame(&g).unwrap();
            let hdr = v.ex.read_texture(&g, "hdr", 0, 0).unwrap();
            proptest::prop_assert_eq!(hdr.non_finite(), 0, "non-finite HDR after\n{}", text);
            if failed {
                late += 1;
            } else {
                ran += 1;
            }
            counts.set((ran, syntax, late));
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    let (ran, syntax, late) = counts.get();
    eprintln!("{ran} scripts ran to the end, {syntax} rejected before running, {late} stopped at a line");
    assert!(
        ran > 100 && syntax > 100 && late > 20,
        "every outcome exercised: {ran} {syntax} {late}"
    );
}

/// Each mutant starts from the scene's lights (a mutant that removed one without adding one
/// would leave every later script without a light 1), through the viewer's own actions.
fn reset_lights(v: &mut Viewer, g: &lightbench::gpu::Gpu, lights: &[lightbench::scene::Light]) {
    use lightbench::viewer::state::Action;
    while v.scene.lights.len() > lights.len() {
        v.apply(g, Action::SelectLight(v.scene.lights.len() - 1)).unwrap();
        v.apply(g, Action::RemoveLight).unwrap();
    }
    while v.scene.lights.len() < lights.len() {
        v.apply(g, Action::AddLight(lights[v.scene.lights.len()].kind)).unwrap();
    }
    for (i, l) in lights.iter().enumerate() {
        v.apply(g, Action::SetLight(i, Box::new(l.clone()))).unwrap();
    }
}
