//! The viewer's light edits (drag, rotate, the panel's fields): a change the running Plan can
//! take is a frame input — no new Plan, no scene upload — so the next frame re-runs only what
//! depends on the light, and it shows what a viewer opened on the edited scene shows. Adding
//! or removing a light, or calling for an effect, takes a new Plan but keeps the scene on the
//! GPU.

use crate::gpu_common;

use gpu_common::*;
use lightbench::io::rmse;
use lightbench::viewer::state::{Action, Viewer};
use lightbench_compiler::ir::ParamValue;
use lightbench_compiler::Workspace;

fn viewer(g: &lightbench::gpu::Gpu, scene: lightbench::scene::Scene) -> Viewer {
    let pipeline = root().join("pipelines/deferred.lbp");
    let mut v = Viewer::new(g, (Workspace::disk(), &pipeline, None), scene, &[]).unwrap_or_else(|e| panic!("{e}"));
    // A fixed exposure: two viewers with different histories expose alike.
    v.apply(g, Action::Param("exposure.automatic".into(), ParamValue::Bool(false)))
        .unwrap();
    v
}

#[test]
fn moving_a_light_reruns_only_what_depends_on_it() {
    let g = gpu();
    let mut scene = lightbench::scene::builtin::cornell();
    scene.size = (48, 48);
    let mut v = viewer(&g, scene.clone());
    for _ in 0..2 {
        v.frame(&g).unwrap();
    }
    let before = output(&g, &v.ex);
    let mut moved = v.scene.lights[0].clone();
    moved.position += glam::Vec3::new(0.3, -0.2, 0.1);
    v.apply(&g, Action::SetLight(0, Box::new(moved.clone()))).unwrap();
    v.frame(&g).unwrap();
    let ran = |pass: &str| {
        let t =
            v.ex.last_timings
                .iter()
                .find(|t| t.pass == pass)
                .unwrap_or_else(|| panic!("no pass {pass}"));
        !t.reused
    };
    assert!(!ran("gbuffer"), "the G-buffer does not depend on the light: kept");
    assert!(ran("shadow_cube_classic"), "the moved light's shadow map is drawn again");
    let after = output(&g, &v.ex);
    assert!(rmse(&before, &after).unwrap() > 1e-3, "the light moved");
    // What a viewer opened on the scene with the light already there shows.
    scene.lights[0] = moved;
    let mut fresh = viewer(&g, scene);
    fresh.frame(&g).unwrap();
    let e = rmse(&after, &output(&g, &fresh.ex)).unwrap();
    assert!(e <= 1e-6, "edited vs opened with the edit: RMSE {e}");
    // Turning a light off changes the Plan's lights: a new Plan, and still a right image.
    v.apply(&g, Action::ToggleLight).unwrap();
    v.frame(&g).unwrap();
    assert!(
        v.ex.plan().passes.iter().all(|p| p.name != "shadow_cube_classic"),
        "no light casts: culled"
    );
}

/// Adding a light, calling for an effect and removing the light again: each a new Plan, the
/// scene's geometry and textures uploaded once in all (`Executor::scene_uploads`), and each
/// frame what a viewer opened on the edited scene shows.
#[test]
fn adding_a_light_or_an_effect_keeps_the_scene_on_the_gpu() {
    use lightbench_compiler::ir::{Effect, LightKind};
    let g = gpu();
    let mut scene = lightbench::scene::builtin::cornell();
    scene.size = (48, 48);
    let mut v = viewer(&g, scene);
    v.frame(&g).unwrap();
    let fresh_agrees = |v: &Viewer, what: &str| {
        let mut fresh = viewer(&g, v.scene.clone());
        fresh.frame(&g).unwrap();
        let e = rmse(&output(&g, &v.ex), &output(&g, &fresh.ex)).unwrap();
        assert!(e <= 1e-6, "{what}: edited vs opened with the edit: RMSE {e}");
    };
    v.apply(&g, Action::AddLight(LightKind::Spot)).unwrap();
    v.frame(&g).unwrap();
    assert_eq!(v.ex.scene().lights.len(), 2, "the executor has the new light");
    fresh_agrees(&v, "a spot light added");
    v.apply(&g, Action::Effect(Effect::Bloom, true)).unwrap();
    v.frame(&g).unwrap();
    assert!(
        v.ex.plan().passes.iter().any(|p| p.name == "bloom_bright"),
        "bloom called for: its passes planned"
    );
    fresh_agrees(&v, "bloom called for");
    v.apply(&g, Action::RemoveLight).unwrap();
    v.frame(&g).unwrap();
    fresh_agrees(&v, "the spot light removed");
    assert_eq!(v.ex.scene_uploads(), 1, "the scene stayed on the GPU");
}

/// A parameter the Plan fixes (here a shadow map's size) set in the viewer plans again with
/// it, as docs/pipelines.md says, keeping the viewer's camera; setting it back gives the
/// first image again. The executor alone refuses it (another Plan is needed).
#[test]
fn a_parameter_the_plan_fixes_plans_again_in_the_viewer() {
    let g = gpu();
    let mut scene = lightbench::scene::builtin::cornell();
    scene.size = (48, 48);
    let mut v = viewer(&g, scene);
    v.apply(&g, Action::Move(glam::Vec3::new(0.1, 0.0, 0.2))).unwrap();
    let camera = v.camera.clone();
    v.frame(&g).unwrap();
    let before = output(&g, &v.ex);
    assert!(
        v.ex.set_param("cube.size", ParamValue::Int(32)).is_err(),
        "the executor alone refuses it"
    );
    v.apply(&g, Action::Param("cube.size".into(), ParamValue::Int(32)))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(v.ex.texture("shadow.cube").unwrap().width(), 32, "a new Plan with the new size");
    assert_eq!(v.camera.position, camera.position, "the camera is kept");
    v.frame(&g).unwrap();
    let coarse = output(&g, &v.ex);
    assert!(rmse(&before, &coarse).unwrap() > 1e-4, "a coarser shadow map shows");
    v.apply(&g, Action::Param("cube.size".into(), ParamValue::Int(512))).unwrap();
    v.frame(&g).unwrap();
    let e = rmse(&before, &output(&g, &v.ex)).unwrap();
    assert!(e <= 1e-6, "back to the first size: RMSE {e}");
    // Out of its range: refused, the running Plan kept.
    assert!(v.apply(&g, Action::Param("cube.size".into(), ParamValue::Int(8))).is_err());
    assert_eq!(v.ex.texture("shadow.cube").unwrap().width(), 512);
}

/// The viewer watches the scene file and its models too: a model's colour edited on disk
/// reloads the scene (its meshes kept on the GPU), the viewer shows the new colour and takes
/// the reloaded scene as its own; the camera stays where the viewer has it.
#[test]
fn the_viewer_reloads_an_edited_model() {
    let g = gpu();
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("viewer-model-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    lightbench::bundled::init(&dir).unwrap();
    let file = dir.join("scenes/sun_only.ron");
    // As `view` loads it: keeping the models, for a reload to parse only what changed.
    let mut models = lightbench::scene::model_cache::ModelCache::keeping();
    let scene = lightbench::scene::load::load_sized_with(file.to_str().unwrap(), Some((32, 32)), &[], &mut models).unwrap();
    let pipeline = dir.join("pipelines/deferred.lbp");
    let mut v = Viewer::new(&g, (Workspace::disk(), &pipeline, None), scene, &[]).unwrap_or_else(|e| panic!("{e}"));
    v.watch(&g, (Some(&file), &[])).unwrap();
    v.keep_models(models);
    v.camera.position.x += 0.25;
    let camera = v.camera.clone();
    v.frame(&g).unwrap();
    let before = output(&g, &v.ex);
    let ground = dir.join("scenes/ground.gltf");
    let mut doc: serde_json::Value = serde_json::from_slice(&std::fs::read(&ground).unwrap()).unwrap();
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = serde_json::json!([0.05, 0.05, 0.05, 1.0]);
    std::fs::write(&ground, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
    while v.ex.scene_uploads() < 2 {
        assert!(std::time::Instant::now() < deadline, "no reload: {:?}", v.last_error);
        v.poll_reload(&g);
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    v.frame(&g).unwrap();
    let after = output(&g, &v.ex);
    assert!(rmse(&before, &after).unwrap() > 1e-3, "the ground darkened");
    assert_eq!(v.camera.position, camera.position, "the viewer's camera stays");
    let grey = v.scene.materials.iter().any(|m| m.base_color[..3] == [0.05, 0.05, 0.05]);
    assert!(grey, "the viewer's scene is the reloaded one");
    let kept = v.scene_kept.expect("the scene reload says what it kept");
    assert_eq!(kept.models, Some((1, 2)), "the chair taken as it was, the ground parsed again");
}
