//! Specialisation constants (`constants`): values for the shaders' `override`s from numbers,
//! parameters and variant options, in the Plan per stage; each mistake a located error, and
//! values that break a shader in some configuration an error naming it.

mod common;

use common::*;
use lightbench_compiler::plan::Plan;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;

const POST_WGSL: &str = r#"override GAIN: f32 = 1.0;
override FAST: bool;
override TAPS: u32 = 2u;
@group(0) @binding(0) var<storage, read> sums: array<f32>;

@fragment
fn fs_main(@location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    var s = 0.0;
    for (var i = 0u; i < TAPS; i++) {
        s += 0.125;
    }
    return vec4<f32>(GAIN, select(0.0, 1.0, FAST), s, 1.0 + 0.0 * sums[0]);
}
"#;

const REDUCE_WGSL: &str = r#"override N: u32 = 64u;
var<workgroup> partial: array<f32, N>;
@group(0) @binding(0) var<storage, read_write> sums: array<f32>;

@compute @workgroup_size(N)
fn cs_main(@builtin(local_invocation_index) i: u32) {
    partial[i] = f32(i);
    workgroupBarrier();
    if i == 0u {
        sums[0] = partial[N - 1u];
    }
}
"#;

/// A project whose `post` pass has the line `constants`, and a compute pass sized by `n`;
/// `broken`: a variant option that presets `n = 0`.
fn project_with(constants: &str, broken: bool) -> std::path::PathBuf {
    let broken = if broken { "    option broken set(n = 0)\n" } else { "" };
    let text = format!(
        "pipeline t\n\nparam gain: Float = 2 in 0..8\nparam n: Int = 64 in 0..256\n\
         texture out: Rgba16Float viewport\nbuffer sums: 256 bytes\n\n\
         compute reduce \"reduce.wgsl\" {{\n    writes sums\n    constants N = param(n)\n    dispatch groups(1, 1, 1)\n}}\n\n\
         fullscreen post \"post.wgsl\" {{\n    reads sums\n    color out\n    {constants}\n}}\n\n\
         variant quality = high {{\n    option high\n    option low\n{broken}}}\n\noutput out\n"
    );
    write_project(
        "constants",
        &[
            ("pipelines/t.lbp", &text),
            ("shaders/post.wgsl", POST_WGSL),
            ("shaders/reduce.wgsl", REDUCE_WGSL),
        ],
    )
}

fn project(constants: &str) -> std::path::PathBuf {
    project_with(constants, false)
}

fn check(dir: &std::path::Path) -> Outcome {
    check_project(dir, "pipelines/t.lbp", &Profile::offline("vulkan").unwrap(), None)
}

fn plan(dir: &std::path::Path, variants: &[(&str, &str)], params: &[(&str, i64)]) -> (Option<Plan>, String) {
    let mut s = Session::new();
    let profile = Profile::offline("vulkan").unwrap();
    let scene = SceneFeatures::everything();
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let checked = s
        .load_checked(&dir.join("pipelines/t.lbp"), None, &profile)
        .unwrap_or_else(|| panic!("{}", s.render()));
    let declared = s
        .plan(&checked, &profile, &scene, &[])
        .unwrap_or_else(|| panic!("{}", s.render()))
        .params;
    let mut values = lightbench_compiler::plan::ParamValues::new();
    for (k, x) in params {
        values.set(&declared, k, lightbench_compiler::ir::ParamValue::Int(*x)).unwrap();
    }
    let plan = s.plan_with(&checked, (&profile, &scene), &v, &values);
    (plan, s.render())
}

fn first(o: &Outcome) -> (String, String, usize, usize) {
    let (code, msg, _, l, c) = o.located().into_iter().next().unwrap_or_else(|| panic!("no diagnostic"));
    (code, msg, l, c)
}

fn stage_constants(plan: &Plan, pass: &str) -> Vec<(String, f64)> {
    plan.pass(pass).unwrap().stages.iter().flat_map(|s| s.constants.clone()).collect()
}

#[test]
fn constants_come_from_numbers_parameters_and_variants() {
    let dir = project("constants GAIN = param(gain), FAST = variant(quality, low), TAPS = 3");
    let o = check(&dir);
    assert!(o.errors().is_empty(), "{}", o.dump());
    let (high, report) = plan(&dir, &[], &[]);
    let high = high.unwrap_or_else(|| panic!("{report}"));
    let expect = |fast: f64| vec![("GAIN".to_string(), 2.0), ("FAST".to_string(), fast), ("TAPS".to_string(), 3.0)];
    assert_eq!(stage_constants(&high, "post"), expect(0.0));
    let (low, _) = plan(&dir, &[("quality", "low")], &[]);
    assert_eq!(stage_constants(&low.unwrap(), "post"), expect(1.0));
    assert_eq!(stage_constants(&high, "reduce"), [("N".to_string(), 64.0)]);
    // A parameter a constant uses is fixed by the Plan: another value, another Plan.
    let (wider, _) = plan(&dir, &[], &[("n", 128)]);
    let wider = wider.unwrap();
    assert_eq!(stage_constants(&wider, "reduce"), [("N".to_string(), 128.0)]);
    let n = wider.params.iter().find(|p| p.name == "n").unwrap();
    assert_eq!(n.sizes, Some(lightbench_compiler::ir::ParamValue::Int(128)));
    let text = lightbench_compiler::plan::to_text(&wider, true);
    assert!(text.contains("constants (fragment): GAIN = 2, FAST = 0, TAPS = 3"), "{text}");
}

#[test]
fn an_override_without_a_default_needs_a_value() {
    let dir = project("constants GAIN = 1");
    let o = check(&dir);
    assert_eq!(
        first(&o),
        (
            "constant-missing".into(),
            "`override FAST` of `post.wgsl#fs_main` has no default and pass `post` gives it no value".into(),
            17,
            15
        ),
        "{}",
        o.dump()
    );
    assert_eq!(o.session.diags.list[0].notes, ["in every configuration"], "no variant decides it");
    // Missing in one option only: the note names that option, not every variant chosen then.
    let dir = project("constants match(quality) { high: (FAST = true), low: (GAIN = 1) }");
    let o = check(&dir);
    assert_eq!(first(&o).0, "constant-missing", "{}", o.dump());
    assert_eq!(o.session.diags.list[0].notes, ["whenever quality = low"], "{}", o.dump());
}

#[test]
fn a_value_its_override_cannot_take_is_located_at_the_value() {
    for (value, what) in [("1.5", "`1.5`"), ("-1", "`-1`"), ("true", "`true`")] {
        let dir = project(&format!("constants FAST = false, TAPS = {value}"));
        let o = check(&dir);
        let msg = format!("`override TAPS` of `post.wgsl` is u32; {what} does not fit it");
        assert_eq!(first(&o), ("constant-type".into(), msg, 17, 36), "{}", o.dump());
    }
    let dir = project("constants FAST = param(gain)");
    let o = check(&dir);
    assert_eq!(first(&o).0, "constant-type", "{}", o.dump());
}

#[test]
fn a_constant_naming_no_override_is_located_with_a_suggestion() {
    let dir = project("constants FAST = true, GAINN = 2");
    let o = check(&dir);
    assert_eq!(
        first(&o),
        (
            "constant-unknown".into(),
            "no `override GAINN` in the pass's shaders (post.wgsl)".into(),
            17,
            28
        ),
        "{}",
        o.dump()
    );
    assert_eq!(o.session.diags.list[0].notes, ["did you mean `GAIN`?"]);
}

/// `broken` presets `n = 0`: a workgroup of no invocations. `check` plans that option and
/// says which configuration breaks the shader; a `--param` that does the same fails its Plan.
#[test]
fn values_that_break_a_shader_name_the_configuration() {
    let dir = project_with("constants FAST = true", true);
    let o = check(&dir);
    let (code, msg, line, col) = first(&o);
    assert_eq!((code.as_str(), line, col), ("constant-invalid", 10, 15), "{}", o.dump());
    assert!(msg.contains("make `reduce.wgsl#cs_main` invalid"), "{msg}");
    assert!(
        o.session.diags.list[0].notes.iter().any(|n| n == "whenever quality = broken"),
        "{}",
        o.dump()
    );
    let (zero, report) = plan(&dir, &[], &[("n", 0)]);
    assert!(zero.is_none() && report.contains("constant-invalid"), "{report}");
    let (some, report) = plan(&dir, &[], &[("n", 32)]);
    assert!(some.is_some(), "{report}");
}
