//! Choices inside a pass (`Match`): the bundled pipelines rewritten with them plan exactly
//! what the copied passes planned (`fixtures/before/` keeps the files as they were), and each
//! form's mistakes are located errors.

mod common;

use common::*;
use lightbench_compiler::plan::Plan;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;
use serde_json::Value;

/// The copied passes' names, as the passes with choices name them.
const RENAMED: &[(&str, &str)] = &[
    ("gbuffer_fat", "gbuffer"),
    ("light_point_atlas", "light_point"),
    ("light_point_paraboloid", "light_point"),
    ("light_directional_spot_fat", "light_directional_spot"),
    ("light_point_fat", "light_point"),
    ("light_point_atlas_fat", "light_point"),
    ("light_point_paraboloid_fat", "light_point"),
    ("volume_point_atlas", "volume_point"),
    ("volume_point_paraboloid", "volume_point"),
    ("volume_directional_spot_fat", "volume_directional_spot"),
    ("volume_point_fat", "volume_point"),
    ("volume_point_atlas_fat", "volume_point"),
    ("volume_point_paraboloid_fat", "volume_point"),
    ("forward_point_atlas", "forward_point"),
    ("forward_point_paraboloid", "forward_point"),
    ("tonemap_aliased", "tonemap"),
    ("indirect_diffuse_rotated", "indirect_diffuse"),
    ("indirect_diffuse_filtered", "indirect_diffuse"),
    ("indirect_compose_filtered", "indirect_compose"),
    ("indirect_compose_temporal", "indirect_compose"),
];

fn new_name(old: &str) -> &str {
    RENAMED.iter().find(|(o, _)| *o == old).map_or(old, |(_, n)| n)
}

/// What must agree: passes (names mapped, the arms left out), resources, parameters, memory.
fn essence(plan: &Plan, rename: bool) -> Value {
    let mut v = serde_json::to_value(plan).unwrap();
    for p in v["passes"].as_array_mut().unwrap() {
        let name = p["name"].as_str().unwrap().to_string();
        p["name"] = Value::from(if rename { new_name(&name) } else { &name });
        p.as_object_mut().unwrap().remove("arms");
        p.as_object_mut().unwrap().remove("origin");
    }
    let keep = [
        "passes",
        "resources",
        "params",
        "samplers",
        "memory_bytes",
        "output",
        "hdr_output",
        "jitter",
    ];
    Value::Object(keep.iter().map(|k| (k.to_string(), v[*k].clone())).collect())
}

/// Every option of every variant alone (as `check` plans them), and every combination of the
/// variants the pipeline's choices choose by (with the lighting model, which decides whether
/// those passes run at all).
fn configurations(variants: &[(String, Vec<String>)], crossed: &[&str]) -> Vec<Vec<(String, String)>> {
    let mut out: Vec<Vec<(String, String)>> = vec![vec![]];
    for (v, opts) in variants {
        out.extend(opts.iter().map(|o| vec![(v.clone(), o.clone())]));
    }
    let mut product: Vec<Vec<(String, String)>> = vec![vec![]];
    for (v, opts) in variants.iter().filter(|(v, _)| crossed.contains(&v.as_str())) {
        product = product
            .iter()
            .flat_map(|c| opts.iter().map(move |o| [c.clone(), vec![(v.clone(), o.clone())]].concat()))
            .collect();
    }
    out.extend(product);
    out
}

/// The Plan as `plan --explain` prints it — names, not indices: a pipeline that uses another
/// declares that one's parameters and resources first — without what may differ: the
/// variants' order, the culled passes (fixed variants' passes are gone), the arms and origins,
/// and the resources' order.
fn text_essence(plan: &Plan, rename: bool) -> String {
    let text = lightbench_compiler::plan::to_text(plan, true);
    let mut out = vec![];
    let mut resources = vec![];
    let mut section = "";
    for line in text.lines() {
        if !line.starts_with(' ') && !line.is_empty() {
            section = line.split([':', ' ', '(']).next().unwrap_or("");
        }
        let t = line.trim_start();
        match section {
            "variants" | "culled" => continue,
            _ if t.starts_with("from: ") || t.starts_with("arms: ") || t.starts_with("written: ") => continue,
            "resources" => resources.push(line.to_string()),
            _ => out.push(line.to_string()),
        }
    }
    resources.sort();
    out.extend(resources);
    // Columns aligned to the longest name: compared word by word.
    let mut text: String = out
        .iter()
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" ") + "\n")
        .collect();
    if rename {
        // Longest names first, whole words only.
        let mut renamed: Vec<&(&str, &str)> = RENAMED.iter().collect();
        renamed.sort_by_key(|(o, _)| std::cmp::Reverse(o.len()));
        for (o, n) in renamed {
            text = replace_word(&text, o, n);
        }
    }
    text
}

/// `text` with the word `from` (a name: letters, digits, `_`; not part of a file or resource
/// name, which have dots) replaced by `to`.
fn replace_word(text: &str, from: &str, to: &str) -> String {
    let word = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '.';
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(from) {
        let before = rest[..i].chars().next_back();
        let after = rest[i + from.len()..].chars().next();
        out.push_str(&rest[..i]);
        if before.is_some_and(word) || after.is_some_and(word) {
            out.push_str(from);
        } else {
            out.push_str(to);
        }
        rest = &rest[i + from.len()..];
    }
    out.push_str(rest);
    out
}

fn plans_agree(file: &str, crossed: &[&str], by_text: bool) -> usize {
    let profile = Profile::offline("vulkan").unwrap();
    let mut s = Session::new();
    let root = repo_root();
    let shaders = root.join("shaders");
    // The old file beside the bundled data files it names.
    let dir = temp_dir("choices");
    for f in std::fs::read_dir(root.join("pipelines")).unwrap().map(|e| e.unwrap().path()) {
        if f.extension().is_some_and(|e| e != "ron" && e != "lbp") {
            std::fs::copy(&f, dir.join("pipelines").join(f.file_name().unwrap())).unwrap();
        }
    }
    let old_file = dir.join("pipelines").join(file);
    std::fs::copy(root.join("compiler/tests/fixtures/before").join(file), &old_file).unwrap();
    let before = s.load_checked(&old_file, Some(&shaders), &profile);
    let after = s.load_checked(&root.join("pipelines").join(file), None, &profile);
    assert!(!s.diags.has_errors(), "{}", s.render());
    let (before, after) = (before.unwrap(), after.unwrap());
    let variants: Vec<(String, Vec<String>)> = before
        .pipeline
        .variants
        .iter()
        .filter(|v| v.options.iter().all(|o| o.params.is_empty()))
        .map(|v| (v.name.value.clone(), v.options.iter().map(|o| o.name.value.clone()).collect()))
        .collect();
    let mut plain = SceneFeatures::everything();
    plain.effects.clear();
    plain.reflective = false;
    let mut planned = 0;
    for scene in [SceneFeatures::everything(), plain] {
        for config in configurations(&variants, crossed) {
            let old = s.plan(&before, &profile, &scene, &config).expect("the old pipeline plans");
            let new = s.plan(&after, &profile, &scene, &config).expect("the new pipeline plans");
            match by_text {
                false => assert_eq!(essence(&old, true), essence(&new, false), "{file} {config:?} on {}", scene.name),
                true => assert_eq!(
                    text_essence(&old, true),
                    text_essence(&new, false),
                    "{file} {config:?} on {}",
                    scene.name
                ),
            }
            planned += 1;
        }
    }
    assert!(!s.diags.has_errors(), "{}", s.render());
    planned
}

#[test]
fn deferred_with_choices_plans_what_its_copied_passes_planned() {
    let n = plans_agree("deferred.ron", &["lighting", "gbuffer", "cube_shadow", "aa"], false);
    assert!(n > 96, "{n} configurations");
}

#[test]
fn deferred_gi_with_choices_plans_what_its_copied_passes_planned() {
    // `deferred_gi` uses `deferred` now: it has the options of deferred's variants it does
    // not fix, `cube_shadow = dual_paraboloid` among them, which it did not have before.
    let n = plans_agree("deferred_gi.ron", &["cube_shadow", "indirect_diffuse", "aa"], true);
    assert!(n > 36, "{n} configurations");
}

const POST_WGSL: &str = r#"@group(0) @binding(0) var color: texture_2d<f32>;
@group(0) @binding(1) var linear: sampler;

@fragment
fn fs_main(@location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    return textureSample(color, linear, uv);
}

@fragment
fn fs_low(@location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    return textureSample(color, linear, uv) * 0.5;
}
"#;

const FILL_WGSL: &str = r#"@fragment
fn fs_main(@location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(uv, 0.0, 1.0);
}
"#;

/// A small LBP project whose `post` pass has the line `choice`.
fn lbp(choice: &str) -> Outcome {
    project("choice", choice, "")
}

/// The project `lbp` writes, with `more` (passes) after `post`.
fn project(tag: &str, line: &str, more: &str) -> Outcome {
    let text = format!(
        "pipeline t\n\nsampler linear: Linear\ntexture color: Rgba16Float viewport\ntexture out: Rgba8Unorm viewport\n\n\
         fullscreen fill \"fill.wgsl\" {{\n    color color\n}}\n\n\
         fullscreen post \"post.wgsl\" {{\n    reads color\n    color out\n    {line}\n}}\n\n{more}\
         variant quality = high {{\n    option high\n    option low\n    option fancy\n}}\n\noutput out\n"
    );
    let dir = write_project(
        tag,
        &[
            ("pipelines/t.lbp", &text),
            ("shaders/post.wgsl", POST_WGSL),
            ("shaders/fill.wgsl", FILL_WGSL),
        ],
    );
    check_project(&dir, "pipelines/t.lbp", &Profile::offline("vulkan").unwrap(), None)
}

/// `check` of a project of one pipeline file (`text` at `file`) and `fill.wgsl`.
fn checked(tag: &str, file: &str, text: &str) -> Outcome {
    let dir = write_project(tag, &[(file, text), ("shaders/fill.wgsl", FILL_WGSL)]);
    check_project(&dir, file, &Profile::offline("vulkan").unwrap(), None)
}

/// The first diagnostic: (code, message, line, column), and its notes.
fn first(o: &Outcome) -> ((String, String, usize, usize), Vec<String>) {
    let (code, msg, _, l, c) = o.located().into_iter().next().unwrap_or_else(|| panic!("no diagnostic"));
    ((code, msg, l, c), o.session.diags.list[0].notes.clone())
}

fn plan_stage_entry(o: &Outcome, quality: &str) -> String {
    let mut s = Session::new();
    let profile = Profile::offline("vulkan").unwrap();
    let v = [("quality".to_string(), quality.to_string())];
    let plan = s.plan_file(&o.dir.join("pipelines/t.lbp"), None, &profile, &SceneFeatures::everything(), &v);
    assert!(!s.diags.has_errors(), "{}", s.render());
    plan.unwrap().pass("post").unwrap().stages[1].entry.clone()
}

#[test]
fn a_choice_picks_the_field_for_each_option() {
    let o = lbp("fragment match(quality) { high | fancy: fs_main, low: fs_low }");
    assert!(o.session.diags.list.is_empty(), "{}", o.dump());
    assert_eq!(plan_stage_entry(&o, "high"), "fs_main");
    assert_eq!(plan_stage_entry(&o, "fancy"), "fs_main");
    assert_eq!(plan_stage_entry(&o, "low"), "fs_low");
    // `_` serves what no other arm names.
    let o = lbp("fragment match(quality) { low: fs_low, _: fs_main }");
    assert!(o.session.diags.list.is_empty(), "{}", o.dump());
    assert_eq!(plan_stage_entry(&o, "fancy"), "fs_main");
    assert_eq!(plan_stage_entry(&o, "low"), "fs_low");
}

#[test]
fn a_choice_missing_an_option_is_located_at_the_choice() {
    let o = lbp("fragment match(quality) { high: fs_main, low: fs_low }");
    let (d, notes) = first(&o);
    assert_eq!(
        d,
        ("choice-incomplete".into(), "no arm for option `fancy` of `quality`".into(), 14, 14),
        "{}",
        o.dump()
    );
    assert!(notes.iter().any(|n| n.contains("default arm `_`")), "{notes:?}");
}

/// Each incomplete choice of a pass is reported, not only the first.
#[test]
fn every_incomplete_choice_of_a_pass_is_reported() {
    let o = lbp("fragment match(quality) { high: fs_main }\n    cull match(quality) { low: Back }");
    let located: Vec<_> = o.located().into_iter().map(|(code, msg, _, l, c)| (code, msg, l, c)).collect();
    assert_eq!(
        located,
        [
            (
                "choice-incomplete".into(),
                "no arm for options `low`, `fancy` of `quality`".into(),
                14,
                14
            ),
            (
                "choice-incomplete".into(),
                "no arm for options `high`, `fancy` of `quality`".into(),
                15,
                10
            ),
        ],
        "{}",
        o.dump()
    );
}

#[test]
fn an_option_in_two_arms_is_located_at_the_second() {
    let o = lbp("fragment match(quality) { high | low: fs_main, low: fs_low, fancy: fs_main }");
    let (d, _) = first(&o);
    assert_eq!(
        d,
        ("choice-overlap".into(), "option `low` is chosen by two arms".into(), 14, 52),
        "{}",
        o.dump()
    );
}

/// Two catch-all arms: the second could never be chosen (the Plan silently took it before).
#[test]
fn two_catch_all_arms_overlap() {
    let o = lbp("fragment match(quality) { _: fs_main, _: fs_low }");
    let (d, _) = first(&o);
    assert_eq!(
        d,
        (
            "choice-overlap".into(),
            "two catch-all arms `_`: the second is never chosen".into(),
            14,
            43
        ),
        "{}",
        o.dump()
    );
}

/// `when` takes a condition, not a choice: in LBP too the documented `type-mismatch` at the
/// choice, with the condition that says it (it was a bare `lbp-syntax`, and `true`/`false`
/// arms dropped the pass without a word).
#[test]
fn a_choice_as_a_condition_is_a_type_mismatch_with_the_condition_to_write() {
    let o = lbp("when match(quality) { high: true, _: false }");
    let (d, notes) = first(&o);
    assert_eq!(
        d,
        (
            "type-mismatch".into(),
            "a choice cannot stand inside a value of `when`".into(),
            14,
            10
        ),
        "{}",
        o.dump()
    );
    assert!(notes.iter().any(|n| n.starts_with("`when` takes a condition")), "{notes:?}");
    // Spelt as the file's language writes it.
    assert!(o.dump().contains("`when` takes a condition: `variant(v, a | b)`"), "{}", o.dump());
    let o = lbp("when match(quality) { high: variant(quality, high), _: reflective }");
    assert_eq!(first(&o).0 .0, "type-mismatch", "{}", o.dump());
}

/// An unknown option, in a choice's arm or among a condition's options, is located where it
/// is written, with a suggestion.
#[test]
fn an_unknown_option_is_located_with_a_suggestion() {
    for (o, col, wanted) in [
        (
            lbp("fragment match(quality) { high | fancy: fs_main, lo: fs_low }"),
            54,
            ("lo", "low"),
        ),
        (conditioned("when variant(quality, high | fnacy)"), 27, ("fnacy", "fancy")),
    ] {
        let (d, notes) = first(&o);
        let message = format!("variant `quality` has no option `{}`", wanted.0);
        assert_eq!(d, ("unknown-variant-option".into(), message, 14, col), "{}", o.dump());
        assert_eq!(notes, [format!("did you mean `{}`?", wanted.1)]);
    }
}

#[test]
fn an_unknown_variant_is_located_with_a_suggestion() {
    let o = lbp("fragment match(qualty) { high | fancy: fs_main, low: fs_low }");
    let (d, notes) = first(&o);
    assert_eq!(
        d,
        ("unknown-variant".into(), "no variant `qualty` to choose by".into(), 14, 20),
        "{}",
        o.dump()
    );
    assert_eq!(notes, ["did you mean `quality`?"]);
}

#[test]
fn a_default_arm_that_serves_nothing_is_a_warning() {
    let o = lbp("fragment match(quality) { high | fancy: fs_main, low: fs_low, _: fs_main }");
    assert!(o.errors().is_empty(), "{}", o.dump());
    let (d, _) = first(&o);
    assert_eq!(d.0, "choice-incomplete");
    assert_eq!((d.2, d.3), (14, 67), "{}", o.dump());
}

#[test]
fn a_choice_inside_a_target_is_refused_where_it_stands() {
    let text = r#"Pipeline(
    name: "t",
    resources: {"out": Texture(format: Rgba8Unorm)},
    passes: [
        Fullscreen(name: "fill", shader: "fill.wgsl", color: [Target(resource: "out", blend: Match(variant: "q", arms: {"a": Add, "b": Alpha}))]),
    ],
    variants: {"q": Variant(default: "a", options: {"a": (), "b": ()})},
    output: "out",
)
"#;
    let o = checked("choice-misplaced", "pipelines/t.ron", text);
    let (d, notes) = first(&o);
    assert_eq!(
        d,
        (
            "type-mismatch".into(),
            "a choice cannot stand inside a value of `color`".into(),
            5,
            94
        ),
        "{}",
        o.dump()
    );
    assert!(notes[0].contains("elements of reads, writes, params, color"), "{notes:?}");
}

/// Both front ends write every form of a choice, and `convert` keeps them: RON -> LBP -> RON
/// gives the text it started from, and both lower to the same copies.
#[test]
fn choices_convert_between_ron_and_lbp_as_written() {
    use lightbench_compiler::front::{lbp as lbp_front, ron as ron_front};
    let o = lbp("fragment match(quality) { low: fs_low, _: fs_main }\n    \
         set match(quality) { low: (k = 1), fancy: match(quality) { fancy: (k = 2), _: (k = 3) }, high: () }\n    \
         writes match(quality) { low: (), _: () }");
    let text = std::fs::read_to_string(o.dir.join("pipelines/t.lbp")).unwrap();
    let mut s = Session::new();
    let p = s.parse_pipeline("t.lbp", text.clone()).unwrap_or_else(|| panic!("{}", s.render()));
    assert_eq!(p.passes.iter().filter(|x| x.name.value == "post").count(), 3);
    let ron = ron_front::print::print(&p, Some(&text));
    assert!(
        ron.contains(r#"fragment: Match(variant: "quality", arms: {"low": "fs_low", "_": "fs_main"})"#),
        "{ron}"
    );
    let back = s.parse_pipeline("t.ron", ron.clone()).unwrap_or_else(|| panic!("{}", s.render()));
    assert!(back.same_as(&p));
    let lbp_again = lbp_front::print::print(&back, Some(&ron));
    let again = s
        .parse_pipeline("u.lbp", lbp_again.clone())
        .unwrap_or_else(|| panic!("{lbp_again}\n{}", s.render()));
    assert_eq!(ron_front::print::print(&again, Some(&lbp_again)), ron);
}

/// A chosen `set` gives the pass's value parameter (`post.gain`) the chosen arm's value.
#[test]
fn chosen_values_become_the_pass_parameters_of_their_option() {
    const GAIN_WGSL: &str = r#"struct Params { gain: f32 };
@group(0) @binding(0) var color: texture_2d<f32>;
@group(0) @binding(1) var linear: sampler;
@group(0) @binding(2) var<uniform> params: Params;

@fragment
fn fs_main(@location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    return textureSample(color, linear, uv) * params.gain;
}
"#;
    let o = lbp("set match(quality) { low: (gain = 0.5), _: (gain = 1) }");
    std::fs::write(o.dir.join("shaders/post.wgsl"), GAIN_WGSL).unwrap();
    let profile = Profile::offline("vulkan").unwrap();
    for (option, gain) in [("low", 0.5), ("high", 1.0), ("fancy", 1.0)] {
        let mut s = Session::new();
        let v = [("quality".to_string(), option.to_string())];
        let plan = s.plan_file(&o.dir.join("pipelines/t.lbp"), None, &profile, &SceneFeatures::everything(), &v);
        assert!(!s.diags.has_errors(), "{}", s.render());
        let plan = plan.unwrap();
        let p = plan.params.iter().find(|p| p.name == "post.gain").expect("post.gain");
        assert_eq!(p.default, lightbench_compiler::ir::ParamValue::Float(gain), "{option}");
    }
}

/// A project whose `post` pass runs `when` the line says, and `plain` writes the output
/// otherwise (`variant(quality, low)`).
fn conditioned(when: &str) -> Outcome {
    project(
        "condition",
        when,
        "fullscreen plain \"fill.wgsl\" {\n    color out\n    when variant(quality, low)\n}\n\n",
    )
}

/// Whether the `post` pass runs with `quality = option`.
fn post_runs(o: &Outcome, quality: &str) -> bool {
    let mut s = Session::new();
    let v = [("quality".to_string(), quality.to_string())];
    let plan = s.plan_file(
        &o.dir.join("pipelines/t.lbp"),
        None,
        &Profile::offline("vulkan").unwrap(),
        &SceneFeatures::everything(),
        &v,
    );
    assert!(!s.diags.has_errors(), "{}", s.render());
    plan.unwrap().pass("post").is_some()
}

/// `variant(v, a | b)`: true while any of the options is chosen, as a choice's arm names them.
#[test]
fn a_condition_may_name_several_options_of_a_variant() {
    let o = conditioned("when variant(quality, high | fancy)");
    assert!(o.session.diags.list.is_empty(), "{}", o.dump());
    assert!(post_runs(&o, "high") && post_runs(&o, "fancy"));
    assert!(!post_runs(&o, "low"));
}

/// Only a variant's option may be several.
#[test]
fn only_a_variant_names_several_options() {
    let o = conditioned("when toggle(a | b)");
    let (d, _) = first(&o);
    assert_eq!((d.1.as_str(), d.2, d.3), ("expected `)`, found `|`", 14, 19), "{}", o.dump());
}

/// Where options are named (`variant(v, a | b)`, an arm `a | b:`) each name is trimmed and
/// `_` is every other option: an option no condition or arm could name is refused.
#[test]
fn an_option_that_cannot_be_named_is_refused_where_it_is_declared() {
    let text = "pipeline t\n\ntexture out: Rgba8Unorm viewport\n\nfullscreen fill \"fill.wgsl\" {\n    color out\n}\n\n\
                variant quality = high {\n    option high\n    option \" low\"\n    option \"_\"\n    option \"\"\n}\n\noutput out\n";
    let o = checked("unnameable", "pipelines/t.lbp", text);
    let found: Vec<(String, usize, usize)> = o.located().into_iter().map(|(_, m, _, l, c)| (m, l, c)).collect();
    let blanks = "be empty or begin or end with blanks: where options are named (`a | b`) each name is trimmed";
    assert_eq!(
        found,
        vec![
            (format!("option ` low`: a name may not {blanks}"), 11, 12),
            (
                "option `_`: a name may not be `_`, which stands for every option an arm of a choice does not name".into(),
                12,
                12
            ),
            (format!("option ``: a name may not {blanks}"), 13, 12),
        ],
        "{}",
        o.dump()
    );
}

/// `|` separates options where several are named, so no option's name may hold one.
#[test]
fn an_option_named_with_a_bar_is_refused_where_it_is_declared() {
    let text = "pipeline t\n\ntexture out: Rgba8Unorm viewport\n\nfullscreen fill \"fill.wgsl\" {\n    color out\n}\n\n\
                variant quality = high {\n    option high\n    option \"low|fast\"\n}\n\noutput out\n";
    let o = checked("bar", "pipelines/t.lbp", text);
    let (d, _) = first(&o);
    assert_eq!(
        d,
        (
            "type-mismatch".into(),
            "option `low|fast`: a name may not contain `|`, which separates options (`a | b`)".into(),
            11,
            12
        ),
        "{}",
        o.dump()
    );
}
