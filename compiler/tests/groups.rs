//! Groups of passes sharing attributes (LBP `group { … }`, RON `Group(…, passes: [...])`):
//! expanded before composition and the one lowering, so a grouped pipeline plans as the same
//! pipeline written out, in both front ends; located errors; printing back as written.

mod common;

use common::*;
use lightbench_compiler::plan::Plan;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;

const FILL: &str = "@group(2) @binding(0) var src: texture_2d<f32>;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    return textureLoad(src, vec2<i32>(p.xy), 0);\n}\n";
const CLEAR: &str = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(0.25);\n}\n";

const HEAD: &str = "pipeline m\n\ntexture src: Rgba8Unorm 8x8\ntexture out: Rgba8Unorm 8x8\n\n\
fullscreen make \"clear.wgsl\" {\n    color src\n}\n\nfullscreen base \"clear.wgsl\" {\n    color out\n}\n";
const TAIL: &str = "\nvariant look = a {\n    option a\n    option b\n    option c\n}\n\noutput out\n";

/// The group's attributes given to each pass: the `when` joined with the pass's own, `reads`
/// first, the rest unless the pass sets its own; a nested group inside, giving its pass the
/// shader.
const GROUPED: &str = "\n// Passes adding `src` to `out` while `look` is a or b.\ngroup {\n    reads src\n    color out load blend Add\n    when variant(look, a | b)\n\n    \
fullscreen one \"fill.wgsl\" {\n        when not effect(Bloom)\n    }\n\n    group {\n        shader \"fill.wgsl\"\n        when variant(look, b)\n\n        \
fullscreen two {\n            color out load blend Alpha\n        }\n    }\n}\n";

const WRITTEN: &str = "\nfullscreen one \"fill.wgsl\" {\n    reads src\n    color out load blend Add\n    when all(variant(look, a | b), not effect(Bloom))\n}\n\n\
fullscreen two \"fill.wgsl\" {\n    reads src\n    color out load blend Alpha\n    when all(variant(look, a | b), variant(look, b))\n}\n";

fn plan(tag: &str, file: &str, text: &str, option: &str, scene: &SceneFeatures) -> Plan {
    let dir = write_project(tag, &[(file, text), ("fill.wgsl", FILL), ("clear.wgsl", CLEAR)]);
    let mut s = Session::new();
    let v = [("look".to_string(), option.to_string())];
    let plan = s.plan_file(&dir.join(file), Some(&dir), &Profile::vulkan(), scene, &v);
    plan.unwrap_or_else(|| panic!("{}", s.render()))
}

fn json(p: &Plan) -> String {
    plain_passes(p)
}

/// A grouped pipeline plans exactly as the pipeline written out, for every option and with
/// and without the effect; its RON form too.
#[test]
fn a_group_plans_as_its_passes_written_out() {
    let grouped = format!("{HEAD}{GROUPED}{TAIL}");
    let written = format!("{HEAD}{WRITTEN}{TAIL}");
    let dir = write_project("groups-ron", &[("m.lbp", &grouped), ("fill.wgsl", FILL), ("clear.wgsl", CLEAR)]);
    let mut s = Session::new();
    let p = s.load_pipeline(&dir.join("m.lbp")).unwrap_or_else(|| panic!("{}", s.render()));
    let ron = lightbench_compiler::front::ron::print::print(&p, Some(&grouped));
    assert!(ron.contains("        Group(\n            reads: [\"src\"],"), "{ron}");
    let mut bloom = SceneFeatures::everything();
    bloom.effects.clear();
    let cases = [
        (SceneFeatures::everything(), [("a", vec![]), ("b", vec!["two"]), ("c", vec![])]),
        (bloom, [("a", vec!["one"]), ("b", vec!["one", "two"]), ("c", vec![])]),
    ];
    for (scene, options) in cases {
        for (option, kept) in options {
            let g = plan("groups-g", "m.lbp", &grouped, option, &scene);
            let w = plan("groups-w", "m.lbp", &written, option, &scene);
            let r = plan("groups-r", "m.ron", &ron, option, &scene);
            assert_eq!(json(&g), json(&w), "look={option}");
            assert_eq!(json(&g), json(&r), "look={option}: RON");
            let added: Vec<&str> = g
                .passes
                .iter()
                .map(|p| p.name.as_str())
                .filter(|n| *n == "one" || *n == "two")
                .collect();
            assert_eq!(added, kept, "look={option}, effects {:?}", scene.effects);
        }
    }
    // `fmt` leaves the grouped file as written; RON and back gives it again.
    assert_eq!(lightbench_compiler::front::lbp::print::print(&p, Some(&grouped)), grouped);
    std::fs::write(dir.join("m.ron"), &ron).unwrap();
    let back = s.load_pipeline(&dir.join("m.ron")).unwrap_or_else(|| panic!("{}", s.render()));
    assert_eq!(lightbench_compiler::front::lbp::print::print(&back, Some(&ron)), grouped);
}

/// A group attribute a pass of the group cannot take is an error at the group's line; a
/// group replacing something is one at that key; an empty group is warned about.
#[test]
fn a_groups_problems_are_located_at_what_the_group_says() {
    let bad = format!(
        "{HEAD}\ngroup {{\n    draw Scene\n    color out load blend Add\n\n    fullscreen one \"fill.wgsl\" {{\n        reads src\n    }}\n}}\n\ngroup {{\n    when effect(Bloom)\n}}\n{TAIL}"
    );
    let dir = write_project(
        "groups-bad",
        &[("m.lbp", &bad), ("shaders/fill.wgsl", FILL), ("shaders/clear.wgsl", CLEAR)],
    );
    let out = check_project(&dir, "m.lbp", &Profile::vulkan(), None);
    let found = out.located();
    assert!(
        found.iter().any(|(c, m, _, l, col)| c == "misplaced"
            && m.contains("`draw` is not a property of fullscreen passes")
            && *l == 15
            && *col == 5),
        "{}",
        out.dump()
    );
    assert!(found.iter().any(|(c, _, _, l, _)| c == "empty-group" && *l == 23), "{}", out.dump());

    let ron = "Pipeline(name: \"m\", resources: {\"out\": Texture(format: Rgba8Unorm, size: Fixed(8, 8))}, \
passes: [Group(replace: true, passes: [Fullscreen(name: \"base\", shader: \"clear.wgsl\", color: [\"out\"])])], output: \"out\")";
    let dir = write_project("groups-bad-ron", &[("m.ron", ron), ("shaders/clear.wgsl", CLEAR)]);
    let out = check_project(&dir, "m.ron", &Profile::vulkan(), None);
    assert!(
        out.located()
            .iter()
            .any(|(c, m, _, l, col)| c == "unknown-key" && m.contains("a group replaces nothing") && *l == 1 && *col == 104),
        "{}",
        out.dump()
    );
}

/// A pipeline that uses another may group its own passes (placed `after` one of the used
/// file's), and the used file's groups are its passes.
#[test]
fn groups_compose_with_a_used_pipeline() {
    let base = format!("{HEAD}{GROUPED}{TAIL}");
    let user = "pipeline u\n\nuse \"m.lbp\"\n\ngroup {\n    reads src\n    color out load blend Add\n    after base\n\n    \
fullscreen three \"fill.wgsl\" {\n    }\n}\n";
    let dir = write_project(
        "groups-use",
        &[("m.lbp", &base), ("u.lbp", user), ("fill.wgsl", FILL), ("clear.wgsl", CLEAR)],
    );
    let mut s = Session::new();
    let v = [("look".to_string(), "b".to_string())];
    let mut scene = SceneFeatures::everything();
    scene.effects.clear();
    let p = s.plan_file(&dir.join("u.lbp"), Some(&dir), &Profile::vulkan(), &scene, &v);
    let p = p.unwrap_or_else(|| panic!("{}", s.render()));
    let names: Vec<&str> = p.passes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["make", "base", "three", "one", "two"]);
}
