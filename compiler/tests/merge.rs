//! Stage `merge` (consecutive passes sharing a render pass), GPU-free: which passes the Plan
//! lets continue the render pass before them.

mod common;

use common::*;
use lightbench_compiler::plan::Plan;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;

const FILL: &str = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(0.25);\n}\n";
const COPY: &str = "@group(2) @binding(0) var input: texture_2d<f32>;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    return textureLoad(input, vec2<i32>(p.xy), 0);\n}\n";

fn plan_of(passes: &str) -> Plan {
    let text = format!("pipeline m\n\ntexture a: Rgba16Float 8x8\ntexture out: Rgba16Float 8x8\n\n{passes}\noutput out\n");
    plan_project(
        "merge",
        &[("pipelines/m.lbp", &text), ("shaders/fill.wgsl", FILL), ("shaders/copy.wgsl", COPY)],
    )
}

fn continues(plan: &Plan) -> Vec<(&str, bool)> {
    plan.passes.iter().map(|p| (p.name.as_str(), p.continues)).collect()
}

/// A pass that loads the attachments the pass before rendered into continues its render pass
/// (sampling other textures is fine); one that renders elsewhere does not.
#[test]
fn a_pass_loading_the_previous_pass_s_targets_continues_it() {
    let plan = plan_of(
        "fullscreen make \"fill.wgsl\" {\n    color a\n}\n\n\
         fullscreen base \"fill.wgsl\" {\n    color out\n}\n\n\
         fullscreen add \"copy.wgsl\" {\n    reads a\n    bind input = a\n    color out load blend Add\n}\n\n\
         fullscreen more \"fill.wgsl\" {\n    color out load blend Add\n}\n",
    );
    assert_eq!(continues(&plan), [("make", false), ("base", false), ("add", true), ("more", true)]);
    let text = lightbench_compiler::plan::to_text(&plan, true);
    assert!(text.contains("continues the render pass of `base`"), "{text}");
}

/// The bundled pipeline: ambient's render pass carries the lights into `hdr`; the G-buffer,
/// shadow maps, compute passes and tone mapping each start their own.
#[test]
fn the_lights_continue_ambient_in_the_default_pipeline() {
    let mut s = Session::new();
    let scene = SceneFeatures::everything();
    let plan = s
        .plan_file(&repo_root().join("pipelines/deferred.lbp"), None, &Profile::vulkan(), &scene, &[])
        .unwrap_or_else(|| panic!("{}", s.render()));
    let merged: Vec<&str> = plan.passes.iter().filter(|p| p.continues).map(|p| p.name.as_str()).collect();
    assert_eq!(merged, ["light_directional_spot", "light_point"], "{:?}", continues(&plan));
}
