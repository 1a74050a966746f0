//! Every wgpu shader feature is nameable in `requires`: on a profile that has it the shader
//! validates (what lightbench cannot bind is then a binding error, not a capability one);
//! on a profile without it the error is located at the `enable` directive or the first use
//! and names the feature to require.

mod common;

use common::*;
use lightbench_compiler::profile::{Feature, Profile};

const PIPELINE: &str = "pipeline p\ntexture out: Rgba8Unorm viewport\nbuffer b: 256 bytes\n\
fullscreen f \"t.wgsl\" {\n    color out\n}\ncompute c \"t.wgsl\" {\n    writes b\n    dispatch groups(1, 1, 1)\n}\noutput out\n";

/// (feature, shader, the text the capability error must point at).
fn cases() -> Vec<(Feature, String, &'static str)> {
    let frag = |head: &str, body: &str| {
        format!(
            "{head}\n@group(2) @binding(0) var<storage, read_write> b: array<u32>;\n@fragment\nfn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {{\n    {body}\n    return vec4<f32>(1.0);\n}}\n@compute @workgroup_size(64)\nfn cs_main(@builtin(local_invocation_index) i: u32) {{\n    b[i] = i;\n}}\n"
        )
    };
    let comp = |head: &str, decl: &str, body: &str| {
        format!(
            "{head}\n{decl}\n@fragment\nfn fs_main() -> @location(0) vec4<f32> {{\n    return vec4<f32>(1.0);\n}}\n@compute @workgroup_size(64)\nfn cs_main(@builtin(local_invocation_index) i: u32) {{\n    {body}\n}}\n"
        )
    };
    vec![
        (Feature::ShaderF64, frag("", "let x: f64 = 1.0lf;"), "1.0lf"),
        (Feature::ShaderInt64, frag("", "let x: i64 = 1li;"), "1li"),
        (Feature::ShaderF16, frag("enable f16;", "let x: f16 = 1.0h;"), "1.0h"),
        (
            // naga asks for all 64-bit atomic operations for an `atomic<u64>` in storage.
            Feature::ShaderInt64AtomicAllOps,
            comp("", "@group(2) @binding(0) var<storage, read_write> b: array<atomic<u64>>;", "atomicMax(&b[i], 5lu);"),
            "atomic<u64>",
        ),
        (
            Feature::Subgroup,
            comp("", "@group(2) @binding(0) var<storage, read_write> b: array<u32>;", "b[i] = subgroupAdd(i);"),
            "subgroupAdd",
        ),
        (
            Feature::PrimitiveIndex,
            "enable primitive_index;\n@group(2) @binding(0) var<storage, read_write> b: array<u32>;\n@fragment\nfn fs_main(@builtin(primitive_index) p: u32) -> @location(0) vec4<f32> {\n    return vec4<f32>(f32(p));\n}\n@compute @workgroup_size(64)\nfn cs_main(@builtin(local_invocation_index) i: u32) {\n    b[i] = i;\n}\n".to_string(),
            "@builtin(primitive_index)",
        ),
        (
            Feature::ExperimentalRayQuery,
            frag(
                "enable wgpu_ray_query;\n@group(2) @binding(1) var acc: acceleration_structure;",
                "var rq: ray_query;\n    rayQueryInitialize(&rq, acc, RayDesc(0u, 0xFFu, 0.0, 1.0, vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0)));",
            ),
            "enable wgpu_ray_query",
        ),
        (
            Feature::TextureBindingArray,
            frag(
                "enable wgpu_binding_array;\n@group(2) @binding(1) var ts: binding_array<texture_2d<f32>, 2>;",
                "let c = textureLoad(ts[0], vec2<i32>(0), 0);",
            ),
            "var ts",
        ),
        (
            // naga points at the whole struct holding the built-in: the `enable` comes first.
            Feature::ClipDistances,
            "enable clip_distances;\nstruct VsOut {\n    @builtin(position) pos: vec4<f32>,\n    @builtin(clip_distances) clip: array<f32, 1>,\n};\n@group(2) @binding(0) var<storage, read_write> b: array<u32>;\n@vertex\nfn vs_main() -> VsOut {\n    var o: VsOut;\n    o.pos = vec4<f32>(0.0, 0.0, 0.0, 1.0);\n    o.clip[0] = 1.0;\n    return o;\n}\n@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0);\n}\n@compute @workgroup_size(64)\nfn cs_main(@builtin(local_invocation_index) i: u32) {\n    b[i] = i;\n}\n".to_string(),
            "enable clip_distances",
        ),
        (
            Feature::Immediates,
            frag("var<immediate> k: vec4<f32>;", "let c = k;"),
            "var<immediate>",
        ),
    ]
}

fn profile(with: Option<Feature>) -> Profile {
    let mut p = Profile::webgpu();
    p.name = "test".into();
    p.features.extend(with);
    p
}

#[test]
fn each_feature_is_accepted_where_present_and_located_where_missing() {
    for (i, (feature, shader, at)) in cases().into_iter().enumerate() {
        let dir = write_project(&format!("feature-{i}"), &[("p.lbp", PIPELINE), ("shaders/t.wgsl", &shader)]);
        let without = check_project(&dir, "p.lbp", &profile(None), None);
        let e = without
            .errors()
            .into_iter()
            .find(|d| d.code.as_str() == "shader-validation")
            .unwrap_or_else(|| panic!("{feature:?}: no capability error without it:\n{}", without.dump()));
        let needs = format!("add `{}` to the `requires`", feature.name());
        assert!(e.notes.iter().any(|n| n.contains(&needs)), "{feature:?}:\n{}", without.dump());
        let (_, line, col) = e.location(&without.session.sources).unwrap();
        let text_line = shader.lines().nth(line - 1).unwrap();
        assert_eq!(
            text_line.find(at).map(|c| c + 1),
            Some(col),
            "{feature:?}: located at {line}:{col}, not at `{at}`:\n{}",
            without.dump()
        );
        let mut with_it = profile(Some(feature));
        if feature == Feature::ShaderInt64AtomicAllOps {
            with_it.features.insert(Feature::ShaderInt64); // its `5lu` is a u64 value
        }
        let with = check_project(&dir, "p.lbp", &with_it, None);
        let capability = with.errors().into_iter().any(|d| d.code.as_str() == "shader-validation");
        assert!(
            !capability,
            "{feature:?}: still a validation error with the feature:\n{}",
            with.dump()
        );
    }
}

/// The README lists every feature `requires` accepts.
#[test]
fn the_readme_names_every_feature() {
    let readme = common::manual();
    let missing: Vec<&str> = Feature::NAMES
        .iter()
        .copied()
        .filter(|n| !readme.contains(&format!("`{n}`")))
        .collect();
    assert!(missing.is_empty(), "the manual lacks {missing:?}");
}

/// `blend: DualSource` needs a `@blend_src(1)` output: without one, an error at the blend; with
/// the pair, one target and no error.
#[test]
fn dual_source_blend_needs_the_second_source() {
    let pipeline =
        "pipeline p\ntexture out: Rgba8Unorm viewport\nfullscreen f \"t.wgsl\" {\n    color out blend DualSource\n}\noutput out\n";
    let single = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0);\n}\n";
    let dir = write_project("dual-single", &[("p.lbp", pipeline), ("shaders/t.wgsl", single)]);
    let out = check_project(&dir, "p.lbp", &Profile::vulkan(), None);
    let located = out.located();
    assert!(
        located.iter().any(|(code, msg, file, line, col)| code == "fragment-outputs"
            && msg.contains("blends `DualSource`, but entry point `fs_main` writes no `@blend_src(1)` output")
            && file == "p.lbp"
            && (*line, *col) == (4, 21)),
        "{}",
        out.dump()
    );
    let pair = "enable dual_source_blending;\nstruct Out {\n    @location(0) @blend_src(0) c: vec4<f32>,\n    @location(0) @blend_src(1) t: vec4<f32>,\n};\n@fragment\nfn fs_main() -> Out {\n    return Out(vec4<f32>(1.0), vec4<f32>(0.5));\n}\n";
    let dir = write_project("dual-pair", &[("p.lbp", pipeline), ("shaders/t.wgsl", pair)]);
    let out = check_project(&dir, "p.lbp", &Profile::vulkan(), None);
    assert!(out.errors().is_empty(), "{}", out.dump());
}

/// A binding error stops `check` before any configuration is planned; an option the profile
/// cannot run is still reported beside it, not hidden by it.
#[test]
fn a_binding_error_does_not_hide_an_unsupported_option() {
    let pipeline = "pipeline p\ntexture out: Rgba8Unorm viewport\n\
        fullscreen f \"fill.wgsl\" {\n    color out\n    when variant(q, fast)\n}\n\
        fullscreen g \"bad.wgsl\" {\n    color out\n    when variant(q, slow)\n}\n\
        variant q = slow {\n    option slow\n    option fast requires(ShaderF16)\n}\noutput out\n";
    let fill = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0);\n}\n";
    let bad = "@group(2) @binding(0) var nothing: texture_2d<f32>;\n@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return textureLoad(nothing, vec2<i32>(0), 0);\n}\n";
    let dir = write_project(
        "hidden-unsupported",
        &[("p.lbp", pipeline), ("shaders/fill.wgsl", fill), ("shaders/bad.wgsl", bad)],
    );
    let o = check_project(&dir, "p.lbp", &profile(None), None);
    let codes: Vec<&str> = o.errors().iter().map(|d| d.code.as_str()).collect();
    assert_eq!(codes, ["binding-unsatisfied", "variant-unsupported"], "{}", o.dump());
}
