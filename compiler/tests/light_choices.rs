//! Choices by light kind (LBP `match light { Directional | Spot: …, Point: … }`, RON
//! `Match(light: {…})`) in a pass that runs per light: the pass becomes one pass per group of
//! kinds its choices tell apart, planned exactly as those passes written out, in both front
//! ends; located errors; printing back as written.

mod common;

use common::*;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;

const CLEAR: &str = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(0.25);\n}\n";

/// A shader reading the texture `name`.
fn reader(name: &str) -> String {
    format!(
        "@group(2) @binding(0) var {name}: texture_2d<f32>;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {{\n    return textureLoad({name}, vec2<i32>(p.xy), 0);\n}}\n"
    )
}

const HEAD: &str = "pipeline m\n\ntexture src_a: Rgba8Unorm 8x8\ntexture src_b: Rgba8Unorm 8x8\ntexture out: Rgba8Unorm 8x8\n\n\
fullscreen make_a \"clear.wgsl\" {\n    color src_a\n}\n\nfullscreen make_b \"clear.wgsl\" {\n    color src_b\n}\n\n\
fullscreen base \"clear.wgsl\" {\n    color out\n}\n";

/// One pass for every light, its shader and what it reads by the light's kind.
const CHOSEN: &str = "\n// Every light, by its kind.\nfullscreen light {\n    \
shader match light { Directional | Spot: \"a.wgsl\", Point: \"b.wgsl\" }\n    per_light(Directional, Spot, Point)\n    \
reads match light { Directional | Spot: src_a, _: src_b }\n    color out load blend Add\n}\n";

const WRITTEN: &str = "\nfullscreen light_directional_spot \"a.wgsl\" {\n    per_light(Directional, Spot)\n    reads src_a\n    \
color out load blend Add\n}\n\nfullscreen light_point \"b.wgsl\" {\n    per_light(Point)\n    reads src_b\n    color out load blend Add\n}\n";

const TAIL: &str = "\noutput out\n";

fn files<'a>(file: &'a str, text: &'a str, a: &'a str, b: &'a str) -> [(&'a str, &'a str); 4] {
    [(file, text), ("a.wgsl", a), ("b.wgsl", b), ("clear.wgsl", CLEAR)]
}

fn passes_json(tag: &str, file: &str, text: &str) -> String {
    let (a, b) = (reader("src_a"), reader("src_b"));
    let dir = write_project(tag, &files(file, text, &a, &b));
    let mut s = Session::new();
    let plan = s.plan_file(&dir.join(file), Some(&dir), &Profile::vulkan(), &SceneFeatures::everything(), &[]);
    let plan = plan.unwrap_or_else(|| panic!("{}", s.render()));
    plain_passes(&plan)
}

/// The pass choosing by light kind plans as the two passes written out — named by the kinds
/// each serves, each per light of its kinds — and so does its RON form; both print back as
/// written.
#[test]
fn a_pass_choosing_by_light_kind_plans_as_its_passes_written_out() {
    let chosen = format!("{HEAD}{CHOSEN}{TAIL}");
    let written = format!("{HEAD}{WRITTEN}{TAIL}");
    let expected = passes_json("light-written", "m.lbp", &written);
    assert!(expected.contains("\"light_directional_spot\"") && expected.contains("\"light_point\""));
    assert_eq!(passes_json("light-chosen", "m.lbp", &chosen), expected);
    let mut s = Session::new();
    let p = s
        .parse_pipeline("m.lbp", chosen.clone())
        .unwrap_or_else(|| panic!("{}", s.render()));
    let ron = lightbench_compiler::front::ron::print::print(&p, Some(&chosen));
    assert!(
        ron.contains("shader: Match(light: {\"Directional | Spot\": \"a.wgsl\", \"Point\": \"b.wgsl\"})"),
        "{ron}"
    );
    assert_eq!(passes_json("light-ron", "m.ron", &ron), expected);
    // Printed back as written: LBP is already formatted, RON -> LBP gives it again.
    assert_eq!(lightbench_compiler::front::lbp::print::print(&p, Some(&chosen)), chosen);
    let mut s = Session::new();
    let back = s.parse_pipeline("m.ron", ron.clone()).unwrap_or_else(|| panic!("{}", s.render()));
    assert_eq!(lightbench_compiler::front::lbp::print::print(&back, Some(&ron)), chosen);
}

/// Each mistake is located where it is written: a pass without `per_light`, a kind the pass
/// does not run for, a misspelt kind (with a suggestion), a kind served twice, two `_` arms, a
/// kind served by no arm.
#[test]
fn light_choice_mistakes_are_located() {
    let cases: [(&str, &str, &str, usize); 6] = [
        (
            "fullscreen light {\n    shader match light { Point: \"a.wgsl\" }\n    color out\n}\n",
            "light-choice",
            "this pass has no `per_light` list",
            2,
        ),
        (
            "fullscreen light {\n    shader match light { Spot: \"a.wgsl\", Point: \"b.wgsl\" }\n    per_light(Spot)\n    color out\n}\n",
            "light-choice",
            "this pass does not run per Point light: its `per_light` lists Spot",
            2,
        ),
        (
            "fullscreen light {\n    shader match light { Pont: \"a.wgsl\", _: \"b.wgsl\" }\n    per_light(Point)\n    color out\n}\n",
            "unknown-value",
            "unknown light kind `Pont`",
            2,
        ),
        (
            "fullscreen light {\n    per_light(Spot, Point)\n    shader match light { Spot: \"a.wgsl\", Spot | Point: \"b.wgsl\" }\n    color out\n}\n",
            "choice-overlap",
            "Spot lights are served by two arms",
            3,
        ),
        (
            "fullscreen light {\n    per_light(Spot, Point)\n    shader match light { _: \"a.wgsl\", _: \"b.wgsl\" }\n    color out\n}\n",
            "choice-overlap",
            "two catch-all arms `_`",
            3,
        ),
        (
            "fullscreen light {\n    per_light(Spot, Point)\n    shader match light { Spot: \"a.wgsl\" }\n    color out\n}\n",
            "choice-incomplete",
            "no arm for Point lights",
            3,
        ),
    ];
    let (a, b) = (reader("src_a"), reader("src_b"));
    for (i, (pass, code, message, line)) in cases.into_iter().enumerate() {
        let text = format!("pipeline m\n\ntexture out: Rgba8Unorm 8x8\n\n{pass}\noutput out\n");
        let dir = write_project(&format!("light-bad-{i}"), &files("m.lbp", &text, &a, &b));
        let out = check_project(&dir, "m.lbp", &Profile::vulkan(), None);
        let found = out.located();
        assert!(
            found
                .iter()
                .any(|(c, m, _, l, _)| c == code && m.contains(message) && *l == line + 4),
            "case {i}: {}",
            out.dump()
        );
        if code == "unknown-value" {
            assert!(out.dump().contains("did you mean `Point`?"), "{}", out.dump());
        }
    }
}

/// Choices that tell no kinds apart (one arm, or `_` alone) leave the pass one pass, named as
/// written, running per light of every kind it lists.
#[test]
fn a_choice_that_tells_no_kinds_apart_keeps_the_pass() {
    let one = "\nfullscreen light {\n    shader match light { _: \"a.wgsl\" }\n    per_light(Directional, Spot, Point)\n    \
reads src_a\n    color out load blend Add\n}\n";
    let written = "\nfullscreen light \"a.wgsl\" {\n    per_light(Directional, Spot, Point)\n    reads src_a\n    \
color out load blend Add\n}\n";
    let expected = passes_json("light-one-written", "m.lbp", &format!("{HEAD}{written}{TAIL}"));
    assert!(expected.contains("\"light\""));
    assert_eq!(passes_json("light-one", "m.lbp", &format!("{HEAD}{one}{TAIL}")), expected);
}

/// A choice by variant may hold one by light kind in an arm (and the other way round, as the
/// bundled pipelines' do): the pass splits by light kind under every option, each arm's
/// choice taken where its option is chosen.
#[test]
fn a_variants_arm_may_choose_by_light_kind() {
    let nested = "\nfullscreen light {\n    shader match(q) { a: match light { Directional | Spot: \"a.wgsl\", Point: \"b.wgsl\" }, _: \"b.wgsl\" }\n    \
per_light(Directional, Spot, Point)\n    reads match(q) { a: match light { Directional | Spot: src_a, _: src_b }, _: src_b }\n    color out load blend Add\n}\n";
    let variant = "\nvariant q = a {\n    option a\n    option b\n}\n";
    let text = format!("{HEAD}{nested}{variant}{TAIL}");
    let (a, b) = (reader("src_a"), reader("src_b"));
    let dir = write_project("light-nested", &files("m.lbp", &text, &a, &b));
    for (option, shader) in [("a", "a.wgsl"), ("b", "b.wgsl")] {
        let mut s = Session::new();
        let v = [("q".to_string(), option.to_string())];
        let plan = s.plan_file(&dir.join("m.lbp"), Some(&dir), &Profile::vulkan(), &SceneFeatures::everything(), &v);
        let plan = plan.unwrap_or_else(|| panic!("{}", s.render()));
        let pass = plan.pass("light_directional_spot").expect("split by light kind");
        let stages = serde_json::to_string(&pass.stages).unwrap();
        assert!(stages.contains(shader), "q = {option}: {stages}");
        assert!(plan
            .pass("light_point")
            .is_some_and(|p| serde_json::to_string(&p.stages).unwrap().contains("b.wgsl")));
    }
}
