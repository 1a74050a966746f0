//! Pipelines built on others (`use`): the README's example as written, the bundled
//! `deferred_gi` (which uses `deferred`), and a located error for each mistake.

mod common;

use common::*;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;
use std::path::{Path, PathBuf};

/// A project with the bundled `deferred.lbp` (and its data files) beside `files`.
fn beside_deferred(tag: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = temp_dir(tag);
    for f in std::fs::read_dir(repo_root().join("pipelines")).unwrap().map(|e| e.unwrap().path()) {
        if f.extension().is_some_and(|e| e == "json" || e == "lbp") {
            std::fs::copy(&f, dir.join("pipelines").join(f.file_name().unwrap())).unwrap();
        }
    }
    for (name, text) in files {
        std::fs::write(dir.join("pipelines").join(name), text).unwrap();
    }
    dir
}

fn check(dir: &Path, file: &str) -> Outcome {
    let mut s = Session::new();
    let shaders = repo_root().join("shaders");
    s.check_file(
        &dir.join("pipelines").join(file),
        Some(&shaders),
        &Profile::offline("vulkan").unwrap(),
        None,
    );
    Outcome {
        session: s,
        dir: dir.to_path_buf(),
    }
}

fn readme_example() -> String {
    let readme = common::manual();
    let after = readme.split("A pipeline that uses the bundled one").nth(1).expect("the section");
    after.split("```\n").nth(1).expect("its code block").to_string()
}

#[test]
fn the_readme_example_builds_on_the_bundled_pipeline() {
    let text = readme_example();
    let dir = beside_deferred("readme-use", &[("brighter.lbp", &text)]);
    let o = check(&dir, "brighter.lbp");
    assert!(o.errors().is_empty(), "{}", o.dump());
    let mut s = Session::new();
    let shaders = repo_root().join("shaders");
    let profile = Profile::offline("vulkan").unwrap();
    let path = dir.join("pipelines/brighter.lbp");
    let plan = s
        .plan_file(&path, Some(&shaders), &profile, &SceneFeatures::everything(), &[])
        .unwrap_or_else(|| panic!("{}", s.render()));
    // Placed after `ambient`, before the light passes that add to `hdr` too.
    let names: Vec<&str> = plan.passes.iter().map(|p| p.name.as_str()).collect();
    let at = |n: &str| names.iter().position(|x| *x == n).unwrap_or_else(|| panic!("no {n} in {names:?}"));
    assert_eq!(at("more_ambient"), at("ambient") + 1, "{names:?}");
    assert!(at("light_directional_spot") > at("more_ambient"));
    assert_eq!(plan.pass("ambient").unwrap().from.as_deref(), Some("deferred.lbp"));
    assert_eq!(plan.pass("more_ambient").unwrap().from, None);
    assert!(lightbench_compiler::plan::to_text(&plan, true).contains("      from: deferred.lbp"));
    let threshold = plan.params.iter().find(|p| p.name == "bloom.threshold").unwrap();
    assert_eq!(threshold.default, lightbench_compiler::ir::ParamValue::Float(2.0));
    // The fixed variant is gone, and with it the pass that could not run any more.
    assert!(plan.variants.iter().all(|v| v.variant != "gbuffer"));
    assert!(!plan.culled.iter().any(|c| c.name == "gbuffer_fat_position"));
    // The used file is one the compilation read: hot reload follows it.
    assert!(
        s.dependencies().iter().any(|d| d.ends_with("deferred.lbp")),
        "{:?}",
        s.dependencies()
    );
    // `fmt` keeps the file as written; RON and back gives the same pipeline.
    let p = s.parse_pipeline(&path.display().to_string(), text.clone()).unwrap();
    assert_eq!(lightbench_compiler::front::lbp::print::print(&p, Some(&text)), text);
    let ron = lightbench_compiler::front::ron::print::print(&p, Some(&text));
    assert!(ron.contains("use: \"deferred.lbp\"") && ron.contains("Replace(Float("), "{ron}");
    let back = s
        .parse_pipeline(&dir.join("pipelines/brighter.ron").display().to_string(), ron)
        .unwrap();
    assert!(back.same_as(&p));
}

/// (the file's text, code, message, line, column) of the first diagnostic.
fn first_error(tag: &str, text: &str) -> (String, String, String, usize, usize) {
    let dir = beside_deferred(tag, &[("t.lbp", text)]);
    let o = check(&dir, "t.lbp");
    let d = o.located().into_iter().next().unwrap_or_else(|| panic!("no diagnostic for {text}"));
    (d.0, d.1, d.2, d.3, d.4)
}

fn using(lines: &str) -> String {
    format!("pipeline t\n\nuse \"deferred.lbp\"\n{lines}\n")
}

#[test]
fn each_composition_mistake_is_located() {
    let cases: &[(&str, &str, &str, &str, usize, usize)] = &[
        (
            "fullscreen ambient \"ambient.wgsl\" {\n    color hdr\n}",
            "duplicate-name",
            "pass `ambient` is declared by the used pipeline too",
            "pipelines/t.lbp",
            4,
            1,
        ),
        (
            "param bloom.threshold: Float = 2",
            "duplicate-name",
            "param `bloom.threshold` is declared by the used pipeline too",
            "pipelines/t.lbp",
            4,
            7,
        ),
        (
            "replace param bloom.treshold: Float = 2",
            "unknown-key",
            "nothing to replace: the used pipeline has no param `bloom.treshold`",
            "pipelines/t.lbp",
            4,
            15,
        ),
        (
            "remove pass ambiant",
            "unknown-pass",
            "the used pipeline has no pass `ambiant`",
            "pipelines/t.lbp",
            4,
            1,
        ),
        (
            "fullscreen x \"ambient.wgsl\" {\n    after ambiant\n    color hdr\n}",
            "unknown-pass",
            "no pass `ambiant` to place this pass after",
            "pipelines/t.lbp",
            5,
            11,
        ),
        (
            "fix gbufer = packed",
            "unknown-variant",
            "no variant `gbufer` to fix",
            "pipelines/t.lbp",
            4,
            5,
        ),
        (
            "fix gbuffer = fat",
            "variant-unsupported",
            "option `fat` of `gbuffer` cannot be fixed: it needs features or limits, sets parameters, substitutes shaders or jitters",
            "pipelines/t.lbp",
            4,
            15,
        ),
    ];
    for (i, (lines, code, msg, file, line, col)) in cases.iter().enumerate() {
        let got = first_error(&format!("compose-{i}"), &using(lines));
        assert_eq!(
            got,
            (code.to_string(), msg.to_string(), file.to_string(), *line, *col),
            "case {i}: {lines}"
        );
    }
}

/// An `after` typo is one error, not one more for each pass placed after the mistyped one;
/// the file's own passes are among the names suggested, and one declared later is said so.
#[test]
fn placing_after_reports_each_mistake_once_and_knows_the_files_own_passes() {
    let text = using(
        "fullscreen x \"ambient.wgsl\" {\n    after tonemapp\n    color hdr\n}\n\
         fullscreen y \"ambient.wgsl\" {\n    after x\n    color hdr\n}\n\
         fullscreen z \"ambient.wgsl\" {\n    after w\n    color hdr\n}\n\
         fullscreen extra_pass \"ambient.wgsl\" {\n    after extra_pas\n    color hdr\n}\n\
         fullscreen w \"ambient.wgsl\" {\n    color hdr\n}",
    );
    let dir = beside_deferred("after-once", &[("t.lbp", &text)]);
    let o = check(&dir, "t.lbp");
    let placing: Vec<_> = (o.session.diags.list.iter())
        .filter(|d| d.message.contains("to place this pass after"))
        .map(|d| (d.message.clone(), d.notes.join("; ")))
        .collect();
    assert_eq!(placing.len(), 3, "{placing:?}");
    assert_eq!(placing[0].0, "no pass `tonemapp` to place this pass after");
    assert_eq!(placing[0].1, "did you mean `tonemap`?");
    assert!(placing[1].1.contains("`w` is declared later in this file"), "{placing:?}");
    // The file's own passes are listed, not the pass being placed.
    assert!(placing[2].1.contains("`taa`, `x`, `y`, `z`, `w`"), "{placing:?}");
    assert!(!placing[2].1.contains("`extra_pass`"), "{placing:?}");
}

#[test]
fn used_files_that_cannot_be_used_are_errors_at_the_use() {
    // Missing, outside the directory, and pipelines that use each other.
    let got = first_error("use-missing", "pipeline t\nuse \"nowhere.lbp\"\n");
    assert_eq!((got.0.as_str(), got.3, got.4), ("file-not-found", 2, 5), "{got:?}");
    let got = first_error("use-outside", "pipeline t\nuse \"../deferred.lbp\"\n");
    assert_eq!((got.0.as_str(), got.3, got.4), ("outside-root", 2, 5), "{got:?}");
    // A link in the directory that leads out of it.
    let outside = beside_deferred("use-link-target", &[]);
    let dir = beside_deferred("use-link", &[("t.lbp", "pipeline t\nuse \"linked.lbp\"\n")]);
    std::os::unix::fs::symlink(outside.join("pipelines/deferred.lbp"), dir.join("pipelines/linked.lbp")).unwrap();
    let d = check(&dir, "t.lbp").located().into_iter().next().expect("a diagnostic");
    assert_eq!((d.0.as_str(), d.3, d.4), ("outside-root", 2, 5), "{d:?}");
    let dir = beside_deferred(
        "use-cycle",
        &[("a.lbp", "pipeline a\nuse \"b.lbp\"\n"), ("b.lbp", "pipeline b\nuse \"a.lbp\"\n")],
    );
    let o = check(&dir, "a.lbp");
    let d = &o.located()[0];
    assert_eq!(
        (d.0.as_str(), d.2.as_str(), d.3),
        ("include-cycle", "pipelines/b.lbp", 2),
        "{}",
        o.dump()
    );
    assert!(d.1.contains("pipelines use each other"), "{}", d.1);
    // Named in the order written: a uses b, which uses a.
    let names: Vec<&str> = d.1.split(": ").nth(1).unwrap().split(" -> ").collect();
    let files: Vec<&str> = names.iter().map(|n| n.rsplit('/').next().unwrap()).collect();
    assert_eq!(files, ["a.lbp", "b.lbp", "a.lbp"], "{}", d.1);
}

/// A second `use` is a located error (it was dropped without a word), pointing at the first.
#[test]
fn a_second_use_is_an_error_at_it() {
    let text = "pipeline two\nuse \"a.lbp\"\nuse \"deferred.lbp\"\n";
    let dir = beside_deferred("use-twice", &[("a.lbp", "pipeline a\nuse \"deferred.lbp\"\n"), ("t.lbp", text)]);
    let o = check(&dir, "t.lbp");
    let d = &o.located()[0];
    assert_eq!(
        (d.0.as_str(), d.1.as_str(), d.3, d.4),
        ("duplicate-key", "`use` is given twice: a pipeline uses one other", 3, 1),
        "{}",
        o.dump()
    );
    // The same in a RON pipeline.
    let ron = "Pipeline(\n    name: \"two\",\n    use: \"a.lbp\",\n    use: \"deferred.lbp\",\n)\n";
    let dir = beside_deferred("use-twice-ron", &[("a.lbp", "pipeline a\nuse \"deferred.lbp\"\n"), ("t.ron", ron)]);
    let o = check(&dir, "t.ron");
    let d = &o.located()[0];
    assert_eq!((d.0.as_str(), d.3, d.4), ("duplicate-key", 4, 5), "{}", o.dump());
}

#[test]
fn fixing_without_a_used_pipeline_is_misplaced() {
    let text = "pipeline t\nfix q = a\ntexture out: Rgba8Unorm viewport\noutput out\n";
    let got = first_error("fix-alone", text);
    assert_eq!(
        (got.0.as_str(), got.1.as_str(), got.3, got.4),
        (
            "misplaced",
            "`fix`: only a pipeline that uses another (`use: \"file\"`) can fix its variants",
            2,
            1
        )
    );
}

#[test]
fn composing_without_a_used_pipeline_is_misplaced() {
    let text = "pipeline t\ntexture out: Rgba8Unorm viewport\nfullscreen f \"fill.wgsl\" {\n    after g\n    color out\n}\noutput out\n";
    let got = first_error("compose-alone", text);
    assert_eq!(
        got,
        (
            "misplaced".into(),
            "`after`: only a pipeline that uses another (`use: \"file\"`) can place or replace its passes".into(),
            "pipelines/t.lbp".into(),
            4,
            5
        )
    );
}

/// Composition keys of the wrong shape are type errors where they stand, never ignored.
#[test]
fn composition_keys_of_the_wrong_shape_are_type_errors() {
    for (keys, message) in [
        ("use: 5,", "expected a pipeline file name, found an integer"),
        ("use: \"deferred.lbp\", fix: [\"a\"],", "expected a map `{...}`, found a list"),
        (
            "use: \"deferred.lbp\", remove: \"x\",",
            "expected a list `[Pass(\"name\"), ...]`, found a string",
        ),
        (
            "use: \"deferred.lbp\", passes: [Fullscreen(name: \"x\", shader: \"ambient.wgsl\", after: 5, color: [\"hdr\"])],",
            "expected a pass name, found an integer",
        ),
    ] {
        let text = format!("Pipeline(name: \"t\", {keys} output: \"ldr\")\n");
        let dir = beside_deferred("compose-shape", &[("t.ron", &text)]);
        let o = check(&dir, "t.ron");
        let first = o.located().into_iter().next().unwrap_or_else(|| panic!("no diagnostic for {keys}"));
        assert_eq!(
            (first.0.as_str(), first.1.as_str()),
            ("type-mismatch", message),
            "{keys}\n{}",
            o.dump()
        );
    }
}
