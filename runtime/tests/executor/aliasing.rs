//! Transient memory aliasing (`PlanResource::shares`, `Executor::set_aliasing`): every
//! bundled pipeline on every bundled scene renders the same image with it as without it, in
//! less memory.

use crate::gpu_common;

use gpu_common::*;
use lightbench::gpu::Executor;
use lightbench::io::rmse;
use lightbench::scene::{builtin, Scene};

/// The built-in scenes and the scene files in `scenes/`, small.
fn scenes() -> Vec<(String, Scene)> {
    let mut out: Vec<(String, Scene)> = builtin::NAMES
        .iter()
        .map(|n| (n.to_string(), lightbench::scene::load(n).unwrap()))
        .collect();
    let mut files: Vec<_> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    for f in files.into_iter().filter(|f| f.extension().is_some_and(|e| e == "ron")) {
        out.push((f.display().to_string(), lightbench::scene::load(f.to_str().unwrap()).unwrap()));
    }
    // Where most transients meet: every effect called for.
    for n in ["cornell", "colonnade"] {
        let mut s = lightbench::scene::load(n).unwrap();
        s.effects.extend(lightbench_compiler::ir::Effect::ALL);
        out.push((format!("{n} with every effect"), s));
    }
    for (_, s) in &mut out {
        s.size = (40, 40);
    }
    out
}

/// Two frames (history and adaptation settle alike on both sides); the output image.
fn frames(g: &lightbench::gpu::Gpu, ex: &mut Executor) -> lightbench::io::Image {
    for f in 0..2 {
        let inputs = ex.inputs(f as f32 / 60.0);
        ex.render_frame(g, &inputs).unwrap_or_else(|e| panic!("{e}"));
    }
    output(g, ex)
}

#[test]
fn every_bundled_pipeline_and_scene_renders_the_same_with_aliased_memory() {
    let g = gpu();
    let mut shared_any = false;
    for pipeline in ["deferred.lbp", "deferred_gi.lbp"] {
        let path = root().join("pipelines").join(pipeline);
        for (name, s) in scenes() {
            let (exe, _) = lightbench::render::compile(&g, &path, None, &s, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
            let mut ex = Executor::new(&g, &exe, &s).unwrap();
            ex.set_reuse(false);
            let own = frames(&g, &mut ex);
            let logical = ex.resource_bytes();
            ex.set_aliasing(&g, &exe, true).unwrap();
            let aliased = frames(&g, &mut ex);
            let physical = ex.resource_bytes();
            let e = rmse(&own, &aliased).unwrap();
            eprintln!("{pipeline} on {name}: RMSE {e:e}, memory {physical} of {logical} bytes");
            assert!(e <= 1e-6, "{pipeline} on {name}: aliasing changed the image (RMSE {e})");
            assert_eq!(physical, exe.plan.physical_bytes, "{pipeline} on {name}");
            assert!(physical <= logical);
            shared_any |= physical < logical;
            // And back: each resource its own memory again, the same image.
            ex.set_aliasing(&g, &exe, false).unwrap();
            assert_eq!(ex.resource_bytes(), logical);
            assert!(rmse(&own, &frames(&g, &mut ex)).unwrap() <= 1e-6);
        }
    }
    assert!(shared_any, "transient resources shared memory somewhere");
}
