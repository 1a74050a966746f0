//! The pipeline language's part 2, driven as a user writes it (LBP files and WGSL, no
//! Rust): per-pass values, data resources, mip chains, reuse of unchanged work, temporal
//! inputs. Small images, asserted on pixels.

mod cli_common;
mod gpu_common;

use gpu_common::*;
use lightbench::scene::builtin;
use std::path::{Path, PathBuf};

/// A scratch project: the bundled shaders (for `lib/`), and the given files.
fn project(tag: &str, files: &[(&str, &str)]) -> PathBuf {
    let d = cli_common::scratch(tag);
    std::fs::create_dir_all(d.join("shaders")).unwrap();
    std::fs::create_dir_all(d.join("pipelines")).unwrap();
    for e in std::fs::read_dir(root().join("shaders/lib")).unwrap() {
        let p = e.unwrap().path();
        std::fs::create_dir_all(d.join("shaders/lib")).unwrap();
        std::fs::copy(&p, d.join("shaders/lib").join(p.file_name().unwrap())).unwrap();
    }
    for (name, text) in files {
        std::fs::write(d.join(name), text).unwrap();
    }
    d
}

fn render_out(pipeline: &Path, frames: u32) -> (lightbench::io::Image, lightbench::gpu::Executor) {
    let g = gpu();
    let ex = render_with(&g, pipeline, &builtin::cornell(), &[], frames);
    (output(&g, &ex), ex)
}

/// A pattern with detail in both directions: impulses on a lattice, ramps in g and b.
const PATTERN: &str = "@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<u32>(pos.xy);
    let spike = select(0.0, 1.0, (p.x * 7u + p.y * 3u) % 5u == 0u);
    return vec4<f32>(spike, pos.x / 32.0, pos.y / 32.0, 1.0);
}
";

/// A box blur along `dir` with `taps` texels on each side.
const BLUR: &str = "struct Params { dir: vec2<f32>, taps: u32 };
@group(2) @binding(0) var input: texture_2d<f32>;
@group(2) @binding(1) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let d = vec2<i32>(params.dir);
    let n = i32(params.taps);
    var sum = vec4<f32>(0.0);
    for (var i = -n; i <= n; i++) {
        sum += textureLoad(input, clamp(vec2<i32>(pos.xy) + d * i, vec2<i32>(0), vec2<i32>(31)), 0);
    }
    return sum / f32(2 * n + 1);
}
";

fn hand_written_blur(dir: &str) -> String {
    BLUR.replace("struct Params { dir: vec2<f32>, taps: u32 };\n", "")
        .replace("@group(2) @binding(1) var<uniform> params: Params;\n", "")
        .replace("vec2<i32>(params.dir)", &format!("vec2<i32>({dir})"))
        .replace("i32(params.taps)", "3")
}

const BLUR_HEAD: &str = "pipeline blur
texture src: Rgba16Float 32x32
texture tmp: Rgba16Float 32x32
texture out: Rgba16Float 32x32

fullscreen pattern \"pattern.wgsl\" {
    color src
}
";

#[test]
fn one_blur_shader_serves_two_passes_through_per_pass_values() {
    let shared = format!(
        "{BLUR_HEAD}
fullscreen blur_h \"blur.wgsl\" {{
    reads src
    bind input = src
    set dir = (1, 0), taps = 3
    color tmp
}}

fullscreen blur_v \"blur.wgsl\" {{
    reads tmp
    bind input = tmp
    set dir = (0, 1), taps = 3
    color out
}}

output out
"
    );
    let separate = format!(
        "{BLUR_HEAD}
fullscreen blur_h \"blur_h.wgsl\" {{
    reads src
    bind input = src
    color tmp
}}

fullscreen blur_v \"blur_v.wgsl\" {{
    reads tmp
    bind input = tmp
    color out
}}

output out
"
    );
    let (h, v) = (hand_written_blur("1, 0"), hand_written_blur("0, 1"));
    let d = project(
        "values",
        &[
            ("shaders/pattern.wgsl", PATTERN),
            ("shaders/blur.wgsl", BLUR),
            ("shaders/blur_h.wgsl", &h),
            ("shaders/blur_v.wgsl", &v),
            ("pipelines/shared.lbp", &shared),
            ("pipelines/separate.lbp", &separate),
        ],
    );
    let (a, ex) = render_out(&d.join("pipelines/shared.lbp"), 1);
    let (b, _) = render_out(&d.join("pipelines/separate.lbp"), 1);
    assert_eq!(a.width, 32);
    assert_eq!(a.rgba, b.rgba, "per-pass values give what two hand-written shaders give");
    // Blurred both ways: the lattice's spikes (1 in 5 texels) spread to about their mean.
    let [r, ..] = a.pixel(16, 16);
    assert!((r - 0.2).abs() < 0.1, "{r}");
    let block = &ex.plan().pass("blur_v").unwrap().uniform_blocks[0];
    let dir = block.fields.iter().find(|f| f.name == "dir").unwrap();
    assert_eq!(
        dir.source,
        lightbench_compiler::layout::FieldSource::Fixed(vec![0f32.to_bits(), 1f32.to_bits()])
    );
}
