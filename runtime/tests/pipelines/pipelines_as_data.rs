//! New behaviour from pipeline files and shaders alone, no Rust: a grayscale post pass added
//! to the deferred pipeline, history resources kept by ping-pong, compute dispatches sized
//! from a resource.

use crate::cli_common;
use crate::gpu_common;

use gpu_common::*;
use lightbench::scene::builtin;
use std::path::{Path, PathBuf};

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            copy_dir(&p, &to.join(p.file_name().unwrap()));
        } else {
            std::fs::copy(&p, to.join(p.file_name().unwrap())).unwrap();
        }
    }
}

fn project(tag: &str) -> PathBuf {
    let d = cli_common::scratch(tag);
    copy_dir(&root().join("shaders"), &d.join("shaders"));
    std::fs::create_dir_all(d.join("pipelines")).unwrap();
    // The bundled pipelines' data file (the area lights' LTC table), read beside them.
    let table = "pipelines/ltc_blinn_phong.json";
    std::fs::copy(root().join(table), d.join(table)).unwrap();
    d
}

const GRAY: &str = "// Grayscale post pass: Rec. 709 luma of the tone-mapped image.
@group(2) @binding(0) var ldr: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(ldr, vec2<i32>(pos.xy), 0);
    let y = dot(c.rgb, vec3<f32>(0.2126, 0.7152, 0.0722));
    return vec4<f32>(y, y, y, 1.0);
}
";

#[test]
fn a_grayscale_post_pass_needs_no_rust() {
    let d = project("gray");
    std::fs::write(d.join("shaders/gray.wgsl"), GRAY).unwrap();
    let base = std::fs::read_to_string(deferred()).unwrap();
    let text = base
        .replace("        \"ldr\": Texture(format: Rgba8UnormSrgb, size: Viewport),", "        \"ldr\": Texture(format: Rgba8UnormSrgb, size: Viewport),\n        \"gray\": Texture(format: Rgba8Unorm, size: Viewport),")
        .replace("    ],\n    variants:", "        Fullscreen(name: \"grayscale\", shader: \"gray.wgsl\", reads: [\"ldr\"], color: [\"gray\"]),\n    ],\n    variants:")
        .replace("    output: \"ldr\",", "    output: \"gray\",");
    assert_ne!(text, base);
    let pipeline = d.join("pipelines/gray.ron");
    std::fs::write(&pipeline, text).unwrap();
    let g = gpu();
    let scene = builtin::cornell();
    let ex = render_with(&g, &pipeline, &scene, &[], 1);
    assert_eq!(ex.plan().passes.last().unwrap().name, "grayscale");
    let img = output(&g, &ex);
    let mut lo = f32::MAX;
    let mut hi = f32::MIN;
    for y in 0..img.height {
        for x in 0..img.width {
            let [r, g_, b, _] = img.pixel(x, y);
            assert!(
                (r - g_).abs() < 1.5 / 255.0 && (r - b).abs() < 1.5 / 255.0,
                "pixel ({x}, {y}) is not gray: {r} {g_} {b}"
            );
            lo = lo.min(r);
            hi = hi.max(r);
        }
    }
    assert!(hi - lo > 0.3, "the image has content: {lo}..{hi}");
    // The red wall is darker in luma than the white back wall.
    let (wall, back) = (img.mean_rgb(4, 60, 10, 70), img.mean_rgb(60, 40, 68, 48));
    assert!(wall < back, "{wall} {back}");
}

const TEMPORAL: &str = r#"Pipeline(
    name: "temporal",
    params: { "step": Float(default: 0.125, min: 0.0, max: 1.0) },
    resources: {
        "acc": Texture(format: Rgba16Float, size: Fixed(8, 8), history: true),
        "ramp": Texture(format: Rgba16Float, size: Fixed(16, 8)),
        "out": Texture(format: Rgba8Unorm, size: Fixed(8, 8)),
    },
    passes: [
        Fullscreen(name: "accumulate", shader: "accumulate.wgsl", reads: [Prev("acc")], color: ["acc"], params: ["step"]),
        Compute(name: "ramp", shader: "ramp.wgsl", writes: ["ramp"], dispatch: Size("ramp")),
        Fullscreen(name: "show", shader: "show.wgsl", reads: ["acc", "ramp"], color: ["out"]),
    ],
    output: "out",
)
"#;

#[test]
fn history_ping_pong_and_sized_dispatch() {
    let d = project("temporal");
    std::fs::write(
        d.join("shaders/accumulate.wgsl"),
        "struct Params { step: f32 };\n@group(0) @binding(0) var acc_prev: texture_2d<f32>;\n@group(0) @binding(1) var<uniform> params: Params;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    return textureLoad(acc_prev, vec2<i32>(p.xy), 0) + vec4<f32>(params.step);\n}\n",
    )
    .unwrap();
    std::fs::write(
        d.join("shaders/ramp.wgsl"),
        "@group(0) @binding(0) var ramp: texture_storage_2d<rgba16float, write>;\n@compute @workgroup_size(8, 8, 1)\nfn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {\n    textureStore(ramp, id.xy, vec4<f32>(f32(id.x) / 16.0, f32(id.y) / 8.0, 0.0, 1.0));\n}\n",
    )
    .unwrap();
    std::fs::write(
        d.join("shaders/show.wgsl"),
        "@group(0) @binding(0) var acc: texture_2d<f32>;\n@group(0) @binding(1) var ramp: texture_2d<f32>;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    let i = vec2<i32>(p.xy);\n    return vec4<f32>(textureLoad(acc, i, 0).r, textureLoad(ramp, i * 2, 0).r, 0.0, 1.0);\n}\n",
    )
    .unwrap();
    let pipeline = d.join("pipelines/temporal.ron");
    std::fs::write(&pipeline, TEMPORAL).unwrap();
    let g = gpu();
    let scene = builtin::cornell();
    let ex = render_with(&g, &pipeline, &scene, &[], 3);
    let acc = ex.read_texture(&g, "acc", 0, 0).unwrap();
    for (x, y) in [(0, 0), (7, 7), (3, 5)] {
        assert!(
            (acc.pixel(x, y)[0] - 0.375).abs() < 1e-3,
            "three frames of 0.125: {:?}",
            acc.pixel(x, y)
        );
    }
    // Size("ramp") dispatched 2×1 groups of 8×8: every texel of the 16×8 target written.
    let ramp = ex.read_texture(&g, "ramp", 0, 0).unwrap();
    for (x, y) in [(0u32, 0u32), (15, 7), (9, 3)] {
        let px = ramp.pixel(x, y);
        assert!(
            (px[0] - x as f32 / 16.0).abs() < 1e-3 && (px[1] - y as f32 / 8.0).abs() < 1e-3,
            "({x}, {y}): {px:?}"
        );
    }
}

/// A pass rendering at half the output size finds its own size in `instance.target_size`
/// (the frame block's `resolution` is the output size): its UVs span 0..1.
#[test]
fn a_half_size_pass_knows_its_target_size() {
    let d = project("half");
    std::fs::write(
        d.join("shaders/uv.wgsl"),
        "#include \"lib/frame.wgsl\"\n\n@fragment\nfn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {\n    let uv = pos.xy * instance.target_size.zw;\n    let out_uv = pos.xy * frame.resolution.zw;\n    return vec4<f32>(uv, out_uv.x, 1.0);\n}\n",
    )
    .unwrap();
    let pipeline = d.join("pipelines/half.ron");
    std::fs::write(
        &pipeline,
        "Pipeline(\n    name: \"half\",\n    resources: {\"half\": Texture(format: Rgba16Float, size: Viewport(0.5))},\n    passes: [Fullscreen(name: \"uv\", shader: \"uv.wgsl\", color: [\"half\"])],\n    output: \"half\",\n)\n",
    )
    .unwrap();
    let g = gpu();
    let mut scene = builtin::cornell();
    scene.size = (64, 64);
    let ex = render_with(&g, &pipeline, &scene, &[], 1);
    let img = output(&g, &ex);
    assert_eq!((img.width, img.height), (32, 32));
    let p = img.pixel(31, 31);
    assert!(
        (p[0] - 31.5 / 32.0).abs() < 1e-3 && (p[1] - 31.5 / 32.0).abs() < 1e-3,
        "target UV: {p:?}"
    );
    assert!(
        (p[2] - 31.5 / 64.0).abs() < 1e-3,
        "the frame's resolution is the output size: {p:?}"
    );
}

/// External resources are filled from files (`render --input`): a JSON buffer and a PNG
/// texture reach the shader as stored; a missing input or a wrong size is an error naming the
/// resource, never a frame of zeros.
#[test]
fn external_resources_come_from_inputs_or_the_render_stops() {
    let d = project("inputs");
    let pipeline = external_inputs_pipeline(&d.join("pipelines"), &d.join("shaders"));
    std::fs::write(d.join("w.json"), "[0.25, 0.5, 0.75, 1.0]").unwrap();
    image::RgbaImage::from_pixel(4, 4, image::Rgba([0, 128, 255, 255]))
        .save(d.join("noise.png"))
        .unwrap();
    let out = d.join("x.exr");
    let (p, o) = (pipeline.to_str().unwrap(), out.to_str().unwrap());
    let w = format!("weights={}", d.join("w.json").display());
    let n = format!("noise={}", d.join("noise.png").display());
    let base = ["render", "--pipeline", p, "--size", "4x4", "--out", o];
    let with = |extra: &[&str]| cli_common::lightbench(&[&base[..], extra].concat());
    let (code, _, err) = with(&["--input", &w, "--input", &n]);
    assert_eq!(code, 0, "{err}");
    let img = image::open(&out).unwrap().to_rgba32f();
    assert_eq!(img.get_pixel(0, 0).0, [0.25, 0.5, 0.75, 1.0], "the buffer as written");
    let t = img.get_pixel(3, 0).0;
    assert!(
        t[0] == 0.0 && (t[1] - 128.0 / 255.0).abs() < 1e-3 && t[2] == 1.0,
        "the texture as stored: {t:?}"
    );
    let (code, _, err) = with(&["--input", &w]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("resource `noise` is external: supply its contents (render --input noise=FILE"),
        "{err}"
    );
    // A file whose content does not fit is bad input (exit 1); a name on the command line
    // that is not an external resource is bad usage (exit 2).
    std::fs::write(d.join("w.json"), "[0.25, 0.5]").unwrap();
    let (code, _, err) = with(&["--input", &w, "--input", &n]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("has 8 bytes, the buffer is declared with 16"), "{err}");
    std::fs::write(d.join("w.json"), "[0.25, 0.5, 1e39, 1.0]").unwrap();
    let (code, _, err) = with(&["--input", &w, "--input", &n]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("element 2 (1e39) is not a finite 32-bit float"), "{err}");
    let (code, _, err) = with(&["--input", "out=x.png"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--input `out`: the resource is not `external: true`"), "{err}");
}
