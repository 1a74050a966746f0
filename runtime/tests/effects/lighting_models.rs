//! The four lighting models of `pipelines/deferred.ron` (variant `lighting`, seed 003 ch. 2–3,
//! §5.1–5.2) give one image: forward single-pass, forward multi-pass with a depth pre-pass,
//! deferred full-screen and deferred over light volumes, from 1 to 100 lights, with the
//! camera inside and outside the lights' volumes.

use crate::gpu_common;

use glam::Vec3;
use gpu_common::*;
use lightbench::gpu::{Executor, Gpu};
use lightbench::io::{rmse, Image};
use lightbench::scene::{builtin, Scene};

const MODELS: [&str; 4] = ["forward_single", "forward_multi", "deferred_fullscreen", "deferred_volumes"];

fn hdr(g: &Gpu, scene: &Scene, variants: &[(&str, &str)]) -> (Image, Executor) {
    let ex = render_with(g, &deferred(), scene, variants, 1);
    for (v, o) in variants {
        let chosen = &ex.plan().variants.iter().find(|c| c.variant == *v).unwrap().option;
        assert_eq!(chosen, o, "{v}={o} ran as {chosen}");
    }
    (ex.read_texture(g, "hdr", 0, 0).unwrap(), ex)
}

/// RMSE over RGB relative to the reference's mean (HDR values have no fixed scale).
fn relative_rmse(reference: &Image, other: &Image) -> f64 {
    let mean = reference.rgba.chunks(4).map(|p| (p[0] + p[1] + p[2]) as f64 / 3.0).sum::<f64>() / (reference.rgba.len() / 4) as f64;
    assert!(mean > 1e-4, "the reference is black");
    rmse(reference, other).unwrap() / mean
}

fn all_finite(img: &Image) -> bool {
    img.rgba.iter().all(|v| v.is_finite())
}

fn unshadowed(mut scene: Scene) -> Scene {
    for l in &mut scene.lights {
        l.shadows = false;
    }
    scene
}

/// Forward shades the mesh's own attributes where deferred reads them back from the G-buffer
/// (8-bit albedo, 16-bit float normals, positions from depth): they agree to this fraction of
/// the mean radiance.
const MODEL_TOLERANCE: f64 = 0.02;

#[test]
fn the_four_lighting_models_agree_for_1_10_and_100_lights() {
    let g = gpu();
    let mut cornell = unshadowed(builtin::cornell());
    cornell.size = (96, 96);
    let scenes = [cornell, builtin::many_lights(10), builtin::many_lights(100)];
    for scene in scenes {
        let (reference, _) = hdr(&g, &scene, &[("lighting", "deferred_fullscreen")]);
        for model in MODELS {
            let (img, _) = hdr(&g, &scene, &[("lighting", model)]);
            assert!(all_finite(&img), "{}: {model} wrote NaN/Inf", scene.name);
            let e = relative_rmse(&reference, &img);
            eprintln!(
                "{} ({} lights): deferred_fullscreen vs {model}: relative RMSE {e:.5}",
                scene.name,
                scene.lights.len()
            );
            assert!(e < MODEL_TOLERANCE, "{}: {model} relative RMSE {e}", scene.name);
        }
    }
}

/// Multi-pass forward and light volumes read each light's shadow map as the full-screen
/// passes do (single-pass forward is unshadowed, so it is left out here).
#[test]
fn shadowed_models_agree_with_every_shadow_kind() {
    let g = gpu();
    for scene in [builtin::cornell(), colonnade_with_point_light()] {
        for cube in ["classic", "instanced", "dual_paraboloid"] {
            let (reference, _) = hdr(&g, &scene, &[("lighting", "deferred_fullscreen"), ("cube_shadow", cube)]);
            for model in ["forward_multi", "deferred_volumes"] {
                let (img, _) = hdr(&g, &scene, &[("lighting", model), ("cube_shadow", cube)]);
                let e = relative_rmse(&reference, &img);
                eprintln!("{} ({cube}): deferred_fullscreen vs {model}: relative RMSE {e:.5}", scene.name);
                assert!(e < MODEL_TOLERANCE, "{} ({cube}): {model} relative RMSE {e}", scene.name);
            }
        }
    }
}

/// A light volume drawn from its far side still covers every pixel when the camera is inside
/// it: the Cornell box's camera is inside its point light's sphere; here it also stands inside
/// a spot light's cone and right next to a point light.
#[test]
fn light_volumes_stay_correct_with_the_camera_inside() {
    let g = gpu();
    let mut scene = unshadowed(builtin::cornell());
    scene.size = (96, 96);
    let eye = scene.camera.position;
    let point = &scene.lights[0];
    assert!(eye.distance(point.position) < point.range, "the camera must be inside the sphere");
    let mut spot = lightbench::scene::Light::point(eye + Vec3::new(0.0, 0.3, 0.5), Vec3::new(1.0, 0.5, 0.3), 3.0, 6.0);
    spot.kind = lightbench_compiler::ir::LightKind::Spot;
    spot.direction = Vec3::new(0.0, -0.2, -1.0);
    spot.shadows = false;
    scene.lights.push(spot);
    let near = lightbench::scene::Light::point(eye + Vec3::new(0.05, 0.0, -0.05), Vec3::new(0.2, 0.4, 1.0), 0.5, 0.5);
    scene.lights.push(near);
    let (fullscreen, _) = hdr(&g, &scene, &[("lighting", "deferred_fullscreen")]);
    let (volumes, ex) = hdr(&g, &scene, &[("lighting", "deferred_volumes")]);
    let e = relative_rmse(&fullscreen, &volumes);
    eprintln!("camera inside: fullscreen vs volumes relative RMSE {e:.6}");
    // The same fragment shader runs on the pixels the volume covers: nothing else may differ.
    assert!(e < 1e-4, "relative RMSE {e}");
    let reps = |pass: &str| ex.last_timings.iter().find(|t| t.pass == pass).map(|t| t.repetitions);
    assert_eq!(reps("volume_point"), Some(2));
    assert_eq!(reps("volume_directional_spot"), Some(1));
}

/// Each model runs the passes it names and no other lighting pass.
#[test]
fn each_model_runs_its_own_passes() {
    let g = gpu();
    let mut scene = builtin::cornell();
    scene.size = (32, 32);
    let expect: [(&str, &[&str], &[&str]); 4] = [
        (
            "forward_single",
            &["forward_single"],
            &["gbuffer", "ambient", "forward_depth", "light_point"],
        ),
        (
            "forward_multi",
            &["forward_depth", "forward_ambient", "forward_point"],
            &["gbuffer", "ambient", "forward_single", "light_point"],
        ),
        (
            "deferred_fullscreen",
            &["gbuffer", "ambient", "light_point"],
            &["volume_point", "forward_point"],
        ),
        (
            "deferred_volumes",
            &["gbuffer", "ambient", "volume_point"],
            &["light_point", "forward_point"],
        ),
    ];
    for (model, runs, not) in expect {
        let (_, ex) = hdr(&g, &scene, &[("lighting", model)]);
        let ran: Vec<&str> = ex.last_timings.iter().map(|t| t.pass.as_str()).collect();
        for p in runs {
            assert!(ran.contains(p), "{model}: {p} did not run: {ran:?}");
        }
        for p in not {
            assert!(!ran.contains(p), "{model}: {p} ran: {ran:?}");
        }
    }
}

/// Pixels a `draw: LightVolume` pass covers for one light, each counted as often as a
/// fragment lands on it (a pipeline written for the test, in memory).
fn volume_coverage(g: &Gpu, scene: &Scene) -> Vec<f32> {
    use lightbench_compiler::workspace::Workspace;
    let vfs = memory_project();
    vfs.write(
        "mem/pipelines/coverage.lbp",
        "pipeline coverage\n\
         texture cover: Rgba16Float viewport\n\
         raster cover \"light_volume.wgsl\" {\n    vertex vs_volume\n    fragment \"count.wgsl#fs_main\"\n    draw LightVolume\n    cull Front\n    \
         per_light(Directional, Spot, Point)\n    color cover clear(0, 0, 0, 0) blend Add\n}\n\
         output cover\n",
    );
    vfs.write(
        "mem/shaders/count.wgsl",
        "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0);\n}\n",
    );
    let ws = Workspace::new(vfs);
    let pipeline = std::path::Path::new("mem/pipelines/coverage.lbp");
    let (exe, report) = lightbench::render::compile_in(&ws, g, pipeline, None, scene, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert!(!report.contains("error"), "{report}");
    let ex = lightbench::render::render(g, &exe, scene, 1).unwrap();
    ex.read_texture(g, "cover", 0, 0).unwrap().rgba.chunks(4).map(|p| p[0]).collect()
}

/// Does the ray through pixel (x, y) pass within `r` of `centre`?
fn ray_meets_sphere(scene: &Scene, (x, y): (u32, u32), centre: Vec3, r: f32) -> bool {
    let (w, h) = scene.size;
    let inv = (scene.camera.proj(w as f32 / h as f32) * scene.camera.view()).inverse();
    let ndc = glam::vec2((x as f32 + 0.5) / w as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / h as f32 * 2.0);
    let far = inv.project_point3(ndc.extend(1.0));
    let eye = scene.camera.position;
    let d = (far - eye).normalize();
    let t = (centre - eye).dot(d).max(0.0);
    (eye + d * t).distance(centre) <= r
}

/// The volumes bound what they stand for, tightly, and cover each pixel once: a sphere seen
/// from outside, from inside, and a cone.
#[test]
fn light_volumes_cover_their_lights_reach_once_and_tightly() {
    let g = gpu();
    let mut scene = builtin::cornell();
    scene.size = (64, 64);
    let eye = scene.camera.position;
    for (centre, r) in [(Vec3::new(0.3, 1.0, 0.0), 0.6), (eye + Vec3::new(0.0, 0.0, -0.2), 0.5)] {
        scene.lights = vec![lightbench::scene::Light::point(centre, Vec3::ONE, 1.0, r)];
        let cover = volume_coverage(&g, &scene);
        assert!(cover.iter().all(|&c| c <= 1.0), "a pixel was shaded twice");
        let (mut exact, mut drawn) = (0, 0);
        for y in 0..scene.size.1 {
            for x in 0..scene.size.0 {
                let covered = cover[(y * scene.size.0 + x) as usize] > 0.5;
                let inside = eye.distance(centre) < r || ray_meets_sphere(&scene, (x, y), centre, r);
                assert!(covered || !inside, "pixel ({x}, {y}) reaches the light but was not drawn");
                exact += inside as u32;
                drawn += covered as u32;
            }
        }
        eprintln!("sphere r {r} at {centre}: {drawn} pixels drawn, {exact} reached");
        assert!(
            exact > 0 && (drawn as f32) < exact as f32 * 1.3 + 16.0,
            "loose volume: {drawn} drawn for {exact}"
        );
    }
    // A narrow spot cone from the side: fewer pixels than its range's sphere would take.
    let mut spot = lightbench::scene::Light::point(Vec3::new(-0.6, 1.8, 0.0), Vec3::ONE, 1.0, 2.0);
    spot.kind = lightbench_compiler::ir::LightKind::Spot;
    spot.direction = Vec3::new(1.0, -0.3, 0.0);
    spot.outer_angle = 15.0;
    spot.inner_angle = 10.0;
    scene.lights = vec![spot];
    let cone: f32 = volume_coverage(&g, &scene).iter().sum();
    scene.lights[0].kind = lightbench_compiler::ir::LightKind::Point;
    let sphere: f32 = volume_coverage(&g, &scene).iter().sum();
    eprintln!("spot cone: {cone} pixels, its sphere {sphere}");
    assert!(cone > 0.0 && cone < sphere * 0.5, "cone {cone}, sphere {sphere}");
}

/// Repetitions that add into the same image (a light pass per light) share one render pass:
/// the image is the one a render pass per repetition gives, and `--timings` still reports
/// each pass once, with all its repetitions.
#[test]
fn merged_light_repetitions_render_the_same_image() {
    let g = gpu();
    for n in [10, 100] {
        let scene = builtin::many_lights(n);
        for model in ["deferred_fullscreen", "deferred_volumes"] {
            let v = [("lighting".to_string(), model.to_string())];
            let (exe, _) = lightbench::render::compile(&g, &deferred(), None, &scene, &v).unwrap_or_else(|e| panic!("{e}"));
            let light = exe.plan.passes.iter().find(|p| p.repetitions as usize == n).unwrap();
            assert!(light.continues, "{model}: the light pass continues ambient's render pass");
            let image = |merge: bool, timing: bool| {
                let mut ex = Executor::new(&g, &exe, &scene).unwrap();
                ex.set_merge(merge);
                ex.set_timing(timing);
                ex.render_frame(&g, &ex.inputs(0.0)).unwrap();
                let lights: Vec<_> = ex.last_timings.iter().filter(|t| t.repetitions as usize == n).cloned().collect();
                (ex.read_texture(&g, "hdr", 0, 0).unwrap(), lights)
            };
            // Timed, repetitions share a render pass; untimed, the light pass also continues
            // ambient's (timestamps would need passes of their own).
            let ((merged, timed), (apart, _), (continued, _)) = (image(true, true), image(false, true), image(true, false));
            for (what, img) in [("merged repetitions", &merged), ("passes continued", &continued)] {
                let e = rmse(&apart, img).unwrap();
                eprintln!("{model}, {n} lights: RMSE {what} vs one render pass per repetition {e:e}");
                assert!(e <= 1e-5, "{model}, {n} lights, {what}: RMSE {e}");
            }
            assert!(
                !timed.is_empty() && timed.iter().all(|t| t.gpu_ms.is_some_and(|ms| ms >= 0.0)),
                "{timed:?}"
            );
        }
    }
}
