//! Stage `alias` (transient memory), GPU-free: small pipelines planned as `plan` would, and
//! which resources the Plan lets share memory asserted.

mod common;

use common::*;
use lightbench_compiler::plan::Plan;

const FILL: &str = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(0.25);\n}\n";
const COPY: &str = "@group(2) @binding(0) var input: texture_2d<f32>;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    return textureLoad(input, vec2<i32>(p.xy), 0);\n}\n";
const ADD: &str = "@group(2) @binding(0) var one: texture_2d<f32>;\n@group(2) @binding(1) var two: texture_2d<f32>;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    return textureLoad(one, vec2<i32>(p.xy), 0) + textureLoad(two, vec2<i32>(p.xy), 0);\n}\n";

/// `a` is made, copied into `b`, `b` into `c`, `c` into `out`: `a` is done with before `c` is
/// first written, so `c` can live in `a`'s memory; `b` overlaps both.
fn chain(last_reads_a_too: bool, c_format: &str) -> String {
    let last = if last_reads_a_too {
        "fullscreen show \"add.wgsl\" {\n    reads c, a\n    bind one = c, two = a\n    color out\n}\n"
    } else {
        "fullscreen show \"copy.wgsl\" {\n    reads c\n    bind input = c\n    color out\n}\n"
    };
    format!(
        "pipeline m\n\ntexture a: Rgba16Float 8x8\ntexture b: Rgba16Float 8x8\ntexture c: {c_format} 8x8\ntexture out: Rgba16Float 8x8\n\n\
fullscreen make \"fill.wgsl\" {{\n    color a\n}}\n\n\
fullscreen first \"copy.wgsl\" {{\n    reads a\n    bind input = a\n    color b\n}}\n\n\
fullscreen second \"copy.wgsl\" {{\n    reads b\n    bind input = b\n    color c\n}}\n\n{last}\noutput out\n"
    )
}

fn plan_of(text: &str) -> Plan {
    let files = [
        ("pipelines/m.lbp", text),
        ("shaders/fill.wgsl", FILL),
        ("shaders/copy.wgsl", COPY),
        ("shaders/add.wgsl", ADD),
    ];
    plan_project("alias", &files)
}

fn shares(plan: &Plan, name: &str) -> Option<String> {
    let r = plan.resources.iter().find(|r| r.name == name).unwrap();
    r.shares.map(|o| plan.res(o).name.clone())
}

#[test]
fn a_resource_done_with_lends_its_memory_to_a_later_one_of_its_shape() {
    let plan = plan_of(&chain(false, "Rgba16Float"));
    assert_eq!(shares(&plan, "c"), Some("a".into()));
    assert_eq!(shares(&plan, "b"), None, "b is read while c is written");
    assert_eq!(shares(&plan, "out"), None, "the output keeps its memory");
    let bytes = |n: &str| plan.resources.iter().find(|r| r.name == n).unwrap().bytes;
    assert_eq!(plan.physical_bytes, plan.memory_bytes - bytes("c"));
    let text = lightbench_compiler::plan::memory_text(&plan);
    assert!(text.contains("shares `a`") && text.contains("own (an output)"), "{text}");
}

/// Two transients that would alias, but the first is read again after the second is written:
/// they do not.
#[test]
fn a_resource_read_later_keeps_its_memory() {
    let plan = plan_of(&chain(true, "Rgba16Float"));
    assert_eq!(shares(&plan, "c"), None);
    assert_eq!(plan.physical_bytes, plan.memory_bytes);
}

#[test]
fn only_the_same_shape_is_shared() {
    let plan = plan_of(&chain(false, "Rgba8Unorm"));
    assert_eq!(shares(&plan, "c"), None);
}

#[test]
fn history_resources_keep_their_memory() {
    let text = chain(false, "Rgba16Float").replace("texture a: Rgba16Float 8x8", "texture a: Rgba16Float 8x8 history");
    let plan = plan_of(&text);
    assert_eq!(shares(&plan, "c"), None);
    assert!(lightbench_compiler::plan::memory_text(&plan).contains("own (history)"));
}
