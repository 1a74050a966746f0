//! Templates (LBP `template NAME(PARAMS) { … }` and `like NAME(ARGS)`, RON `templates: {..}`
//! and `like: Like(..)`): attributes written once, given to passes and groups with each `$PARAM`
//! replaced by the instance's argument. A pipeline with templates plans as the same pipeline
//! written out, in both front ends; located errors; printing back as written.

mod common;

use common::*;
use lightbench_compiler::plan::Plan;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;

const FILL: &str = "struct Params {\n    value: f32,\n}\n@group(1) @binding(0) var<uniform> params: Params;\n\
@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(params.value);\n}\n";
const COPY: &str = "@group(2) @binding(0) var layers: texture_2d_array<f32>;\n@fragment\n\
fn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    return textureLoad(layers, vec2<i32>(p.xy), 0, 1);\n}\n";

const HEAD: &str = "pipeline m\n\ntexture out: Rgba8Unorm 8x8\ntexture layers: Rgba8Unorm 8x8 layers 2 D2Array\n";
const TAIL: &str = "\nfullscreen copy \"copy.wgsl\" {\n    reads layers\n    color out\n}\n\n\
variant look = a {\n    option a\n    option b\n}\n\noutput out\n";

/// Two templates, one built on the other: the parameters stand for a layer and a value; one
/// pass says nothing but its template, one adds a condition (joined with the template's), a
/// group is like the base template.
const TEMPLATED: &str = "\n// One layer filled with a value, while `look` is a or b.\ntemplate fill(layer, v) like base {\n    \
color layers layer $layer\n    set value = $v\n}\n\ntemplate base {\n    shader \"fill.wgsl\"\n    when variant(look, a | b)\n}\n\n\
fullscreen front like fill(0, 0.25)\n\nfullscreen back like fill(1, 0.5) {\n    when variant(look, b)\n}\n\n\
group like base {\n    color layers load blend Add layer 1\n\n    fullscreen more {\n        set value = 0.125\n    }\n}\n";

const WRITTEN: &str =
    "\nfullscreen front \"fill.wgsl\" {\n    color layers layer 0\n    set value = 0.25\n    when variant(look, a | b)\n}\n\n\
fullscreen back \"fill.wgsl\" {\n    color layers layer 1\n    set value = 0.5\n    when all(variant(look, a | b), variant(look, b))\n}\n\n\
fullscreen more \"fill.wgsl\" {\n    color layers load blend Add layer 1\n    set value = 0.125\n    when variant(look, a | b)\n}\n";

fn plan(tag: &str, file: &str, text: &str, option: Option<&str>) -> Plan {
    let dir = write_project(tag, &[(file, text), ("fill.wgsl", FILL), ("copy.wgsl", COPY)]);
    let mut s = Session::new();
    let v: Vec<(String, String)> = option.map(|o| ("look".to_string(), o.to_string())).into_iter().collect();
    let plan = s.plan_file(&dir.join(file), Some(&dir), &Profile::vulkan(), &SceneFeatures::everything(), &v);
    plan.unwrap_or_else(|| panic!("{}", s.render()))
}

fn json(p: &Plan) -> String {
    plain_passes(p)
}

/// The templated pipeline plans exactly as the pipeline written out, for each option; its RON
/// form too; `fmt` leaves it as written and RON converts back to it.
#[test]
fn a_template_plans_as_its_passes_written_out() {
    let templated = format!("{HEAD}{TEMPLATED}{TAIL}");
    let written = format!("{HEAD}{WRITTEN}{TAIL}");
    let dir = write_project("templates-ron", &[("m.lbp", &templated), ("fill.wgsl", FILL), ("copy.wgsl", COPY)]);
    let mut s = Session::new();
    let p = s.load_pipeline(&dir.join("m.lbp")).unwrap_or_else(|| panic!("{}", s.render()));
    assert_eq!(s.diags.list.len(), 0, "{}", s.render());
    let ron = lightbench_compiler::front::ron::print::print(&p, Some(&templated));
    assert!(
        ron.contains("        \"fill\": Template(\n            parameters: [\"layer\", \"v\"],\n            like: Like(\"base\"),"),
        "{ron}"
    );
    assert!(
        ron.contains("name: \"front\",\n            like: Like(\"fill\", 0, 0.25),"),
        "{ron}"
    );
    for (option, kept) in [("a", vec!["front", "more", "copy"]), ("b", vec!["front", "back", "more", "copy"])] {
        let t = plan("templates-t", "m.lbp", &templated, Some(option));
        let w = plan("templates-w", "m.lbp", &written, Some(option));
        let r = plan("templates-r", "m.ron", &ron, Some(option));
        assert_eq!(json(&t), json(&w), "look={option}");
        assert_eq!(json(&t), json(&r), "look={option}: RON");
        let names: Vec<&str> = t.passes.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, kept, "look={option}");
    }
    assert_eq!(lightbench_compiler::front::lbp::print::print(&p, Some(&templated)), templated);
    // `plan --explain` says where each pass was written; the written-out pipeline's passes
    // say nothing of the kind.
    let explained = lightbench_compiler::plan::to_text(&plan("templates-x", "m.lbp", &templated, Some("b")), true);
    for line in [
        "      written: like `fill(0, 0.25)`\n",
        "      written: like `fill(1, 0.5)`\n",
        "      written: in a group (like `base`)\n",
    ] {
        assert!(explained.contains(line), "{line}\n{explained}");
    }
    let plain = lightbench_compiler::plan::to_text(&plan("templates-y", "m.lbp", &written, Some("b")), true);
    assert!(!plain.contains("written:"), "{plain}");
    std::fs::write(dir.join("m.ron"), &ron).unwrap();
    let back = s.load_pipeline(&dir.join("m.ron")).unwrap_or_else(|| panic!("{}", s.render()));
    assert_eq!(lightbench_compiler::front::lbp::print::print(&back, Some(&ron)), templated);
}

/// Each problem is an error at what says it: an unknown template (with a suggestion), the
/// wrong number of arguments, templates like each other, a parameter the template lacks, a
/// `$NAME` outside any template, a template's attribute a pass cannot take (at the template's
/// line), a template declared twice; a template nothing is like is warned about.
#[test]
fn a_templates_problems_are_located_at_what_says_them() {
    let bad = format!(
        "{HEAD}\ntemplate fill(layer, v) {{\n    shader \"fill.wgsl\"\n    color layers layer $layer\n    set value = $value\n}}\n\n\
template a like b {{\n    when variant(look, a)\n}}\n\ntemplate b like a {{\n}}\n\ntemplate drawn {{\n    draw Scene\n}}\n\n\
template idle {{\n}}\n\ntemplate idle {{\n}}\n\n\
fullscreen one like fil(0, 1)\n\nfullscreen two like fill(0)\n\nfullscreen three like a {{\n    color out\n}}\n\n\
fullscreen four \"fill.wgsl\" like drawn {{\n    color layers layer $layer\n}}\n{TAIL}"
    );
    let dir = write_project(
        "templates-bad",
        &[("m.lbp", &bad), ("shaders/fill.wgsl", FILL), ("shaders/copy.wgsl", COPY)],
    );
    let out = check_project(&dir, "m.lbp", &Profile::vulkan(), None);
    let found = out.located();
    let has = |code: &str, text: &str, line: usize, col: usize| {
        assert!(
            found
                .iter()
                .any(|(c, m, n, l, k)| c == code && (m.contains(text) || n.contains(text)) && *l == line && *k == col),
            "{code} `{text}` at {line}:{col}\n{found:?}"
        );
    };
    has("template-param", "template `fill` has no parameter `value`", 9, 17);
    has("duplicate-name", "template `idle` is declared twice", 26, 10);
    has("unknown-template", "no template `fil`", 29, 21);
    has("template-arguments", "`fill` takes 2 arguments (layer, v), given 1", 31, 21);
    has("template-cycle", "templates are like each other: a -> b -> a", 16, 17);
    has("misplaced", "`draw` is not a property of fullscreen passes", 20, 5);
    has("template-param", "`$layer` outside a template", 38, 24);
    has("unused-template", "no pass or group is like `idle`", 23, 10);
    for note in ["expected one of: `layer`, `v`", "did you mean `fill`?"] {
        assert!(out.dump().contains(note), "{note}\n{}", out.dump());
    }
    // A pass whose template cannot be had is not lowered as well (no error about what it lacks).
    assert!(!found.iter().any(|f| f.0 == "missing-key"), "{found:?}");
}

/// RON says the same with `Template(parameters: [..], ..)`, `like: Like(..)` and `Arg("NAME")`;
/// a template holding passes is an error at that key.
#[test]
fn ron_templates_take_arguments_and_hold_no_passes() {
    let ron = "Pipeline(name: \"m\", resources: {\"out\": Texture(format: Rgba8Unorm, size: Fixed(8, 8))}, \
templates: {\"lit\": Template(parameters: [\"v\"], shader: \"fill.wgsl\", values: {\"value\": Arg(\"v\")}), \
\"holder\": Template(passes: [])}, \
passes: [Fullscreen(name: \"one\", like: Like(\"lit\", 0.5), color: [\"out\"])], output: \"out\")";
    let dir = write_project("templates-ron-bad", &[("m.ron", ron), ("shaders/fill.wgsl", FILL)]);
    let out = check_project(&dir, "m.ron", &Profile::vulkan(), None);
    let found = out.located();
    assert!(
        found
            .iter()
            .any(|(c, m, _, l, _)| c == "unknown-key" && m.contains("a template has no `passes`") && *l == 1),
        "{}",
        out.dump()
    );
    assert_eq!(found.iter().filter(|f| f.0 != "unknown-key").count(), 0, "{}", out.dump());
    let good = ron.replace(", \"holder\": Template(passes: [])", "");
    let p = plan("templates-ron-good", "m.ron", &good, None);
    let written = "Pipeline(name: \"m\", resources: {\"out\": Texture(format: Rgba8Unorm, size: Fixed(8, 8))}, \
passes: [Fullscreen(name: \"one\", shader: \"fill.wgsl\", values: {\"value\": 0.5}, color: [\"out\"])], output: \"out\")";
    assert_eq!(json(&p), json(&plan("templates-ron-written", "m.ron", written, None)));
}

/// The bundled pipelines say each thing once: no line of theirs (ignoring comments, blank
/// lines and lines of braces only) repeats an earlier one — each lighting model is one pass
/// per shadow technique, what passes share is a group's or a template's. Their Plans are the
/// passes they replaced (`choices.rs` compares every configuration with the files before).
#[test]
fn no_line_of_a_bundled_pipeline_repeats_an_earlier_one() {
    let dir = repo_root().join("pipelines");
    let mut files = 0;
    for f in lightbench_compiler::pipeline_files(&dir).unwrap() {
        if f.extension().and_then(|e| e.to_str()) != Some("lbp") {
            continue;
        }
        files += 1;
        let text = std::fs::read_to_string(&f).unwrap();
        let mut seen = std::collections::HashMap::new();
        for (n, line) in text.lines().enumerate() {
            let t = line.trim();
            if t.is_empty() || t.starts_with("//") || t.chars().all(|c| matches!(c, '{' | '}' | ' ')) {
                continue;
            }
            if let Some(first) = seen.insert(t, n + 1) {
                panic!("{}:{}: `{t}` repeats line {first}", f.display(), n + 1);
            }
        }
    }
    assert!(files >= 3, "the bundled .lbp pipelines: {files}");
}

/// `like a, b`: both templates' attributes, `when`s together and `reads` in the order
/// written; an attribute both give is `duplicate-key` at the second.
#[test]
fn several_templates_give_their_attributes_together() {
    let head = "pipeline m\n\ntexture out: Rgba8Unorm 8x8\ntexture layers: Rgba8Unorm 8x8 layers 2 D2Array\n\n\
template a {\n    shader \"fill.wgsl\"\n    when variant(look, a)\n}\n\ntemplate b {\n    color layers layer 0\n    when variant(look, a | b)\n}\n\n\
template c {\n    shader \"copy.wgsl\"\n}\n";
    let good = format!("{head}\nfullscreen one like a, b {{\n    set value = 0.5\n}}\n{TAIL}");
    let written = format!(
        "{}\nfullscreen one \"fill.wgsl\" {{\n    color layers layer 0\n    set value = 0.5\n    when all(variant(look, a | b), variant(look, a))\n}}\n{TAIL}",
        "pipeline m\n\ntexture out: Rgba8Unorm 8x8\ntexture layers: Rgba8Unorm 8x8 layers 2 D2Array\n"
    );
    let dir = write_project("templates-two", &[("m.lbp", &good), ("fill.wgsl", FILL), ("copy.wgsl", COPY)]);
    let mut s = Session::new();
    s.load_pipeline(&dir.join("m.lbp")).unwrap_or_else(|| panic!("{}", s.render()));
    // (With `look = b` nothing would write `layers` before `copy` reads it.)
    let good = good.replace("template c {\n    shader \"copy.wgsl\"\n}\n", "");
    let t = plan("templates-two-t", "m.lbp", &good, Some("a"));
    assert_eq!(json(&t), json(&plan("templates-two-w", "m.lbp", &written, Some("a"))));
    let bad = format!("{head}\nfullscreen one like b, a, c {{\n    set value = 0.5\n}}\n{TAIL}");
    let dir = write_project(
        "templates-two-bad",
        &[("m.lbp", &bad), ("shaders/fill.wgsl", FILL), ("shaders/copy.wgsl", COPY)],
    );
    let out = check_project(&dir, "m.lbp", &Profile::vulkan(), None);
    assert!(
        out.located().iter().any(|(c, m, _, l, col)| c == "duplicate-key"
            && m.contains("`shader` is given by two templates, `a` and `c`")
            && *l == 20
            && *col == 27),
        "{:?}",
        out.located()
    );
}

/// Templates like each other in a long chain are an error at the depth limit (no stack
/// exhausted); RON's `like: []` is one at the list.
#[test]
fn a_chain_too_deep_and_an_empty_like_are_located() {
    let mut text = String::from("pipeline m\n\ntexture out: Rgba8Unorm 8x8\n");
    for i in 0..100 {
        text += &format!("\ntemplate t{i} like t{} {{\n}}\n", i + 1);
    }
    text += "\ntemplate t100 {\n    shader \"fill.wgsl\"\n}\n\nfullscreen one like t0 {\n    color out\n}\n\noutput out\n";
    let dir = write_project("templates-deep", &[("m.lbp", &text), ("shaders/fill.wgsl", FILL)]);
    let out = check_project(&dir, "m.lbp", &Profile::vulkan(), None);
    assert!(
        out.located()
            .iter()
            .any(|(c, m, ..)| c == "nesting-too-deep" && m.contains("templates are like others more than 64 deep")),
        "{}",
        out.dump()
    );
    let ron = "Pipeline(name: \"m\", resources: {\"out\": Texture(format: Rgba8Unorm, size: Fixed(8, 8))}, \
passes: [Fullscreen(name: \"one\", shader: \"fill.wgsl\", like: [], color: [\"out\"])], output: \"out\")";
    let dir = write_project("templates-empty-like", &[("m.ron", ron), ("shaders/fill.wgsl", FILL)]);
    let out = check_project(&dir, "m.ron", &Profile::vulkan(), None);
    assert!(
        out.located()
            .iter()
            .any(|(c, m, _, l, _)| c == "type-mismatch" && m.contains("found an empty list") && *l == 1),
        "{}",
        out.dump()
    );
}

/// A `$NAME` in a declaration is a value of the wrong kind there, located.
#[test]
fn a_parameter_in_a_declaration_is_a_type_mismatch() {
    let text = "pipeline m\n\ntexture $x: Rgba8Unorm 8x8\n\noutput out\n";
    let dir = write_project("templates-declaration", &[("m.lbp", text)]);
    let out = check_project(&dir, "m.lbp", &Profile::vulkan(), None);
    assert!(
        out.located()
            .iter()
            .any(|(c, m, _, l, col)| c == "type-mismatch" && m.contains("found `Arg(...)`") && *l == 3 && *col == 9),
        "{}",
        out.dump()
    );
}
