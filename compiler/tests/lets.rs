//! Named conditions (`let NAME = CONDITION`, RON `lets` and `Let("NAME")`): one lowering for
//! both front ends, the Plan of the condition written out, located errors, printing back, and
//! composition with a used pipeline.

mod common;

use common::*;
use lightbench_compiler::plan::Plan;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;

const FILL: &str = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(0.25);\n}\n";

/// Two passes under one named condition and its negation; `first` is what names it.
fn pipeline(first: &str, second: &str, lets: &str) -> String {
    format!(
        "pipeline m\n\ntexture out: Rgba8Unorm 8x8\n{lets}\n\
fullscreen base \"fill.wgsl\" {{\n    color out\n}}\n\n\
fullscreen one \"fill.wgsl\" {{\n    color out load blend Add\n    when {first}\n}}\n\n\
fullscreen two \"fill.wgsl\" {{\n    color out load blend Add\n    when {second}\n}}\n\n\
variant look = a {{\n    option a\n    option b\n    option c\n}}\n\noutput out\n"
    )
}

fn plan(tag: &str, file: &str, text: &str, variants: &[(&str, &str)]) -> Plan {
    let dir = write_project(tag, &[(file, text), ("shaders/fill.wgsl", FILL)]);
    let mut s = Session::new();
    let chosen: Vec<(String, String)> = variants.iter().map(|(v, o)| (v.to_string(), o.to_string())).collect();
    let plan = s.plan_file(&dir.join(file), None, &Profile::vulkan(), &SceneFeatures::everything(), &chosen);
    plan.unwrap_or_else(|| panic!("{}", s.render()))
}

fn names(p: &Plan) -> Vec<&str> {
    p.passes.iter().map(|p| p.name.as_str()).collect()
}

/// A named condition plans as the condition written out, in LBP and in RON, for every option.
#[test]
fn a_named_condition_plans_as_the_condition_written_out() {
    let lets = "\nlet ab = variant(look, a | b)\nlet only_a = all(ab, not variant(look, b))\n";
    let named = pipeline("only_a", "not ab", lets);
    let written = pipeline("all(variant(look, a | b), not variant(look, b))", "not variant(look, a | b)", "");
    let ron = "Pipeline(\n    name: \"m\",\n    resources: {\"out\": Texture(format: Rgba8Unorm, size: Fixed(8, 8))},\n    \
lets: {\"ab\": Variant(\"look\", \"a | b\"), \"only_a\": All([Let(\"ab\"), Not(Variant(\"look\", \"b\"))])},\n    passes: [\n        \
Fullscreen(name: \"base\", shader: \"fill.wgsl\", color: [\"out\"]),\n        \
Fullscreen(name: \"one\", shader: \"fill.wgsl\", color: [Target(resource: \"out\", load: Load, blend: Add)], when: Let(\"only_a\")),\n        \
Fullscreen(name: \"two\", shader: \"fill.wgsl\", color: [Target(resource: \"out\", load: Load, blend: Add)], when: Not(Let(\"ab\"))),\n    ],\n    \
variants: {\"look\": Variant(default: \"a\", options: {\"a\": (), \"b\": (), \"c\": ()})},\n    output: \"out\",\n)\n";
    for (option, kept) in [("a", vec!["base", "one"]), ("b", vec!["base"]), ("c", vec!["base", "two"])] {
        let v = [("look", option)];
        let (n, w) = (plan("lets-named", "m.lbp", &named, &v), plan("lets-written", "m.lbp", &written, &v));
        let r = plan("lets-ron", "m.ron", ron, &v);
        assert_eq!(names(&n), kept, "look={option}");
        let json = |p: &Plan| serde_json::to_string(&p.passes).unwrap();
        assert_eq!(json(&n), json(&w), "look={option}: named and written out plan alike");
        assert_eq!(json(&n), json(&r), "look={option}: LBP and RON plan alike");
    }
}

/// An unknown name (with the nearest declared), names that lead back to themselves (the
/// chain, at the use that closes it), a `let` nothing uses (a warning) and a `Let` of no name:
/// each located.
#[test]
fn named_conditions_report_located_errors() {
    let lets = "\nlet ab = variant(look, a | b)\nlet loop_a = all(loop_b)\nlet loop_b = any(loop_a, ab)\nlet spare = effect(Bloom)\n";
    let text = pipeline("abb", "loop_a", lets);
    let dir = write_project("lets-errors", &[("m.lbp", &text), ("shaders/fill.wgsl", FILL)]);
    let out = check_project(&dir, "m.lbp", &Profile::vulkan(), None);
    let found = out.located();
    let has = |code: &str, message: &str, line: usize, col: usize| {
        found
            .iter()
            .any(|(c, m, _, l, cc)| c == code && m.contains(message) && *l == line && *cc == col)
    };
    assert!(
        has("unknown-let", "no `let` declares the condition `abb`", 16, 10),
        "{}",
        out.dump()
    );
    assert!(out.dump().contains("did you mean `ab`?"), "{}", out.dump());
    assert!(
        has("let-cycle", "lead back to themselves: loop_a -> loop_b -> loop_a", 7, 18),
        "{}",
        out.dump()
    );
    assert!(has("unused-let", "no condition uses `spare`", 8, 5), "{}", out.dump());
    let unused: Vec<_> = found.iter().filter(|f| f.0 == "unused-let").collect();
    assert_eq!(unused.len(), 1, "`ab` is used, in the cycle: {}", out.dump());
    assert_eq!(
        found.iter().filter(|f| f.0 == "let-cycle").count(),
        1,
        "one cycle, said once: {}",
        out.dump()
    );

    let ron = "Pipeline(name: \"m\", resources: {\"out\": Texture(format: Rgba8Unorm, size: Fixed(8, 8))}, \
passes: [Fullscreen(name: \"base\", shader: \"fill.wgsl\", color: [\"out\"], when: Let())], output: \"out\")";
    let dir = write_project("lets-errors-ron", &[("m.ron", ron), ("shaders/fill.wgsl", FILL)]);
    let out = check_project(&dir, "m.ron", &Profile::vulkan(), None);
    assert!(
        out.located()
            .iter()
            .any(|(c, m, _, l, _)| c == "type-mismatch" && m.contains("condition `Let`") && *l == 1),
        "{}",
        out.dump()
    );
}

/// `fmt` prints `let`s as written, `convert` to RON and back gives the same text.
#[test]
fn named_conditions_print_back_as_written() {
    let lets = "\n// Either of the first two.\nlet ab = variant(look, a | b)\n";
    let text = pipeline("ab", "not ab", lets);
    let dir = write_project("lets-print", &[("m.lbp", &text), ("shaders/fill.wgsl", FILL)]);
    let mut s = Session::new();
    let p = s.load_pipeline(&dir.join("m.lbp")).unwrap_or_else(|| panic!("{}", s.render()));
    let lbp = lightbench_compiler::front::lbp::print::print(&p, Some(&text));
    assert_eq!(lbp, text, "fmt leaves the file as it is");
    let ron = lightbench_compiler::front::ron::print::print(&p, Some(&text));
    assert!(
        ron.contains("lets: {\n        // Either of the first two.\n        \"ab\": Variant(\"look\", \"a | b\"),"),
        "{ron}"
    );
    assert!(ron.contains("when: Not(Let(\"ab\"))"), "{ron}");
    std::fs::write(dir.join("m.ron"), &ron).unwrap();
    let mut s = Session::new();
    let back = s.load_pipeline(&dir.join("m.ron")).unwrap_or_else(|| panic!("{}", s.render()));
    assert_eq!(lightbench_compiler::front::lbp::print::print(&back, Some(&ron)), text);
}

/// A pipeline that uses another uses its `let`s, replaces one (`replace let`) or removes one
/// (`remove let`); declaring one again without `replace` is a duplicate.
#[test]
fn named_conditions_compose_with_a_used_pipeline() {
    let base = pipeline("ab", "not ab", "\nlet ab = variant(look, a | b)\n");
    let user = |items: &str| format!("pipeline u\n\nuse \"m.lbp\"\n{items}\n");
    let plan_of = |tag: &str, own: &str, option: &str| {
        let dir = write_project(tag, &[("m.lbp", &base), ("u.lbp", own), ("shaders/fill.wgsl", FILL)]);
        let mut s = Session::new();
        let v = [("look".to_string(), option.to_string())];
        let plan = s.plan_file(&dir.join("u.lbp"), None, &Profile::vulkan(), &SceneFeatures::everything(), &v);
        (plan, s)
    };
    // The used pipeline's `let`, in a pass of the user's own.
    let own = user("fullscreen three \"fill.wgsl\" {\n    color out load blend Add\n    when ab\n}");
    let (p, s) = plan_of("lets-use", &own, "b");
    assert_eq!(names(&p.unwrap_or_else(|| panic!("{}", s.render()))), ["base", "one", "three"]);
    // Replaced: `ab` now means `c`, for the used pipeline's passes too.
    let (p, s) = plan_of("lets-replace", &user("replace let ab = variant(look, c)"), "c");
    assert_eq!(names(&p.unwrap_or_else(|| panic!("{}", s.render()))), ["base", "one"]);
    // Declared again: a duplicate, pointing at both.
    let (p, s) = plan_of("lets-dup", &user("let ab = variant(look, c)"), "a");
    assert!(p.is_none() && s.render().contains("duplicate-name"), "{}", s.render());
    // Removed while a pass still names it: an unknown name at that pass.
    let (p, s) = plan_of("lets-remove", &user("remove let ab"), "a");
    assert!(
        p.is_none() && s.render().contains("no `let` declares the condition `ab`"),
        "{}",
        s.render()
    );
}
