//! Pipelines checked in one run share compiled shaders; errors stay located per session.

mod common;

use common::*;
use lightbench_compiler::profile::Profile;
use lightbench_compiler::Workspace;
use std::sync::Arc;

const FILL: &str = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0);\n}\n";

fn pipeline(name: &str) -> String {
    format!("Pipeline(name: \"{name}\", resources: {{\"out\": Texture(format: Rgba8Unorm)}}, passes: [Fullscreen(name: \"f\", shader: \"fill.wgsl\", color: [\"out\"])], output: \"out\")")
}

#[test]
fn shared_cache_compiles_a_shader_once() {
    let dir = write_project(
        "cache",
        &[
            ("pipelines/a.ron", &pipeline("a")),
            ("pipelines/b.ron", &pipeline("b")),
            ("shaders/fill.wgsl", FILL),
        ],
    );
    let ws = Workspace::disk();
    let scene = lightbench_compiler::scene::SceneFeatures::everything();
    let mut modules = vec![];
    for p in ["a", "b"] {
        let mut s = ws.session();
        let exe = s
            .executable(&dir.join(format!("pipelines/{p}.ron")), None, &Profile::vulkan(), &scene, &[])
            .unwrap();
        modules.push(exe.modules[0][1].clone());
    }
    assert!(
        Arc::ptr_eq(&modules[0].compiled, &modules[1].compiled),
        "the second pipeline reused the compiled module"
    );
    // Each session still has its own source map: spans point into its own files.
    assert_ne!(Arc::as_ptr(&modules[0]), Arc::as_ptr(&modules[1]));
}

#[test]
fn broken_shader_is_reported_in_every_session() {
    let dir = write_project(
        "cache-err",
        &[
            ("pipelines/a.ron", &pipeline("a")),
            ("pipelines/b.ron", &pipeline("b")),
            (
                "shaders/fill.wgsl",
                "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0) +;\n}\n",
            ),
        ],
    );
    let ws = Workspace::disk();
    for p in ["a", "b"] {
        let mut s = ws.session();
        s.check_file(&dir.join(format!("pipelines/{p}.ron")), None, &Profile::vulkan(), None);
        let d = s.diags.errors().next().expect("error in each session");
        assert_eq!(d.code, "wgsl-parse");
        let (f, l, _) = d.location(&s.sources).unwrap();
        assert!(f.ends_with("fill.wgsl") && l == 3, "{f}:{l}");
    }
}

/// `check` runs its files in parallel: each shader they share is still compiled once (the
/// others wait for it or take other work), and each file's report stays its own, in order.
#[test]
fn files_checked_together_compile_a_shared_shader_once() {
    let names = ["a", "b", "c", "d", "e", "f", "g", "h"];
    let mut files: Vec<(String, String)> = names.iter().map(|n| (format!("pipelines/{n}.ron"), pipeline(n))).collect();
    // One broken pipeline among them, in the middle.
    files[3].1 = files[3].1.replace("\"out\")", "\"nowhere\")");
    files.push(("shaders/fill.wgsl".into(), FILL.into()));
    let refs: Vec<(&str, &str)> = files.iter().map(|(p, t)| (p.as_str(), t.as_str())).collect();
    let dir = write_project("cache-parallel", &refs);
    let ws = Workspace::disk();
    let paths: Vec<_> = names.iter().map(|n| dir.join(format!("pipelines/{n}.ron"))).collect();
    let sessions = ws.check_files(&paths, None, &Profile::vulkan(), None);
    assert_eq!(sessions.len(), names.len());
    for (i, s) in sessions.iter().enumerate() {
        let errors: Vec<_> = s.diags.errors().collect();
        if i == 3 {
            let d = errors.first().expect("the broken pipeline's error is in its own session");
            let (f, _, _) = d.location(&s.sources).unwrap();
            assert!(f.ends_with("d.ron"), "{f}");
        } else {
            assert!(errors.is_empty(), "{}: {}", names[i], s.render());
        }
    }
    // The fragment shader and the built-in full-screen vertex stage, once each.
    assert_eq!(ws.module_stats().compiled, 2, "{:?}", ws.module_stats());
}

/// A pipeline file several files of one run parse (itself, and the one that `use`s it) is
/// parsed once and shared; an error found in it afterwards is still located in it, in each
/// session's own copy, at the same line and column.
#[test]
fn a_used_pipeline_parsed_once_is_located_in_every_session() {
    // `base.ron` parses cleanly but names a resource it lacks (a lowering/check error).
    let base = pipeline("base").replace("color: [\"out\"]", "color: [\"nowhere\"]");
    let user = "Pipeline(name: \"user\", use: \"base.ron\")";
    let dir = write_project(
        "cache-used",
        &[
            ("pipelines/base.ron", &base),
            ("pipelines/user.ron", user),
            ("shaders/fill.wgsl", FILL),
        ],
    );
    // `base.ron` is parsed in its own session first, so the second takes it.
    let at: Vec<(String, usize, usize)> = first_errors_in_order(&dir, &["base.ron", "user.ron"])
        .into_iter()
        .map(|(at, _)| at)
        .collect();
    let col = base.find("\"nowhere\"").unwrap() + 1;
    for (f, l, c) in &at {
        assert!(
            f.ends_with("base.ron") && *l == 1 && *c == col,
            "{f}:{l}:{c}, want base.ron:1:{col}"
        );
    }
}

/// A shader the files of one run share is expanded once (its includes spliced in) and the
/// others take that expansion into their own source maps: an error in an included file is
/// located in it in every session, though the files sit at other places in each map.
#[test]
fn a_shared_expansion_is_located_in_every_session() {
    let helpers = "fn helper() -> f32 {\n    return 1u;\n}\n";
    let lit = "#include \"lib/helpers.wgsl\"\n@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(helper());\n}\n";
    let a = "Pipeline(name: \"a\", resources: {\"out\": Texture(format: Rgba8Unorm)}, passes: [Fullscreen(name: \"f\", shader: \"lit.wgsl\", color: [\"out\"])], output: \"out\")";
    // `b` loads another shader first: its source map holds the shared files at other ids.
    let b = "Pipeline(name: \"b\", resources: {\"out\": Texture(format: Rgba8Unorm), \"first\": Texture(format: Rgba8Unorm)}, \
             passes: [Fullscreen(name: \"e\", shader: \"fill.wgsl\", color: [\"first\"]), Fullscreen(name: \"f\", shader: \"lit.wgsl\", color: [\"out\"])], output: \"out\")";
    let dir = write_project(
        "cache-expanded",
        &[
            ("pipelines/a.ron", a),
            ("pipelines/b.ron", b),
            ("shaders/fill.wgsl", FILL),
            ("shaders/lit.wgsl", lit),
            ("shaders/lib/helpers.wgsl", helpers),
        ],
    );
    // `a` expands `lit.wgsl` first, `b` takes its expansion.
    for ((f, l, c), report) in first_errors_in_order(&dir, &["a.ron", "b.ron"]) {
        // The invalid function, with `1u` marked in it on line 2.
        assert!(f.ends_with("helpers.wgsl") && (l, c) == (1, 1), "{f}:{l}:{c}\n{report}");
        assert!(report.contains("2 │ │     return 1u;"), "{report}");
    }
}

/// Check `pipelines/<file>` of `dir` in one run, on one thread (so in the order given, each
/// taking what the ones before made): each session's first error, located, and its report.
fn first_errors_in_order(dir: &std::path::Path, files: &[&str]) -> Vec<((String, usize, usize), String)> {
    let ws = Workspace::disk();
    let paths: Vec<_> = files.iter().map(|f| dir.join("pipelines").join(f)).collect();
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let sessions = one.install(|| ws.check_files(&paths, None, &Profile::vulkan(), None));
    sessions
        .iter()
        .map(|s| {
            let report = s.render();
            let d = s
                .diags
                .errors()
                .next()
                .unwrap_or_else(|| panic!("an error in each session: {report}"));
            (d.location(&s.sources).unwrap(), report)
        })
        .collect()
}
