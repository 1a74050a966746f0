//! Replacing the running Plan (hot reload, variant switching): built on the side and swapped
//! only on success, reusing resources and pipelines whose descriptors did not change,
//! keeping parameter overrides that still apply.

use crate::gpu_common;

use gpu_common::*;
use lightbench::gpu::{Executor, Gpu};
use lightbench::io::rmse;
use lightbench::render::compile_in;
use lightbench::scene::{builtin, Scene};
use lightbench_compiler::ir::ParamValue;
use lightbench_compiler::layout::BindingType;
use lightbench_compiler::plan::ResourceShape;
use lightbench_compiler::vfs::{MemoryVfs, Vfs};
use lightbench_compiler::{Executable, Workspace};
use std::path::Path;
use std::sync::Arc;

const PIPELINE: &str = "mem/pipelines/deferred.ron";

fn compile(g: &Gpu, ws: &Workspace, scene: &Scene) -> Executable {
    compile_in(ws, g, Path::new(PIPELINE), None, scene, &[])
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// The bundled deferred pipeline in memory, compiled and running on the Cornell box.
fn running(g: &Gpu) -> (Scene, Arc<MemoryVfs>, Workspace, Executable, Executor) {
    let scene = builtin::cornell();
    let vfs = memory_project();
    let ws = Workspace::new(vfs.clone());
    let exe = compile(g, &ws, &scene);
    let ex = Executor::new(g, &exe, &scene).unwrap();
    (scene, vfs, ws, exe, ex)
}

fn frame(g: &Gpu, ex: &mut Executor) -> lightbench::io::Image {
    let inputs = ex.inputs(0.0);
    ex.render_frame(g, &inputs).unwrap();
    output(g, ex)
}

/// The tone map with its result halved: a one-shader change with a visible effect.
fn darker_tonemap(vfs: &MemoryVfs) {
    let path = "mem/shaders/tonemap.wgsl";
    let text = vfs.read(Path::new(path)).unwrap();
    let edited = text.replace("vec3<f32>(1.0)), 1.0);", "vec3<f32>(1.0)) * 0.5, 1.0);");
    assert_ne!(edited, text);
    vfs.write(path, edited);
}

#[test]
fn a_failed_replace_leaves_the_old_plan_rendering_identically() {
    let g = gpu();
    let (scene, _, ws, exe, mut ex) = running(&g);
    let before = frame(&g, &mut ex);

    // A texture larger than the device allows: resource creation fails.
    let mut too_big = compile(&g, &ws, &scene);
    let hdr = too_big.plan.resource_id("hdr").unwrap();
    if let ResourceShape::Texture { extent, .. } = &mut too_big.plan.resources[hdr.0 as usize].shape {
        *extent = (g.device.limits().max_texture_dimension_2d + 1, 4);
    }
    let err = ex.replace(&g, &too_big).expect_err("an oversized texture must fail").to_string();
    assert!(err.contains("creating resources"), "{err}");

    // A layout that does not match the shader: pipeline creation fails.
    let mut bad_layout = compile(&g, &ws, &scene);
    let tonemap = bad_layout.plan.passes.iter_mut().find(|p| p.name == "tonemap").unwrap();
    let hdr_binding = tonemap
        .bind_groups
        .iter_mut()
        .flat_map(|g| &mut g.entries)
        .find(|e| e.name == "hdr")
        .unwrap();
    hdr_binding.ty = BindingType::Uniform { min_binding_size: 16 };
    let err = ex.replace(&g, &bad_layout).expect_err("a mismatched layout must fail").to_string();
    assert!(err.contains("pass `tonemap`"), "{err}");

    // The old Plan is untouched and renders exactly as before.
    assert_eq!(ex.plan(), &exe.plan);
    let after = frame(&g, &mut ex);
    assert_eq!(rmse(&before, &after), Some(0.0));
    assert_eq!(after.non_finite(), 0);
}

#[test]
fn a_one_shader_change_rebuilds_exactly_one_pipeline() {
    let g = gpu();
    let (scene, vfs, ws, _, mut ex) = running(&g);
    let before = frame(&g, &mut ex);

    darker_tonemap(&vfs);
    let compiled = ws.modules().stats().compiled;
    let edited = compile(&g, &ws, &scene);
    assert_eq!(
        ws.modules().stats().compiled,
        compiled + 1,
        "the workspace compiles only the edited module"
    );
    let report = ex.replace(&g, &edited).unwrap();
    assert_eq!(report.pipelines_built, vec!["tonemap".to_string()], "{report:?}");
    assert_eq!(report.pipelines_reused.len(), edited.plan.passes.len() - 1, "{report:?}");
    assert!(report.resources_created.is_empty(), "{report:?}");

    let after = frame(&g, &mut ex);
    let fresh = frame(&g, &mut Executor::new(&g, &edited, &scene).unwrap());
    assert!(rmse(&after, &fresh).unwrap() < 1e-6, "the replaced plan renders like a fresh one");
    let (b, a) = (before.mean_rgb(0, 0, 128, 128), after.mean_rgb(0, 0, 128, 128));
    assert!(a < 0.6 * b && a > 0.0, "halved tone map: {a} vs {b}");
}

#[test]
fn many_edits_keep_the_pipeline_cache_bounded() {
    // A long editing session: every edit is a new module and a new pipeline; old ones are
    // spares up to a bound, and their shader modules go with them.
    let g = gpu();
    let (scene, vfs, ws, exe, mut ex) = running(&g);
    let original = vfs.read(Path::new("mem/shaders/tonemap.wgsl")).unwrap();
    for i in 0..150 {
        let edited = original.replace(
            "vec3<f32>(1.0)), 1.0);",
            &format!("vec3<f32>(1.0)) * {:.4}, 1.0);", 0.5 + i as f64 * 1e-3),
        );
        vfs.write("mem/shaders/tonemap.wgsl", edited);
        let report = ex.replace(&g, &compile(&g, &ws, &scene)).unwrap();
        assert_eq!(report.pipelines_built.len(), 1);
    }
    let (pipelines, modules) = ex.cached();
    let passes = exe.plan.passes.len();
    assert!(pipelines <= passes + 64, "{pipelines} pipelines kept");
    // Each kept pipeline has at most two stage modules, and the tone map's vertex stage is shared.
    assert!(modules <= pipelines + passes, "{modules} shader modules for {pipelines} pipelines");
    assert_eq!(frame(&g, &mut ex).non_finite(), 0);
}

#[test]
fn a_parameter_override_survives_a_replace() {
    let g = gpu();
    let (scene, vfs, ws, _, mut ex) = running(&g);
    ex.set_param("tonemap.key", ParamValue::Float(0.5)).unwrap();
    frame(&g, &mut ex);

    darker_tonemap(&vfs);
    let edited = compile(&g, &ws, &scene);
    let report = ex.replace(&g, &edited).unwrap();
    assert!(report.params_dropped.is_empty(), "{report:?}");
    let kept = frame(&g, &mut ex);

    let mut with = Executor::new(&g, &edited, &scene).unwrap();
    with.set_param("tonemap.key", ParamValue::Float(0.5)).unwrap();
    let with = frame(&g, &mut with);
    let without = frame(&g, &mut Executor::new(&g, &edited, &scene).unwrap());
    assert!(rmse(&kept, &with).unwrap() < 1e-6, "the override still applies");
    assert!(rmse(&kept, &without).unwrap() > 1e-3, "and it changes the image");
}

#[test]
fn overrides_that_no_longer_apply_are_dropped_and_bad_ones_refused() {
    let g = gpu();
    let (scene, vfs, ws, _, mut ex) = running(&g);
    let err = ex.set_param("tonemap.kee", ParamValue::Float(0.5)).unwrap_err().to_string();
    assert!(err.contains("did you mean `tonemap.key`"), "{err}");
    assert!(
        ex.set_param("tonemap.key", ParamValue::Float(7.0)).is_err(),
        "above the declared max"
    );
    assert!(ex.set_param("tonemap.key", ParamValue::Bool(true)).is_err(), "wrong type");
    ex.set_param("tonemap.key", ParamValue::Float(0.3)).unwrap();

    // The parameter is renamed in the pipeline file (and its block field in the shaders of the
    // luminance options: `single`'s, and the block the other two share).
    let text = vfs
        .read(Path::new(PIPELINE))
        .unwrap()
        .replace("tonemap.key", "tonemap.exposure_key");
    vfs.write(PIPELINE, text);
    for shader in ["luminance.wgsl", "lib/luminance_reduce.wgsl"] {
        let shader = format!("mem/shaders/{shader}");
        let text = vfs.read(Path::new(&shader)).unwrap();
        assert!(text.contains("params.key"), "{shader} declares the block");
        vfs.write(&shader, text.replace("key", "exposure_key"));
    }
    let report = ex.replace(&g, &compile(&g, &ws, &scene)).unwrap();
    assert_eq!(report.params_dropped.len(), 1, "{report:?}");
    assert_eq!(report.params_dropped[0].0, "tonemap.key");
    // Frames render with the defaults; a frame asking for the old name is refused.
    let img = frame(&g, &mut ex);
    assert_eq!(img.non_finite(), 0);
    let mut stale = ex.inputs(0.0);
    let old_plan = compile(&g, &Workspace::new(memory_project()), &scene).plan;
    stale.params.set(&old_plan.params, "tonemap.key", ParamValue::Float(0.3)).unwrap();
    let err = ex.render_frame(&g, &stale).unwrap_err().to_string();
    assert!(err.contains("tonemap.key"), "{err}");
}

#[test]
fn frames_take_the_camera_they_are_given() {
    let g = gpu();
    let (_, _, _, _, mut ex) = running(&g);
    let front = frame(&g, &mut ex);
    let mut inputs = ex.inputs(0.0);
    inputs.camera.yaw += 180.0; // look out of the open box
    ex.render_frame(&g, &inputs).unwrap();
    let back = output(&g, &ex);
    assert!(rmse(&front, &back).unwrap() > 0.05, "a turned camera sees something else");
    // The executor keeps the last camera for the next frame's default inputs.
    assert_eq!(ex.inputs(1.0).camera.yaw, inputs.camera.yaw);
}

/// A textured Cornell box: the tall box's material takes a 4×4 map.
fn textured_cornell() -> Scene {
    let mut scene = builtin::cornell();
    let texels: Vec<u8> = (0..16u8).flat_map(|i| [40 + 12 * i, 200 - 8 * i, 90, 255]).collect();
    scene.textures.push(lightbench::scene::ImageData {
        width: 4,
        height: 4,
        rgba: texels.into(),
        srgb: true,
    });
    let tall = scene.meshes.iter().position(|m| m.name.contains("tall")).expect("a tall box");
    let material = scene.meshes[tall].material;
    scene.materials[material].base_color_texture = Some(0);
    scene.size = (32, 32);
    scene
}

/// A new scene keeps on the GPU what it shares with the old one: an edit that moves one mesh
/// keeps every other mesh's buffers, the texture and (ray-traced shadows) the other meshes'
/// BLAS resident, and renders exactly what an executor made for the new scene renders.
#[test]
fn a_new_scene_keeps_what_did_not_change_resident_and_renders_as_a_fresh_one() {
    let g = gpu();
    let shadows = [("shadows".to_string(), "rt".to_string())];
    let path = root().join("pipelines/deferred.lbp");
    let compile = |s: &Scene| {
        lightbench::render::compile(&g, &path, None, s, &shadows)
            .unwrap_or_else(|e| panic!("{e}"))
            .0
    };
    let before = textured_cornell();
    let mut ex = Executor::new(&g, &compile(&before), &before).unwrap();
    let first = frame(&g, &mut ex);
    // The short box moved up a little: its vertices change, nothing else.
    let mut after = textured_cornell();
    let short = after.meshes.iter().position(|m| m.name.contains("short")).expect("a short box");
    for v in &mut after.meshes[short].vertices {
        v.position[1] += 0.05;
    }
    let exe = compile(&after);
    let report = ex.replace_scene(&g, &exe, &after).unwrap();
    let kept = report.scene_kept.expect("a new scene reports what it kept");
    let meshes = kept.meshes.1;
    assert!(meshes >= 5, "{kept:?}");
    assert_eq!(kept.meshes, (meshes - 1, meshes), "every mesh but the moved one kept");
    assert_eq!(kept.textures, (1, 1), "the texture kept");
    assert_eq!(kept.blas, Some((meshes - 1, meshes)), "every BLAS but the moved mesh's kept");
    let ours = frame(&g, &mut ex);
    let mut fresh = Executor::new(&g, &exe, &after).unwrap();
    let theirs = frame(&g, &mut fresh);
    assert_eq!(
        rmse(&ours, &theirs),
        Some(0.0),
        "the same image as an executor made for the new scene"
    );
    assert!(rmse(&ours, &first).unwrap() > 0.0, "the moved box shows");
    // Nothing changed: everything kept; a changed texel: the texture uploaded again.
    let report = ex.replace_scene(&g, &exe, &after).unwrap();
    assert_eq!(report.scene_kept.unwrap().meshes, (meshes, meshes));
    let mut recoloured = after.clone();
    recoloured.textures[0].rgba.to_mut()[0] = 255;
    let report = ex.replace_scene(&g, &exe, &recoloured).unwrap();
    assert_eq!(report.scene_kept.unwrap().textures, (0, 1));
}
