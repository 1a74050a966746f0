//! Rendering on a real adapter (lavapipe in CI): shadows where the geometry puts them, spot
//! cones where the angle says, no NaN/Inf anywhere, goldens, variants, backends, timings.

use crate::gpu_common;

use glam::{Mat4, Vec3};
use gpu_common::*;
use lightbench::io::{rmse, Image};
use lightbench::scene::geometry::{cuboid, quad};
use lightbench::scene::{builtin, Camera, Light, Material, Scene};

/// A 6×6 white floor seen from above and in front, an optional box, and one light.
fn stage(boxes: &[(Vec3, Vec3)], light: Light) -> Scene {
    let (mut vs, mut is) = (vec![], vec![]);
    quad(Vec3::ZERO, Vec3::X * 3.0, Vec3::NEG_Z * 3.0, &mut vs, &mut is);
    let mut meshes = vec![mesh("floor", (vs, is), Mat4::IDENTITY)];
    for (i, (center, half)) in boxes.iter().enumerate() {
        meshes.push(mesh(&format!("box{i}"), cuboid(*half), Mat4::from_translation(*center)));
    }
    Scene {
        name: "stage".into(),
        size: (128, 128),
        camera: Camera {
            position: Vec3::new(0.0, 5.0, 4.0),
            yaw: 0.0,
            pitch: -50.0,
            fov: 55.0,
            near: 0.1,
            far: 50.0,
            animation: None,
        },
        meshes,
        materials: vec![Material::color("white", [0.8, 0.8, 0.8], 0.9)],
        textures: vec![],
        lights: vec![light],
        effects: Default::default(),
    }
}

/// Mean linear HDR value in a 5×5 window around where the camera sees `p`.
fn hdr_at(gpu: &lightbench::gpu::Gpu, ex: &lightbench::gpu::Executor, scene: &Scene, p: Vec3) -> f32 {
    hdr_window(gpu, ex, scene, p, 2)
}

fn hdr_window(gpu: &lightbench::gpu::Gpu, ex: &lightbench::gpu::Executor, scene: &Scene, p: Vec3, r: u32) -> f32 {
    let img = ex.read_texture(gpu, "hdr", 0, 0).unwrap();
    let (x, y) = scene.project(p).expect("point in view");
    let (x, y) = (x as u32, y as u32);
    img.mean_rgb(x.saturating_sub(r), y.saturating_sub(r), x + r + 1, y + r + 1)
}

#[test]
fn point_light_shadow_behind_an_occluder() {
    let g = gpu();
    let light = Light::point(Vec3::new(0.0, 2.0, 0.0), Vec3::ONE, 4.0, 8.0);
    let occluder = [(Vec3::new(0.0, 1.0, 0.0), Vec3::splat(0.3))];
    let behind = Vec3::new(0.0, 0.0, 0.0);
    for variant in ["classic", "instanced"] {
        let with = stage(&occluder, light.clone());
        let without = stage(&[], light.clone());
        let a = hdr_at(
            &g,
            &render_with(&g, &deferred(), &with, &[("cube_shadow", variant)], 1),
            &with,
            behind,
        );
        let b = hdr_at(
            &g,
            &render_with(&g, &deferred(), &without, &[("cube_shadow", variant)], 1),
            &without,
            behind,
        );
        assert!(b > 0.05, "{variant}: the floor under the light should be lit ({b})");
        assert!(a < 0.2 * b, "{variant}: shadowed {a} vs unshadowed {b}");
        // Off to the side the occluder changes nothing.
        let side = Vec3::new(1.5, 0.0, 0.5);
        let sa = hdr_at(
            &g,
            &render_with(&g, &deferred(), &with, &[("cube_shadow", variant)], 1),
            &with,
            side,
        );
        let sb = hdr_at(
            &g,
            &render_with(&g, &deferred(), &without, &[("cube_shadow", variant)], 1),
            &without,
            side,
        );
        assert!((sa - sb).abs() < 0.05 * sb.max(1e-3), "{variant}: {sa} vs {sb}");
    }
}

#[test]
fn directional_shadow_falls_under_the_box() {
    let g = gpu();
    // Straight down: the lookAt up vector must not be parallel to the light direction.
    let sun = Light::directional(Vec3::NEG_Y, Vec3::ONE, 2.0);
    let scene = stage(&[(Vec3::new(0.8, 1.0, 0.0), Vec3::splat(0.3))], sun);
    let ex = render_with(&g, &deferred(), &scene, &[], 1);
    let under = hdr_at(&g, &ex, &scene, Vec3::new(0.8, 0.0, 0.0));
    let mirror = hdr_at(&g, &ex, &scene, Vec3::new(-0.8, 0.0, 0.0));
    let beside = hdr_at(&g, &ex, &scene, Vec3::new(0.8, 0.0, 0.8));
    assert!(mirror > 0.1, "open floor is lit: {mirror}");
    assert!(under < 0.2 * mirror, "under the box {under} vs open floor {mirror}");
    assert!(beside > 0.8 * mirror, "beside the box footprint is lit: {beside} vs {mirror}");
}

#[test]
fn spot_cone_edge_is_where_the_angle_says() {
    let g = gpu();
    let h = 3.0f32;
    let (inner, outer) = (18.0f32, 20.0f32);
    let spot = Light::spot(Vec3::new(0.0, h, 0.0), Vec3::NEG_Y, inner, outer, Vec3::ONE, 8.0, 10.0);
    let scene = stage(&[], spot);
    let ex = render_with(&g, &deferred(), &scene, &[], 1);
    let r_inner = h * inner.to_radians().tan();
    let r_outer = h * outer.to_radians().tan();
    for dir in [Vec3::X, Vec3::NEG_X, Vec3::NEG_Z] {
        // Single pixels: a window would straddle the edge where the floor is foreshortened.
        let inside = hdr_window(&g, &ex, &scene, dir * (r_inner * 0.9), 0);
        let outside = hdr_window(&g, &ex, &scene, dir * (r_outer * 1.1), 0);
        // Far outside the cone only the ambient term remains.
        let ambient = hdr_at(&g, &ex, &scene, dir * 2.4);
        assert!(
            inside > 4.0 * ambient,
            "inside the cone is lit along {dir}: {inside} vs ambient {ambient}"
        );
        assert!(
            (outside - ambient).abs() < 0.02 * inside,
            "just outside the cone along {dir}: {outside}, ambient {ambient}, inside {inside}"
        );
    }
}

/// Every texture slice and buffer of the plan, all finite.
fn assert_all_finite(g: &lightbench::gpu::Gpu, ex: &lightbench::gpu::Executor, what: &str) {
    for r in &ex.plan().resources {
        for (inst, layer) in ex.slices(&r.name).unwrap() {
            if r.is_buffer() {
                let words = ex.read_buffer(g, &r.name, inst).unwrap();
                assert!(
                    words.iter().all(|w| w.is_finite()),
                    "{what}: buffer {} has non-finite values: {words:?}",
                    r.name
                );
            } else {
                let img: Image = ex.read_texture(g, &r.name, inst, layer).unwrap();
                assert_eq!(img.non_finite(), 0, "{what}: {} instance {inst} layer {layer} has NaN/Inf", r.name);
            }
        }
    }
}

#[test]
fn no_nan_or_inf_in_any_resource() {
    let g = gpu();
    let mut colonnade = builtin::colonnade();
    colonnade.size = (128, 64);
    let mut dark = builtin::cornell();
    for l in &mut dark.lights {
        l.on = false; // black frame: log-average luminance of nothing
    }
    let cases: Vec<(&str, Scene, &str)> = vec![
        ("cornell classic", builtin::cornell(), "classic"),
        ("cornell instanced", builtin::cornell(), "instanced"),
        ("colonnade", colonnade, "classic"),
        ("many lights", builtin::many_lights(6), "classic"),
        ("black frame", dark, "classic"),
    ];
    for (what, scene, variant) in cases {
        let ex = render_with(&g, &deferred(), &scene, &[("cube_shadow", variant)], 2);
        assert_all_finite(&g, &ex, what);
    }
}

#[test]
fn golden_cornell_matches() {
    let g = gpu();
    let scene = builtin::cornell();
    let ex = render_with(&g, &deferred(), &scene, &[], 1);
    let img = output(&g, &ex);
    let path = root().join("runtime/tests/golden/cornell_deferred_128.png");
    if std::env::var_os("LIGHTBENCH_BLESS").is_some() {
        img.save(&path).unwrap();
    }
    let golden = Image::load_png(&path).unwrap_or_else(|e| panic!("{e}: render it with LIGHTBENCH_BLESS=1, review it, commit it"));
    // Compare in the stored (8-bit sRGB) encoding.
    let ours = Image {
        rgba: img.rgba.iter().map(|v| (v.clamp(0.0, 1.0) * 255.0).round() / 255.0).collect(),
        ..img.clone()
    };
    let e = rmse(&ours, &golden).expect("same size");
    assert!(e < 0.01, "RMSE {e:.4} against {}", path.display());
}

/// Every cube-shadow option renders what `classic` does, on the Cornell box and the
/// colonnade. `multiview` must really run: CI's lavapipe (Mesa 25 from bookworm-backports)
/// renders multiview correctly, and a driver whose multiview fails the probe (Mesa 22.3) fails
/// this test instead of skipping it.
/// How far dual paraboloid shadows may stray from classic cube shadows (HDR RMSE).
const DUAL_PARABOLOID_RMSE: f64 = 0.015;

#[test]
fn cube_shadow_variants_agree() {
    let g = gpu();
    assert!(
        g.profile.has(lightbench_compiler::profile::Feature::Multiview),
        "this test needs an adapter with working multiview (lavapipe from Mesa 25; see README): {}",
        g.describe()
    );
    for scene in [builtin::cornell(), colonnade_with_point_light()] {
        let hdr = |v: &str| {
            let ex = render_with(&g, &deferred(), &scene, &[("cube_shadow", v)], 1);
            let chosen = ex
                .plan()
                .variants
                .iter()
                .find(|c| c.variant == "cube_shadow")
                .unwrap()
                .option
                .clone();
            assert_eq!(chosen, v, "{v} ran as {chosen}");
            ex.read_texture(&g, "hdr", 0, 0).unwrap()
        };
        let classic = hdr("classic");
        // Dual paraboloid maps sample the surroundings differently (two hemispheres at 512²
        // against six faces at 512²), so shadow edges move by a texel here and there.
        for (v, bound) in [("multiview", 0.02), ("instanced", 0.02), ("dual_paraboloid", DUAL_PARABOLOID_RMSE)] {
            let e = rmse(&classic, &hdr(v)).unwrap();
            eprintln!("{}: classic vs {v} RMSE {e}", scene.name);
            assert!(e < bound, "{}: classic vs {v} RMSE {e}", scene.name);
        }
    }
}

#[test]
fn timings_list_every_executed_pass_and_no_culled_one() {
    let g = gpu();
    let scene = builtin::cornell();
    let ex = render_with(&g, &deferred(), &scene, &[], 1);
    let timed: Vec<&str> = ex.last_timings.iter().map(|t| t.pass.as_str()).collect();
    let planned: Vec<&str> = ex.plan().passes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(timed, planned);
    for t in &ex.last_timings {
        let ms = t.gpu_ms.expect("lavapipe has timestamp queries");
        assert!(ms.is_finite() && ms >= 0.0, "{t:?}");
    }
    for c in &ex.plan().culled {
        assert!(!timed.contains(&c.name.as_str()), "culled pass {} was timed", c.name);
    }
    assert!(
        ex.plan().culled.iter().any(|c| c.name == "shadow_map"),
        "no directional/spot light in the Cornell box"
    );
    assert_eq!(
        ex.last_timings
            .iter()
            .find(|t| t.pass == "shadow_cube_classic")
            .unwrap()
            .repetitions,
        6
    );
}

#[test]
fn replacing_the_plan_keeps_unchanged_resources() {
    let g = gpu();
    let scene = builtin::cornell();
    let ex = render_with(&g, &deferred(), &scene, &[], 1);
    let before = output(&g, &ex);
    let v = vec![("tonemap".to_string(), "simple".to_string())];
    let (exe, _) = lightbench::render::compile(&g, &deferred(), None, &scene, &v).unwrap();
    let mut ex = ex;
    let report = ex.replace(&g, &exe).unwrap();
    for name in ["gbuf.normal", "gbuf.depth", "hdr", "shadow.cube", "ldr"] {
        assert!(
            report.resources_reused.iter().any(|r| r == name),
            "{name} was recreated; reused: {:?}",
            report.resources_reused
        );
    }
    ex.render_frame(&g, &ex.inputs(0.0)).unwrap();
    let after = output(&g, &ex);
    assert_eq!(after.non_finite(), 0);
    // A different operator: the images differ, but not wildly.
    let e = rmse(&before, &after).unwrap();
    assert!(e > 1e-4 && e < 0.25, "RMSE {e}");
}

/// docs/embedding.md: `replace` reuses textures and buffers *of the same name* whose
/// descriptors did not change. The output renamed (`ldr` → `display`, the same descriptor)
/// is made anew; the rest is reused; the image is the same.
#[test]
fn replacing_the_plan_reuses_resources_by_name_and_descriptor() {
    use lightbench_compiler::vfs::Vfs;
    use lightbench_compiler::workspace::Workspace;
    let g = gpu();
    let scene = builtin::cornell();
    let vfs = memory_project();
    let ws = Workspace::new(vfs.clone());
    let path = std::path::Path::new("mem/pipelines/deferred.lbp");
    let (exe, _) = lightbench::render::compile_in(&ws, &g, path, None, &scene, &[]).unwrap_or_else(|e| panic!("{e}"));
    let mut ex = lightbench::render::render(&g, &exe, &scene, 1).unwrap();
    let before = output(&g, &ex);
    let text = vfs.read(path).unwrap();
    let renamed = text
        .replace("texture ldr: Rgba8UnormSrgb viewport", "texture display: Rgba8UnormSrgb viewport")
        .replace("color match(aa) { \"none\": ldr,", "color match(aa) { \"none\": display,")
        .replace("    color ldr\n", "    color display\n")
        .replace("    color ldr, taa.history", "    color display, taa.history")
        .replace("\noutput ldr\n", "\noutput display\n");
    assert!(
        !renamed.contains(" ldr\n") && !renamed.contains(" ldr,"),
        "every use of `ldr` renamed"
    );
    vfs.write(path, renamed);
    let (exe, _) = lightbench::render::compile_in(&ws, &g, path, None, &scene, &[]).unwrap_or_else(|e| panic!("{e}"));
    let report = ex.replace(&g, &exe).unwrap();
    assert!(report.resources_created.iter().any(|r| r == "display"), "{report:?}");
    assert!(!report.resources_reused.iter().any(|r| r == "display" || r == "ldr"), "{report:?}");
    for name in ["gbuf.normal", "gbuf.depth", "hdr"] {
        assert!(report.resources_reused.iter().any(|r| r == name), "{name}: {report:?}");
    }
    ex.render_frame(&g, &ex.inputs(0.0)).unwrap();
    let after = ex.read_texture(&g, "display", 0, 0).unwrap();
    assert_eq!(rmse(&before, &after).unwrap(), 0.0);
}

#[test]
fn black_frame_tone_maps_to_black() {
    let g = gpu();
    let mut scene = builtin::cornell();
    scene.lights.clear();
    let mut ex = render_with(&g, &deferred(), &scene, &[], 1);
    // No light and no ambient term: the log-average luminance is that of a black frame.
    let black = lightbench_compiler::ir::ParamValue::Vec(vec![0.0, 0.0, 0.0]);
    ex.set_param("ambient.color", black).unwrap();
    ex.render_frame(&g, &ex.inputs(0.0)).unwrap();
    let lum = ex.read_buffer(&g, "lum", 0).unwrap();
    assert!(
        lum[0].is_finite() && lum[0] > 0.0 && lum[0] < 1e-3,
        "log-average of a black frame: {lum:?}"
    );
    let img = output(&g, &ex);
    assert_eq!(img.non_finite(), 0);
    assert!(img.mean_rgb(0, 0, 128, 128) < 0.02, "{}", img.mean_rgb(0, 0, 128, 128));
}

#[test]
fn gl_backend_falls_back_from_multiview_and_renders_alike() {
    let vk = gpu();
    let gl = lightbench::gpu::Gpu::new(&lightbench::gpu::DeviceOptions {
        backend: Some(lightbench::gpu::device::BackendChoice::Gl),
        adapter: None,
    })
    .unwrap_or_else(|e| panic!("the GL backend (llvmpipe through EGL) must be available: {e}"));
    assert!(!gl.profile.has(lightbench_compiler::profile::Feature::Multiview));
    let scene = builtin::cornell();
    let v = vec![("cube_shadow".to_string(), "multiview".to_string())];
    let (exe, _) = lightbench::render::compile(&gl, &deferred(), None, &scene, &v).unwrap();
    let chosen = exe.plan.variants.iter().find(|c| c.variant == "cube_shadow").unwrap();
    assert_ne!(chosen.option, "multiview");
    assert!(
        chosen.reason.as_deref().unwrap_or("").contains("needs feature Multiview"),
        "{chosen:?}"
    );
    let ex = lightbench::render::render(&gl, &exe, &scene, 1).unwrap();
    let on_gl = ex.read_texture(&gl, "hdr", 0, 0).unwrap();
    let on_vk = render_with(&vk, &deferred(), &scene, &[], 1)
        .read_texture(&vk, "hdr", 0, 0)
        .unwrap();
    assert_eq!(on_gl.non_finite(), 0);
    let e = rmse(&on_gl, &on_vk).unwrap();
    assert!(e < 0.03, "GL vs Vulkan RMSE {e}");
    // The lighting models and dual paraboloid shadows need nothing GL lacks; the fat G-buffer
    // stores positions in 32-bit floats, which GL cannot render to: it falls back to packed.
    let v = vec![("gbuffer".to_string(), "fat".to_string())];
    let (exe, _) = lightbench::render::compile(&gl, &deferred(), None, &scene, &v).unwrap();
    let chosen = exe.plan.variants.iter().find(|c| c.variant == "gbuffer").unwrap();
    assert_eq!(chosen.option, "packed");
    assert!(
        chosen.reason.as_deref().unwrap_or("").contains("needs feature Float32Renderable"),
        "{chosen:?}"
    );
    for (k, o) in [
        ("lighting", "forward_single"),
        ("lighting", "forward_multi"),
        ("lighting", "deferred_volumes"),
        ("cube_shadow", "dual_paraboloid"),
    ] {
        let v = vec![(k.to_string(), o.to_string())];
        let (exe, _) = lightbench::render::compile(&gl, &deferred(), None, &scene, &v).unwrap();
        let chosen = &exe.plan.variants.iter().find(|c| c.variant == k).unwrap().option;
        assert_eq!(chosen, o, "{k}={o} fell back on GL");
        let on_gl = lightbench::render::render(&gl, &exe, &scene, 1)
            .unwrap()
            .read_texture(&gl, "hdr", 0, 0)
            .unwrap();
        let on_vk = render_with(&vk, &deferred(), &scene, &[(k, o)], 1)
            .read_texture(&vk, "hdr", 0, 0)
            .unwrap();
        let e = rmse(&on_gl, &on_vk).unwrap();
        assert!(on_gl.non_finite() == 0 && e < 0.03, "{k}={o}: GL vs Vulkan RMSE {e}");
    }
}

/// Does the segment from `a` to `b` pass through the box `half` placed by `model`?
fn segment_hits_box(a: Vec3, b: Vec3, model: Mat4, half: Vec3) -> bool {
    let inv = model.inverse();
    let (la, lb) = (inv.transform_point3(a), inv.transform_point3(b));
    let d = lb - la;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for k in 0..3 {
        if d[k].abs() < 1e-9 {
            if la[k].abs() > half[k] {
                return false;
            }
            continue;
        }
        let (mut e, mut f) = ((-half[k] - la[k]) / d[k], (half[k] - la[k]) / d[k]);
        if e > f {
            std::mem::swap(&mut e, &mut f);
        }
        t0 = t0.max(e);
        t1 = t1.min(f);
        if t0 > t1 {
            return false;
        }
    }
    // Stop short of the end point so the surface itself does not count.
    t0 < 0.999
}

#[test]
fn cornell_point_shadow_lies_where_the_tall_box_blocks_the_light() {
    let g = gpu();
    let with_box = builtin::cornell();
    let mut without = builtin::cornell();
    without.meshes.retain(|m| m.name != "tall_box");
    let mut dark = builtin::cornell();
    dark.lights[0].on = false;
    let tall = with_box.meshes.iter().find(|m| m.name == "tall_box").unwrap().transform;
    let short = with_box.meshes.iter().find(|m| m.name == "short_box").unwrap().transform;
    let (tall_half, short_half) = (Vec3::new(0.3, 0.6, 0.3), Vec3::splat(0.3));
    let light = with_box.lights[0].position;
    let cam = with_box.camera.position;
    let hdr = |scene: &Scene| render_with(&g, &deferred(), scene, &[], 1).read_texture(&g, "hdr", 0, 0).unwrap();
    let (a, b, ambient) = (hdr(&with_box), hdr(&without), hdr(&dark));
    let (mut shadow_ok, mut shadow_bad, mut lit_ok, mut lit_bad) = (0, 0, 0, 0);
    // Points on the left wall and the floor are in shadow exactly when the light's view of
    // them crosses the tall box; only points the camera sees past both boxes are compared.
    for i in 1..20 {
        for j in 1..20 {
            let (u, v) = (i as f32 / 20.0, j as f32 / 20.0);
            for p in [
                Vec3::new(-0.999, 2.0 * v, 1.0 - 2.0 * u),
                Vec3::new(2.0 * u - 1.0, 0.001, 1.0 - 2.0 * v),
            ] {
                if segment_hits_box(cam, p, tall, tall_half) || segment_hits_box(cam, p, short, short_half) {
                    continue;
                }
                let Some((x, y)) = with_box.project(p) else { continue };
                let (x, y) = (x as u32, y as u32);
                if x < 1 || y < 1 || x + 2 >= a.width || y + 2 >= a.height {
                    continue;
                }
                let at = |img: &Image| img.mean_rgb(x - 1, y - 1, x + 2, y + 2);
                // Direct light only: the ambient term is the same in all three images.
                let (da, db) = (at(&a) - at(&ambient), at(&b) - at(&ambient));
                if db < 0.005 {
                    continue; // facing away from the light: nothing to compare
                }
                if segment_hits_box(light, p, tall, tall_half) {
                    if da < 0.25 * db {
                        shadow_ok += 1
                    } else {
                        shadow_bad += 1
                    }
                } else if !segment_hits_box(light, p, short, short_half) {
                    if (da - db).abs() < 0.1 * db + 0.002 {
                        lit_ok += 1
                    } else {
                        lit_bad += 1
                    }
                }
            }
        }
    }
    // A 3×3 window straddling the shadow's edge may disagree; nearly all samples must not.
    assert!(
        shadow_ok >= 5 && shadow_bad * 10 <= shadow_ok,
        "in the tall box's shadow: {shadow_ok} dark, {shadow_bad} not"
    );
    assert!(
        lit_ok >= 50 && lit_bad * 10 <= lit_ok,
        "outside it: {lit_ok} unchanged, {lit_bad} changed"
    );
}

#[test]
fn a_device_opened_elsewhere_renders_alike() {
    // A viewer opens its device for its window and hands it over; the capability profile comes
    // from what that device has enabled (here: no optional features), not from the adapter.
    let g = gpu();
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default())).expect("an adapter");
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor::default())).expect("a device");
    let other = lightbench::gpu::Gpu::from_parts(adapter, device, queue).unwrap();
    use lightbench_compiler::profile::Feature;
    assert!(
        !other.profile.has(Feature::TimestampQuery) && !other.profile.has(Feature::Multiview),
        "{:?}",
        other.profile.features
    );
    let scene = builtin::cornell();
    let ours = output(&g, &render_with(&g, &deferred(), &scene, &[], 1));
    let ex = render_with(&other, &deferred(), &scene, &[], 1);
    assert!(
        ex.last_timings.iter().all(|t| t.gpu_ms.is_none()),
        "no timestamps without the feature"
    );
    let theirs = output(&other, &ex);
    let e = rmse(&ours, &theirs).unwrap();
    assert!(e < 0.01, "RMSE {e}");
}

/// A point light with `shadows: false` (a scene file as a user writes it) gets no shadow
/// pass — none is timed — and lights the ground as if nothing stood in its way: wherever the
/// ground is seen in both, the image equals the same scene without the box. With shadows
/// on, the box's shadow shows there.
#[test]
fn a_light_without_shadows_gets_no_shadow_pass() {
    let g = gpu();
    let d = scene_dir("noshadow", &["ground.gltf", "red_box.gltf"]);
    let scene = |shadows: bool, with_box: bool| {
        let text = format!(
            "Scene(name: \"s\", size: (64, 64), camera: (position: (0.0, 2.0, 3.0), pitch: -30.0, fov: 50.0),\n\
             models: [(path: \"ground.gltf\", scale: 0.2){}],\n\
             lights: [Point(position: (-1.0, 1.5, 0.0), intensity: 5.0, range: 8.0, shadows: {shadows})])\n",
            if with_box { ", (path: \"red_box.gltf\")" } else { "" }
        );
        let path = d.join(format!("s_{shadows}_{with_box}.ron"));
        std::fs::write(&path, text).unwrap();
        lightbench::scene::load(path.to_str().unwrap()).unwrap()
    };
    let render = |s: &Scene| {
        let ex = render_with(&g, &deferred(), s, &[], 1);
        let timed: Vec<String> = ex.last_timings.iter().map(|t| t.pass.clone()).collect();
        let out = (
            ex.read_texture(&g, "hdr", 0, 0).unwrap(),
            ex.read_texture(&g, "gbuf.depth", 0, 0).unwrap(),
        );
        (ex.plan().clone(), timed, out)
    };
    let (plan, timed, (off, depth)) = render(&scene(false, true));
    assert!(!timed.iter().any(|t| t.starts_with("shadow_cube")), "{timed:?}");
    let culled = plan.culled.iter().find(|c| c.name == "shadow_cube_classic").expect("culled");
    assert!(culled.reason.contains("no such light casts shadows"), "{}", culled.reason);
    let (_, _, (open, open_depth)) = render(&scene(false, false));
    let (_, timed_on, (on, _)) = render(&scene(true, true));
    assert!(timed_on.iter().any(|t| t == "shadow_cube_classic"), "{timed_on:?}");
    let ground: Vec<usize> = (0..64 * 64)
        .filter(|&i| depth.rgba[4 * i] < 1.0 && (depth.rgba[4 * i] - open_depth.rgba[4 * i]).abs() < 1e-6)
        .collect();
    assert!(ground.len() > 500, "{} ground pixels seen in both", ground.len());
    let diff = |a: &Image, b: &Image, i: usize| (0..3).map(|c| (a.rgba[4 * i + c] - b.rgba[4 * i + c]).abs()).fold(0.0f32, f32::max);
    let worst = ground.iter().map(|&i| diff(&off, &open, i)).fold(0.0f32, f32::max);
    assert!(worst < 2e-3, "unshadowed light vs no box: largest difference {worst}");
    let shadowed = ground.iter().filter(|&&i| diff(&on, &open, i) > 0.01).count();
    assert!(shadowed > 20, "with shadows on, {shadowed} ground pixels lie in the box's shadow");
    // A casting and a non-casting light, in either order: the caster's cube map (the only
    // instance) is found by the right light.
    let two = |first: &str, second: &str| {
        let text = format!(
            "Scene(name: \"t\", size: (64, 64), camera: (position: (0.0, 2.0, 3.0), pitch: -30.0, fov: 50.0),\n\
             models: [(path: \"ground.gltf\", scale: 0.2), (path: \"red_box.gltf\")],\n\
             lights: [{first}, {second}])\n"
        );
        let path = d.join(format!("two_{}.ron", first.len()));
        std::fs::write(&path, text).unwrap();
        let s = lightbench::scene::load(path.to_str().unwrap()).unwrap();
        let ex = render_with(&g, &deferred(), &s, &[], 1);
        assert_eq!(ex.plan().resource("shadow.cube").unwrap().instances, 1);
        ex.read_texture(&g, "hdr", 0, 0).unwrap()
    };
    let caster = "Point(position: (-1.0, 1.5, 0.0), intensity: 5.0, range: 8.0)";
    let plain = "Point(position: (1.0, 1.5, 0.5), intensity: 2.0, range: 8.0, shadows: false)";
    let (a, b) = (two(caster, plain), two(plain, caster));
    let e = rmse(&a, &b).unwrap();
    assert!(e < 1e-4, "light order changed the image: RMSE {e}");
}

/// Cube shadows with `cube.pcf` soften their edges the same way under every cube-shadow
/// option; `cube.normal_offset_texels` (2 texels by default) removes the acne that no bias leaves.
#[test]
fn cube_shadow_pcf_and_normal_offset() {
    let g = gpu();
    let scene = builtin::cornell();
    let p = deferred();
    let hdr_with = |variant: &str, params: &[(&str, lightbench_compiler::ir::ParamValue)]| {
        let v = [("cube_shadow".to_string(), variant.to_string())];
        let (exe, _) = lightbench::render::compile(&g, &p, None, &scene, &v).unwrap();
        let params: Vec<(String, lightbench_compiler::ir::ParamValue)> = params.iter().map(|(k, v)| (k.to_string(), v.clone())).collect();
        lightbench::render::render_with(&g, &exe, &scene, 1, &params)
            .unwrap()
            .read_texture(&g, "hdr", 0, 0)
            .unwrap()
    };
    use lightbench_compiler::ir::ParamValue::{Bool, Float};
    let hard = hdr_with("classic", &[]);
    let soft = hdr_with("classic", &[("cube.pcf", Bool(true))]);
    let changed = (0..hard.rgba.len() / 4)
        .filter(|&i| (hard.rgba[4 * i] - soft.rgba[4 * i]).abs() > 1e-3)
        .count();
    assert!(
        changed > 20 && changed < hard.rgba.len() / 4 / 4,
        "PCF changes shadow edges only: {changed} pixels"
    );
    for v in ["multiview", "instanced"] {
        let e = rmse(&soft, &hdr_with(v, &[("cube.pcf", Bool(true))])).unwrap();
        eprintln!("pcf: classic vs {v} RMSE {e}");
        assert!(e < 0.02, "pcf: classic vs {v} RMSE {e}");
    }
    let acne = |img: &Image| {
        (0..hard.rgba.len() / 4)
            .filter(|&i| img.rgba[4 * i] < hard.rgba[4 * i] * 0.9)
            .count()
    };
    let unbiased = hdr_with(
        "classic",
        &[("cube.bias_texels", Float(0.0)), ("cube.normal_offset_texels", Float(0.0))],
    );
    let offset = hdr_with("classic", &[("cube.bias_texels", Float(0.0))]);
    eprintln!(
        "pixels darker than the biased image by 10%: bias 0 {}, bias 0 + normal offset {}",
        acne(&unbiased),
        acne(&offset)
    );
    assert!(
        acne(&offset) * 4 < acne(&unbiased).max(1),
        "{} vs {}",
        acne(&offset),
        acne(&unbiased)
    );
}
