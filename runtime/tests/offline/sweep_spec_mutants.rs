//! The mutation run of the bundled sweep specs: 2,000 mutants (byte flips, token
//! deletions and duplications, swapped lines, numbers replaced by NaN, infinity, values beyond
//! f32 and negatives) go through what `lightbench sweep` does before it renders anything —
//! load, list the points, load the first scene, plan the pipeline, check every point's
//! settings. Never a panic or a hang, and every rejection located in a file.

use crate::cli_common;
use crate::mutate;

use cli_common::{root, scratch};
use lightbench::sweep::{self, spec};
use lightbench_compiler::profile::Profile;
use lightbench_compiler::Workspace;
use mutate::{mutate, mutation};
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::sync::mpsc;
use std::time::Duration;

/// `file:LINE:COL` somewhere in the message (the spec's place, or a pipeline diagnostic's).
fn located(msg: &str) -> bool {
    msg.split(':').collect::<Vec<_>>().windows(3).any(|w| {
        let n = |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_digit());
        n(w[1]) && n(w[2].split_whitespace().next().unwrap_or(""))
    })
}

/// What `sweep` checks before rendering, for one spec file: `Ok` or the error's text.
fn up_front(ws: &Workspace, path: &std::path::Path) -> Result<usize, String> {
    let l = spec::load(path).map_err(|e| e.to_string())?;
    let points = spec::points(&l);
    let Some(first) = points.first() else { return Ok(0) };
    let scene = sweep::load_scene(&l, first).map_err(|e| e.to_string())?;
    sweep::check_up_front(ws, &Profile::vulkan(), &l, &scene, &points).map_err(|e| e.to_string())?;
    Ok(points.len())
}

#[test]
fn mutated_sweep_specs_are_rejected_with_a_location_or_checked() {
    let dir = scratch("spec-mutants");
    let specs: Vec<String> = std::fs::read_dir(root().join("sweeps"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .map(|p| {
            std::fs::read_to_string(p)
                .unwrap()
                .replace("\"../", &format!("\"{}/", root().display()))
        })
        .collect();
    assert!(specs.len() >= 3);
    // The checks run on a worker; a mutant that takes over a minute is a hang.
    let (to_worker, jobs) = mpsc::channel::<Option<String>>();
    let (to_main, results) = mpsc::channel::<Result<usize, String>>();
    let worker_dir = dir.clone();
    let worker = std::thread::spawn(move || {
        let ws = Workspace::disk();
        let path = worker_dir.join("mutant.ron");
        while let Ok(Some(text)) = jobs.recv() {
            std::fs::write(&path, &text).unwrap();
            let _ = to_main.send(up_front(&ws, &path));
        }
    });
    let config = Config {
        cases: 2000,
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha));
    let (accepted, rejected) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
    let strategy = (0..specs.len(), proptest::collection::vec(mutation(), 1..4));
    runner
        .run(&strategy, |(which, ms)| {
            let mut text = specs[which].clone();
            for m in &ms {
                text = String::from_utf8_lossy(&mutate(&text, m)).into_owned();
            }
            to_worker.send(Some(text.clone())).unwrap();
            match results.recv_timeout(Duration::from_secs(60)) {
                Ok(Ok(_)) => accepted.set(accepted.get() + 1),
                Ok(Err(msg)) => {
                    proptest::prop_assert!(located(&msg), "unlocated: {msg}\n{text}");
                    rejected.set(rejected.get() + 1);
                }
                Err(_) => panic!("a hang or a panic in the checks of:\n{text}"),
            }
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    to_worker.send(None).unwrap();
    worker.join().unwrap();
    eprintln!("{} mutants checked, {} rejected", accepted.get(), rejected.get());
    assert!(accepted.get() > 50 && rejected.get() > 500, "both outcomes exercised");
}

/// The README's per-pass value in a sweep spec (`"bloom_up.strength"`): accepted as a setting
/// of a spec whose scenes call for bloom; a value that is not a number is an error at it.
#[test]
fn sweep_specs_set_per_pass_values() {
    let dir = scratch("spec-pass-values");
    let spec = |values: &str| {
        format!(
            "Sweep(\n    pipeline: {:?},\n    scenes: [\"cornell\"],\n    sizes: [(32, 32)],\n    grid: {{\"bloom_up.strength\": [{values}]}},\n    effect: [\"bloom_up\"],\n    compare: \"hdr\",\n    reference: (term: direct, spp: 1),\n)\n",
            root().join("pipelines/deferred.ron").display().to_string()
        )
    };
    let ws = Workspace::disk();
    let path = dir.join("pass_values.ron");
    let run = |text: &str| {
        std::fs::write(&path, text).unwrap();
        let mut l = spec::load(&path).map_err(|e| e.to_string())?;
        l.add_effects(&[lightbench_compiler::ir::Effect::Bloom]);
        let points = spec::points(&l);
        let scene = sweep::load_scene(&l, &points[0]).map_err(|e| e.to_string())?;
        sweep::check_up_front(&ws, &Profile::vulkan(), &l, &scene, &points).map_err(|e| e.to_string())
    };
    run(&spec("0.5, 1.0")).unwrap_or_else(|e| panic!("{e}"));
    let err = run(&spec("0.5, \"much\"")).unwrap_err();
    assert!(err.contains("pass_values.ron:5:") && err.contains("bloom_up.strength"), "{err}");
}
