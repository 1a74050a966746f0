//! The compile workspace a long-running process holds: between compilations it recompiles
//! only the shader modules whose text changed, reports every file a result depended on
//! (included files, and files that do not exist yet), and bounds its module cache.

use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::vfs::MemoryVfs;
use lightbench_compiler::{Executable, Workspace};
use std::path::{Path, PathBuf};
use std::sync::Arc;

const PIPELINE: &str = r#"Pipeline(
    name: "two",
    resources: {
        "a": Texture(format: Rgba8Unorm),
        "out": Texture(format: Rgba8Unorm),
    },
    passes: [
        Fullscreen(name: "first", shader: "a.wgsl", color: ["a"]),
        Fullscreen(name: "second", shader: "b.wgsl", reads: ["a"], color: ["out"]),
    ],
    output: "out",
)
"#;

fn a_wgsl(value: f32) -> String {
    format!("@fragment\nfn fs_main() -> @location(0) vec4<f32> {{\n    return vec4<f32>({value:?});\n}}\n")
}

const B_WGSL: &str = "#include \"lib/tint.wgsl\"\n@group(0) @binding(0) var a: texture_2d<f32>;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    return tint(textureLoad(a, vec2<i32>(p.xy), 0));\n}\n";

fn tint(scale: f32) -> String {
    format!("fn tint(c: vec4<f32>) -> vec4<f32> {{\n    return c * {scale:?};\n}}\n")
}

fn project() -> Arc<MemoryVfs> {
    let vfs = Arc::new(MemoryVfs::new());
    vfs.write("proj/pipelines/p.ron", PIPELINE);
    vfs.write("proj/shaders/a.wgsl", a_wgsl(0.5));
    vfs.write("proj/shaders/b.wgsl", B_WGSL);
    vfs.write("proj/shaders/lib/tint.wgsl", tint(2.0));
    vfs
}

fn compile(ws: &Workspace) -> (Option<Executable>, lightbench_compiler::Session) {
    let mut s = ws.session();
    let exe = s.executable(
        Path::new("proj/pipelines/p.ron"),
        None,
        &Profile::vulkan(),
        &SceneFeatures::everything(),
        &[],
    );
    (exe, s)
}

#[test]
fn only_the_changed_module_is_recompiled() {
    let vfs = project();
    let ws = Workspace::new(vfs.clone());
    let (exe, s) = compile(&ws);
    assert!(exe.is_some(), "{}", s.render());
    // a.wgsl, b.wgsl (with its include) and the built-in fullscreen vertex stage.
    assert_eq!(ws.modules().stats().compiled, 3);

    // Unchanged: nothing is compiled again.
    let (exe, _) = compile(&ws);
    assert!(exe.is_some());
    assert_eq!(ws.modules().stats().compiled, 3);

    // One of the two shaders changes: exactly one module is compiled.
    vfs.write("proj/shaders/a.wgsl", a_wgsl(0.25));
    let (exe, _) = compile(&ws);
    let exe = exe.expect("compiles");
    assert_eq!(ws.modules().stats().compiled, 4);
    let first = &exe.modules[0];
    let second = &exe.modules[1];
    assert!(first[1].expanded.text.contains("0.25"), "the new text was compiled");

    // A change in an included file recompiles the module that includes it, and only that.
    vfs.write("proj/shaders/lib/tint.wgsl", tint(3.0));
    let (exe, _) = compile(&ws);
    let again = exe.expect("compiles");
    assert_eq!(ws.modules().stats().compiled, 5);
    assert_eq!(again.modules[0][1].hash, first[1].hash, "a.wgsl is the same module");
    assert_ne!(again.modules[1][1].hash, second[1].hash, "b.wgsl changed through its include");
}

#[test]
fn a_broken_edit_is_reported_and_the_last_good_text_is_still_cached() {
    let vfs = project();
    let ws = Workspace::new(vfs.clone());
    assert!(compile(&ws).0.is_some());
    vfs.write(
        "proj/shaders/a.wgsl",
        "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0) +;\n}\n",
    );
    let (exe, s) = compile(&ws);
    assert!(exe.is_none());
    let d = s.diags.errors().next().expect("an error");
    assert_eq!(d.code, "wgsl-parse");
    let (file, line, _) = d.location(&s.sources).unwrap();
    assert_eq!((file.as_str(), line), ("proj/shaders/a.wgsl", 3));
    // Undoing the edit finds the earlier module: no compilation.
    let before = ws.modules().stats().compiled;
    vfs.write("proj/shaders/a.wgsl", a_wgsl(0.5));
    assert!(compile(&ws).0.is_some());
    assert_eq!(ws.modules().stats().compiled, before);
}

#[test]
fn the_dependency_set_names_every_file_read_including_includes() {
    let ws = Workspace::new(project());
    let (exe, s) = compile(&ws);
    let exe = exe.expect("compiles");
    let expected: Vec<PathBuf> = [
        "proj/pipelines/p.ron",
        "proj/shaders/a.wgsl",
        "proj/shaders/b.wgsl",
        "proj/shaders/lib/tint.wgsl",
    ]
    .iter()
    .map(PathBuf::from)
    .collect();
    assert_eq!(exe.files.iter().cloned().collect::<Vec<_>>(), expected);
    assert_eq!(s.dependencies(), &exe.files);
}

#[test]
fn a_missing_include_is_a_dependency_too() {
    // A watcher must see the file appear.
    let vfs = project();
    vfs.remove("proj/shaders/lib/tint.wgsl");
    let ws = Workspace::new(vfs.clone());
    let (exe, s) = compile(&ws);
    assert!(exe.is_none());
    assert!(s.diags.errors().any(|d| d.code == "include-not-found"), "{}", s.render());
    assert!(
        s.dependencies().contains(Path::new("proj/shaders/lib/tint.wgsl")),
        "{:?}",
        s.dependencies()
    );
    vfs.write("proj/shaders/lib/tint.wgsl", tint(2.0));
    assert!(compile(&ws).0.is_some());
}

#[test]
fn the_module_cache_is_bounded() {
    let vfs = project();
    let ws = Workspace::new(vfs.clone()).with_module_capacity(2);
    assert!(compile(&ws).0.is_some());
    let stats = ws.modules().stats();
    assert_eq!((stats.entries, stats.evicted), (2, 1), "{stats:?}");
    for v in 1..=5 {
        vfs.write("proj/shaders/a.wgsl", a_wgsl(v as f32 / 10.0));
        assert!(compile(&ws).0.is_some());
        assert!(ws.modules().stats().entries <= 2);
    }
}
