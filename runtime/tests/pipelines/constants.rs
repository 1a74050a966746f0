//! Specialisation constants on the GPU: a pass's `constants` reach its shader's `override`s
//! as wgpu pipeline constants, from a number, a parameter (a new value, a new Plan) and a
//! variant option.

use crate::cli_common;
use crate::gpu_common;

use gpu_common::*;
use lightbench::scene::builtin;
use lightbench_compiler::ir::ParamValue;
use lightbench_compiler::plan::ParamValues;
use lightbench_compiler::workspace::Workspace;

const POST_WGSL: &str = r#"override GAIN: f32 = 1.0;
override FAST: bool;
override TAPS: u32 = 2u;

@fragment
fn fs_main(@location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    var s = 0.0;
    for (var i = 0u; i < TAPS; i++) {
        s += 0.125;
    }
    return vec4<f32>(GAIN, select(0.0, 1.0, FAST), s, 1.0);
}
"#;

const PIPELINE: &str = "pipeline t\n\nparam gain: Float = 2 in 0..8\ntexture out: Rgba16Float viewport\n\n\
fullscreen post \"post.wgsl\" {\n    color out\n    constants GAIN = param(gain), FAST = variant(quality, low), TAPS = 3\n}\n\n\
variant quality = high {\n    option high\n    option low\n}\n\noutput out\n";

/// The pixel the pass writes, for the options and `gain` given.
fn pixel(variants: &[(&str, &str)], gain: Option<f64>) -> [f32; 4] {
    let d = cli_common::scratch(&format!("constants-{variants:?}-{gain:?}"));
    std::fs::create_dir_all(d.join("shaders")).unwrap();
    std::fs::create_dir_all(d.join("pipelines")).unwrap();
    std::fs::write(d.join("shaders/post.wgsl"), POST_WGSL).unwrap();
    std::fs::write(d.join("pipelines/t.lbp"), PIPELINE).unwrap();
    let mut scene = builtin::cornell();
    scene.size = (8, 8);
    let g = gpu();
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let path = d.join("pipelines/t.lbp");
    let (exe, _) = lightbench::render::compile(&g, &path, None, &scene, &v).unwrap_or_else(|e| panic!("{e}"));
    let exe = match gain {
        None => exe,
        Some(x) => {
            let mut values = ParamValues::new();
            values.set(&exe.plan.params, "gain", ParamValue::Float(x)).unwrap();
            lightbench::render::compile_with(&Workspace::disk(), &g, (&path, None), &scene, &v, &values)
                .unwrap_or_else(|e| panic!("{e}"))
                .0
        }
    };
    let ex = lightbench::render::render(&g, &exe, &scene, 1).unwrap_or_else(|e| panic!("{e}"));
    let img = ex.read_texture(&g, "out", 0, 0).unwrap();
    [img.rgba[0], img.rgba[1], img.rgba[2], img.rgba[3]]
}

#[test]
fn constants_reach_the_shader_from_numbers_parameters_and_variants() {
    assert_eq!(pixel(&[], None), [2.0, 0.0, 0.375, 1.0]);
    assert_eq!(pixel(&[("quality", "low")], None), [2.0, 1.0, 0.375, 1.0]);
    assert_eq!(pixel(&[("quality", "low")], Some(4.5)), [4.5, 1.0, 0.375, 1.0]);
}
