//! A researcher's own model: rendered directly (`--scene model.glb`), framed and lit by
//! rule; exposed for what was drawn, not for the empty background; exposure by hand with
//! `--param`.

use crate::cli_common;
use crate::gpu_common;

use cli_common::{lightbench, scratch};
use gpu_common::*;
use lightbench::scene::{self, builtin, export};
use std::path::Path;

/// Pack a `.gltf` + `.bin` pair as one binary `.glb` (glTF 2.0 §4.4: header, JSON chunk
/// padded with spaces, BIN chunk padded with zeros).
fn pack_glb(gltf: &Path, bin: &Path, out: &Path) {
    let mut doc: serde_json::Value = serde_json::from_slice(&std::fs::read(gltf).unwrap()).unwrap();
    let mut data = std::fs::read(bin).unwrap();
    doc["buffers"] = serde_json::json!([{"byteLength": data.len()}]);
    let mut json = serde_json::to_vec(&doc).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    while !data.len().is_multiple_of(4) {
        data.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + data.len();
    let mut glb = vec![];
    glb.extend(b"glTF");
    glb.extend(2u32.to_le_bytes());
    glb.extend((total as u32).to_le_bytes());
    glb.extend((json.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(json);
    glb.extend((data.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(data);
    std::fs::write(out, glb).unwrap();
}

#[test]
fn a_glb_model_renders_framed_from_the_command_line() {
    let d = scratch("glb");
    let mut box_only = builtin::cornell();
    box_only.lights.clear(); // no KHR lights: the default rig lights it
    export::export(&box_only, &d.join("box.gltf")).unwrap();
    pack_glb(&d.join("box.gltf"), &d.join("box.bin"), &d.join("box.glb"));
    let out = d.join("box.png");
    let (code, _, err) = lightbench(&[
        "render",
        "--scene",
        d.join("box.glb").to_str().unwrap(),
        "--size",
        "96x64",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let img = lightbench::io::Image::load_png(&out).unwrap();
    assert_eq!((img.width, img.height), (96, 64));
    // Framed: the model fills the middle, and the image is not flat.
    let centre = img.mean_rgb(40, 24, 56, 40);
    let (left, right) = (img.mean_rgb(8, 8, 40, 56), img.mean_rgb(56, 8, 88, 56));
    assert!(centre > 0.05, "the model is in the middle of the frame: {centre}");
    assert!(
        (left - right).abs() > 0.01 || (centre - left).abs() > 0.02,
        "not uniform: {left} {centre} {right}"
    );
    // The same scene through the library: the framing rule and the default rig.
    let s = scene::load(d.join("box.glb").to_str().unwrap()).unwrap();
    let (lo, hi) = s.bounds();
    let centre = (lo + hi) * 0.5;
    let to_centre = (centre - s.camera.position).normalize();
    assert!(to_centre.dot(s.camera.forward()) > 0.999, "the camera looks at the bounds' centre");
    assert!(s.camera.near > 0.0 && s.camera.near < (centre - s.camera.position).length() - (hi - lo).length() * 0.5);
    assert_eq!(s.lights.len(), 2, "key and fill");
    assert!(s.lights[0].shadows && !s.lights[1].shadows);
}

#[test]
fn a_model_with_its_own_lights_keeps_them_and_a_missing_one_is_named() {
    let d = scratch("own");
    export::export(&builtin::cornell(), &d.join("lit.gltf")).unwrap();
    let s = scene::load(d.join("lit.gltf").to_str().unwrap()).unwrap();
    assert_eq!(s.lights.len(), 1, "the model's KHR point light, no rig");
    let (code, _, err) = lightbench(&["check", "pipelines/deferred.ron", "--scene", d.join("nope.glb").to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("error[model-load]") && err.contains("<--scene>:1:1"), "{err}");
}

/// Log-average (geometric mean) linear luminance of the LDR output where something was drawn
/// (depth < 1), the fraction of those pixels clipped to white, and their count.
fn drawn_luminance(g: &lightbench::gpu::Gpu, ex: &lightbench::gpu::Executor) -> (f32, f32, usize) {
    let img = output(g, ex);
    let depth = ex.read_texture(g, "gbuf.depth", 0, 0).unwrap();
    let lin = img.linear();
    let (mut sum, mut clipped, mut n) = (0.0f32, 0, 0);
    for i in 0..(img.width * img.height) as usize {
        if depth.rgba[i * 4] < 1.0 {
            let l = 0.2126 * lin[i * 4] + 0.7152 * lin[i * 4 + 1] + 0.0722 * lin[i * 4 + 2];
            sum += (1e-4 + l).ln();
            clipped += (lin[i * 4..i * 4 + 3].iter().any(|c| *c >= 0.999)) as usize;
            n += 1;
        }
    }
    ((sum / n.max(1) as f32).exp(), clipped as f32 / n.max(1) as f32, n)
}

/// Exposure puts the drawn pixels' log-average at the key (0.18). With the simple operator
/// L / (1 + L) that displays as about 0.18 / 1.18 ≈ 0.15: a lone object's displayed
/// log-average must be within a factor of 2 of that, with (almost) nothing clipped. The
/// default operator's white point maps the brightest drawn pixel to white by design, so
/// there only most of the object must stay below white. (Averaging the black background
/// too, as before, exposed the chair ~390× too bright: every pixel white.)
#[test]
fn a_lone_object_is_exposed_for_itself_not_the_background() {
    let g = gpu();
    let chair = scene::load(root().join("scenes/chair.gltf").to_str().unwrap()).unwrap();
    let ex = render_with(&g, &deferred(), &chair, &[("tonemap", "simple")], 1);
    let (mean, clipped, n) = drawn_luminance(&g, &ex);
    assert!(n > 500 && n < 128 * 128 / 2, "the chair covers part of the frame: {n} pixels");
    let target = 0.18 / 1.18;
    assert!(
        mean > target / 2.0 && mean < target * 2.0,
        "object log-average luminance {mean} vs {target}"
    );
    assert!(clipped < 0.02, "{:.1}% of the object clipped", clipped * 100.0);
    let ex = render_with(&g, &deferred(), &chair, &[], 1);
    let (mean, clipped, _) = drawn_luminance(&g, &ex);
    assert!(
        mean < 0.8 && clipped < 0.25,
        "white point operator: log-average {mean}, {:.0}% white",
        clipped * 100.0
    );
}

/// In the Cornell box almost every pixel is drawn: the background rule changes the exposure
/// by little, and the GPU's reduction agrees with the rule computed here.
#[test]
fn a_filled_frame_is_exposed_as_before_and_manual_exposure_works() {
    let g = gpu();
    let mut ex = render_with(&g, &deferred(), &builtin::cornell(), &[], 1);
    let hdr = ex.read_texture(&g, "hdr", 0, 0).unwrap();
    let depth = ex.read_texture(&g, "gbuf.depth", 0, 0).unwrap();
    let (mut all, mut drawn, mut n) = (0.0f64, 0.0f64, 0usize);
    for i in 0..(hdr.width * hdr.height) as usize {
        let p = &hdr.rgba[i * 4..i * 4 + 3];
        // The tone value: each pixel's largest channel (lib/luminance.wgsl).
        let l = (1e-4 + p[0].max(p[1]).max(p[2])).ln() as f64;
        all += l;
        if depth.rgba[i * 4] < 1.0 {
            drawn += l;
            n += 1;
        }
    }
    let pixels = (hdr.width * hdr.height) as f64;
    let (avg_all, avg_drawn) = ((all / pixels).exp(), (drawn / n as f64).exp());
    let lum = ex.read_buffer(&g, "lum", 0).unwrap();
    assert!((lum[0] as f64 / avg_drawn - 1.0).abs() < 0.01, "GPU {} vs CPU {avg_drawn}", lum[0]);
    assert!(
        (avg_drawn / avg_all - 1.0).abs() < 0.25,
        "background rule: {avg_all} -> {avg_drawn}"
    );
    assert!(
        (lum[2] - 0.18 / lum[0]).abs() < 1e-3 * lum[2],
        "automatic exposure = key / Lavg: {lum:?}"
    );
    // Manual exposure: 2^ev, whatever the image.
    ex.set_param("exposure.automatic", lightbench_compiler::ir::ParamValue::Bool(false))
        .unwrap();
    ex.set_param("exposure.ev", lightbench_compiler::ir::ParamValue::Float(-1.5))
        .unwrap();
    ex.render_frame(&g, &ex.inputs(0.0)).unwrap();
    let lum = ex.read_buffer(&g, "lum", 0).unwrap();
    assert!((lum[2] - 2f32.powf(-1.5)).abs() < 1e-5, "{lum:?}");
}

/// The README's vector form (`--param ambient.color=0.1,0.1,0.12`), as written, against a
/// stronger ambient: both render, and more ambient light is a brighter image.
#[test]
fn the_readme_vector_param_renders() {
    let d = scratch("param-vec");
    let mut means = vec![];
    for (name, value) in [("readme", "0.1,0.1,0.12"), ("strong", "0.8,0.8,0.8")] {
        let out = d.join(format!("{name}.png"));
        let ambient = format!("ambient.color={value}");
        let args = [
            "render",
            "--param",
            "exposure.automatic=false",
            "--param",
            &ambient,
            "--out",
            out.to_str().unwrap(),
        ];
        let (code, _, err) = lightbench(&args);
        assert_eq!(code, 0, "{err}");
        means.push(lightbench::io::Image::load_png(&out).unwrap().mean_rgb(0, 0, 128, 128));
    }
    assert!(means[1] > means[0] * 1.2, "{means:?}");
    let (code, _, err) = lightbench(&[
        "render",
        "--param",
        "ambient.color=0.1,0.1",
        "--out",
        d.join("x.png").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("ambient.color"), "{err}");
}

#[test]
fn params_from_the_command_line_reach_the_frame_and_the_manifest() {
    let d = scratch("param");
    let (dark, bright) = (d.join("dark.png"), d.join("bright.png"));
    let manifest = d.join("m.json");
    for (out, ev) in [(&dark, "-3"), (&bright, "1")] {
        let args = [
            "render",
            "--param",
            "exposure.automatic=false",
            "--param",
            &format!("exposure.ev={ev}"),
            "--out",
            out.to_str().unwrap(),
            "--manifest",
            manifest.to_str().unwrap(),
        ];
        let (code, _, err) = lightbench(&args);
        assert_eq!(code, 0, "{err}");
    }
    let mean = |p: &Path| lightbench::io::Image::load_png(p).unwrap().mean_rgb(0, 0, 128, 128);
    assert!(mean(&bright) > 2.0 * mean(&dark), "{} vs {}", mean(&bright), mean(&dark));
    let m: serde_json::Value = serde_json::from_slice(&std::fs::read(&manifest).unwrap()).unwrap();
    let ev = m["params"].as_array().unwrap().iter().find(|p| p["name"] == "exposure.ev").unwrap();
    assert_eq!(
        ev["value"],
        serde_json::json!({"Float": 1.0}),
        "the manifest records the value used"
    );
    for (arg, msg) in [
        ("exposure.evv=1", "no such parameter (did you mean `exposure.ev`?)"),
        ("exposure.ev=99", "99 is above its max 30"),
        ("exposure.ev=bright", "`bright` is not a number"),
    ] {
        let (code, _, err) = lightbench(&["render", "--param", arg, "--out", d.join("x.png").to_str().unwrap()]);
        assert_eq!(code, 2, "{arg}: {err}");
        assert!(err.contains(msg), "{arg}: {err}");
    }
}

/// `--out x.exr` holds the linear image before tone mapping (values above 1 where a light
/// is strong); the PNG of the same frame is the tone-mapped output.
#[test]
fn exr_output_is_linear_hdr_and_png_is_tone_mapped() {
    let d = scratch("exr");
    let scene = d.join("bright.ron");
    std::fs::write(
        &scene,
        "Scene(builtin: \"cornell\", lights: [Point(position: (0.0, 1.0, 0.0), intensity: 40.0, range: 6.0)])\n",
    )
    .unwrap();
    let (exr, png) = (d.join("x.exr"), d.join("x.png"));
    for out in [&exr, &png] {
        let (code, _, err) = lightbench(&["render", "--scene", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
        let expected = if out == &exr { "(hdr," } else { "(ldr," };
        assert!(err.contains(expected), "{err}");
    }
    let hdr = image::open(&exr).unwrap().to_rgba32f();
    let max = hdr.pixels().flat_map(|p| p.0[..3].to_vec()).fold(0.0f32, f32::max);
    assert!(max > 1.0, "bright pixels stay above 1 in the EXR: max {max}");
    let ldr = image::open(&png).unwrap().to_rgba8();
    assert!(ldr.pixels().any(|p| p.0[0] > 200), "the PNG is tone-mapped, not black");
}

/// The Cornell box exported and re-imported at scales 0.001, 1 and 1000 (camera and the
/// model's light scaled with it) renders the same image, shadows included: shadow planes
/// follow the light's range, the directional fit follows the bounds, and attenuation is
/// scale-free.
#[test]
fn the_cornell_box_renders_alike_at_any_scale() {
    let d = scratch("scale");
    export::export(&builtin::cornell(), &d.join("box.gltf")).unwrap();
    let g = gpu();
    let mut images = vec![];
    for s in [0.001f32, 1.0, 1000.0] {
        let file = d.join(format!("box_{s}.ron"));
        let text = format!(
            "Scene(\n    size: (64, 64),\n    camera: (position: (0.0, {}, {}), fov: 40.0, near: {}, far: {}),\n    models: [(path: \"box.gltf\", scale: {s})],\n    effects: [Shadows],\n)\n",
            1.0 * s,
            3.6 * s,
            0.05 * s,
            20.0 * s
        );
        std::fs::write(&file, text).unwrap();
        let scene = scene::load(file.to_str().unwrap()).unwrap();
        assert_eq!(scene.lights.len(), 1);
        let img = output(&g, &render_with(&g, &deferred(), &scene, &[], 1));
        assert_eq!(img.non_finite(), 0, "scale {s}");
        images.push((s, scene, img));
    }
    for (s, _, img) in &images {
        let e = lightbench::io::rmse(img, &images[1].2).unwrap();
        assert!(e < 0.01, "scale {s} differs from scale 1: RMSE {e}");
    }
    // Shadows are there at the largest scale: turning them off changes the image.
    let (_, scene, shadowed) = &images[2];
    let mut unshadowed = scene.clone();
    unshadowed.lights[0].shadows = false;
    let img = output(&g, &render_with(&g, &deferred(), &unshadowed, &[], 1));
    let e = lightbench::io::rmse(&img, shadowed).unwrap();
    assert!(e > 0.02, "shadows at scale 1000: RMSE to unshadowed {e}");
}
