//! The two G-buffer layouts of `pipelines/deferred.ron` (variant `gbuffer`, seed 003 §3.1,
//! §5.2): packed (normal in 2 × 16-bit fixed point, eq. 3.1–3.3; position from depth) and fat
//! (world normal in half floats, world position stored) light the scene alike, and the packed
//! normals decode finite and unit length everywhere, facing away from the camera included.

use crate::gpu_common;

use glam::{Mat4, Vec3};
use gpu_common::*;
use lightbench::gpu::Gpu;
use lightbench::io::{rmse, Image};
use lightbench::scene::geometry::{quad, sphere};
use lightbench::scene::{builtin, Scene};
use lightbench_compiler::workspace::Workspace;

fn hdr(g: &Gpu, scene: &Scene, variants: &[(&str, &str)]) -> Image {
    let ex = render_with(g, &deferred(), scene, variants, 1);
    for (v, o) in variants {
        let chosen = &ex.plan().variants.iter().find(|c| c.variant == *v).unwrap().option;
        assert_eq!(chosen, o, "{v}={o} ran as {chosen}");
    }
    ex.read_texture(g, "hdr", 0, 0).unwrap()
}

fn relative_rmse(reference: &Image, other: &Image) -> f64 {
    let mean = reference.rgba.chunks(4).map(|p| (p[0] + p[1] + p[2]) as f64 / 3.0).sum::<f64>() / (reference.rgba.len() / 4) as f64;
    rmse(reference, other).unwrap() / mean
}

/// The Cornell box with a sphere (normals all round, grazing at its outline) and a panel whose
/// normals point straight away from the camera though it faces it (n = (0, 0, -1) in view
/// space: where eq. 3.1 divides by zero).
fn normals_scene() -> Scene {
    let mut scene = builtin::cornell();
    scene.size = (64, 64);
    scene
        .meshes
        .push(mesh("ball", sphere(0.3, 12, 16), Mat4::from_translation(Vec3::new(0.4, 1.3, 0.3))));
    let (mut vs, mut is) = (vec![], vec![]);
    quad(Vec3::new(-0.45, 1.45, 0.4), Vec3::X * 0.2, Vec3::Y * 0.2, &mut vs, &mut is);
    for v in &mut vs {
        v.normal = [0.0, 0.0, -1.0];
    }
    scene.meshes.push(mesh("away", (vs, is), Mat4::IDENTITY));
    scene
}

#[test]
fn packed_and_fat_layouts_light_alike() {
    let g = gpu();
    for scene in [
        builtin::cornell(),
        colonnade_with_point_light(),
        builtin::many_lights(10),
        normals_scene(),
    ] {
        for model in ["deferred_fullscreen", "deferred_volumes"] {
            let packed = hdr(&g, &scene, &[("gbuffer", "packed"), ("lighting", model)]);
            let fat = hdr(&g, &scene, &[("gbuffer", "fat"), ("lighting", model)]);
            assert!(
                fat.rgba.iter().chain(&packed.rgba).all(|v| v.is_finite()),
                "{}: NaN/Inf",
                scene.name
            );
            let e = relative_rmse(&fat, &packed);
            eprintln!("{} ({model}): fat vs packed relative RMSE {e:.5}", scene.name);
            // Positions from depth against stored ones, 16-bit fixed-point normals against
            // half floats: a fraction of a percent of the mean radiance.
            assert!(e < 0.01, "{} ({model}): fat vs packed relative RMSE {e}", scene.name);
        }
    }
}

/// The packed normals as the lighting passes decode them (`load_surface` of
/// lib/gbuffer.wgsl, run by a pass written for the test), against the fat layout's half-float
/// world normals of the same pixels.
#[test]
fn packed_normals_decode_finite_and_unit_length_everywhere() {
    let g = gpu();
    let vfs = memory_project();
    vfs.write(
        "mem/pipelines/decode.lbp",
        "pipeline decode\n\
         texture gbuf.normal: Rgba16Uint viewport\n\
         texture gbuf.fat_normal: Rgba16Float viewport\n\
         texture gbuf.albedo: Rgba8Unorm viewport\n\
         texture gbuf.emissive: Rgba16Float viewport\n\
         texture gbuf.depth: Depth32Float viewport\n\
         texture fat.depth: Depth32Float viewport\n\
         texture fat.albedo: Rgba8Unorm viewport\n\
         texture fat.emissive: Rgba16Float viewport\n\
         texture decoded: Rgba32Float viewport\n\
         texture fat_copy: Rgba32Float viewport\n\
         raster packed \"gbuffer.wgsl\" {\n    color gbuf.normal, gbuf.albedo, gbuf.emissive\n    depth gbuf.depth\n}\n\
         raster fat \"gbuffer.wgsl\" {\n    fragment fs_fat\n    color gbuf.fat_normal, fat.albedo, fat.emissive\n    depth fat.depth\n}\n\
         fullscreen decode \"decode.wgsl\" {\n    reads gbuf.depth, gbuf.normal, gbuf.albedo, gbuf.fat_normal\n    color decoded, fat_copy\n}\n\
         output decoded\n",
    );
    vfs.write(
        "mem/shaders/decode.wgsl",
        "#include \"lib/frame.wgsl\"\n#include \"lib/gbuffer.wgsl\"\n\nstruct Out {\n    @location(0) decoded: vec4<f32>,\n    @location(1) fat: vec4<f32>,\n};\n\n\
         @fragment\nfn fs_main(@builtin(position) pos: vec4<f32>) -> Out {\n    let s = load_surface(vec2<i32>(pos.xy));\n    \
         return Out(vec4<f32>(s.n, select(0.0, 1.0, s.covered)), textureLoad(gbuf_fat_normal, vec2<i32>(pos.xy), 0));\n}\n",
    );
    let scene = normals_scene();
    let ws = Workspace::new(vfs);
    let pipeline = std::path::Path::new("mem/pipelines/decode.lbp");
    let (exe, report) = lightbench::render::compile_in(&ws, &g, pipeline, None, &scene, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert!(!report.contains("error"), "{report}");
    let ex = lightbench::render::render(&g, &exe, &scene, 1).unwrap();
    let decoded = ex.read_texture(&g, "decoded", 0, 0).unwrap();
    let fat = ex.read_texture(&g, "fat_copy", 0, 0).unwrap();
    let view = scene.camera.view();
    let (mut covered, mut away, mut worst) = (0, 0, 0.0f32);
    for (d, f) in decoded.rgba.chunks(4).zip(fat.rgba.chunks(4)) {
        let n = Vec3::new(d[0], d[1], d[2]);
        assert!(n.is_finite(), "a decoded normal is not finite: {n}");
        assert!(
            (n.length() - 1.0).abs() < 1e-4,
            "a decoded normal is not unit length: {n} ({})",
            n.length()
        );
        if d[3] > 0.5 {
            covered += 1;
            let reference = Vec3::new(f[0], f[1], f[2]).normalize();
            worst = worst.max(n.angle_between(reference));
            away += (view.transform_vector3(reference).z < -0.99) as u32;
        }
    }
    eprintln!("{covered} covered pixels, {away} facing away; worst angle to the half-float normal {worst:.5} rad");
    assert!(covered > 1000 && away > 20, "{covered} covered, {away} facing away");
    // Half floats carry 11 bits, the fixed point 16: the difference is the half floats'.
    assert!(worst < 2e-3, "worst angle {worst}");
}
