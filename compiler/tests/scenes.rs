//! The scene front end: every bad value a located error naming the item and field, built-in
//! scenes and `builtin:` merging, the README's and the bundled scene files. (Mutated scene
//! files are the runtime's `scene_files` test: accepted ones are rendered there.)

mod common;

use common::repo_root;
use lightbench_compiler::diag::Diagnostics;
use lightbench_compiler::ir::{Effect, LightKind};
use lightbench_compiler::scene::{self, SceneDesc};
use lightbench_compiler::span::SourceMap;
use std::path::Path;

/// Load scene text as if from `scenes/t.ron`.
fn load(text: &str) -> (Option<SceneDesc>, Diagnostics, SourceMap) {
    let mut sources = SourceMap::new();
    let mut diags = Diagnostics::default();
    let desc = scene::load_text(Path::new("scenes/t.ron"), text.to_string(), &mut sources, &mut diags);
    (desc, diags, sources)
}

/// (code, message, line, column) of each diagnostic.
fn located(text: &str) -> Vec<(String, String, usize, usize)> {
    let (_, diags, sources) = load(text);
    diags
        .list
        .iter()
        .map(|d| {
            let (_, l, c) = d.location(&sources).unwrap_or_default();
            (d.code.to_string(), d.message.clone(), l, c)
        })
        .collect()
}

/// A valid scene with one light of each kind, a model and a camera; cases edit one line.
const BASE: &str = r#"Scene(
    size: (64, 48),
    camera: (position: (0.0, 1.0, 3.0), fov: 50.0, near: 0.1, far: 50.0),
    models: [(path: "chair.gltf", scale: 0.5, triangles: 0.5)],
    lights: [
        Point(position: (0.0, 1.8, 0.0), intensity: 4.0, range: 6.0),
        Spot(position: (0.0, 3.0, 0.0), direction: (0.0, -1.0, 0.0), inner: 18.0, outer: 20.0, range: 10.0),
        Directional(direction: (0.4, -0.6, 0.5), intensity: 2.0),
    ],
    effects: [Shadows],
)
"#;

/// Replace `from` by `to` in BASE and expect [code] with `msg` pointing at the first `at`
/// from the edit on (1-based line and column, checked against the diagnostic's).
fn expect(from: &str, to: &str, code: &str, msg: &str, at: &str) {
    let start = BASE.find(from).unwrap_or_else(|| panic!("edit target `{from}` not in BASE"));
    let text = BASE.replacen(from, to, 1);
    let pos = start + text[start..].find(at).unwrap_or_else(|| panic!("`{at}` not in the edited text"));
    let line = text[..pos].matches('\n').count() + 1;
    let col = text[..pos].rsplit('\n').next().unwrap().chars().count() + 1;
    let found = located(&text);
    let hit = found
        .iter()
        .any(|(c, m, l, co)| c == code && m.contains(msg) && (*l, *co) == (line, col));
    assert!(hit, "expected [{code}] {msg:?} at {line}:{col}; got {found:#?}");
}

#[test]
fn base_scene_is_valid() {
    let (desc, diags, _) = load(BASE);
    assert!(diags.list.is_empty(), "{:?}", diags.list);
    let d = desc.unwrap();
    assert_eq!((d.name.as_str(), d.size, d.lights.len()), ("t", (64, 48), 3));
    assert_eq!(
        d.models[0].file,
        Path::new("scenes/chair.gltf"),
        "model paths resolve against the scene file"
    );
    assert_eq!(d.lights[0].color, [1.0, 1.0, 1.0], "defaults come from the table");
}

#[test]
fn non_finite_numbers_name_the_item_and_field() {
    expect(
        "intensity: 4.0",
        "intensity: NaN",
        "non-finite",
        "`intensity` of light 1 (point) is not finite",
        "intensity",
    );
    expect(
        "position: (0.0, 1.0, 3.0)",
        "position: (0.0, inf, 3.0)",
        "non-finite",
        "`position` of the camera",
        "position",
    );
    expect(
        "scale: 0.5",
        "scale: 1e39",
        "non-finite",
        "`scale` of model `chair.gltf` is not finite",
        "scale",
    );
    expect(
        "direction: (0.4, -0.6, 0.5)",
        "direction: (0.4, -inf, 0.5)",
        "non-finite",
        "of light 3 (directional)",
        "direction",
    );
}

#[test]
fn camera_values_out_of_range() {
    expect(
        "fov: 50.0",
        "fov: 180.0",
        "value-out-of-range",
        "`fov` of the camera must be at least 0.001 and below 180 degrees",
        "fov",
    );
    expect("fov: 50.0", "fov: 0", "value-out-of-range", "`fov` of the camera", "fov");
    expect(
        "fov: 50.0",
        "fov: 50.0, yaw: 3e38",
        "value-out-of-range",
        "`yaw` of the camera must be within ±1e6 degrees",
        "yaw",
    );
    expect(
        "near: 0.1",
        "near: 0.0",
        "value-out-of-range",
        "`near` of the camera must be greater than 0",
        "near",
    );
    expect(
        "far: 50.0",
        "far: 0.1",
        "value-out-of-range",
        "`far` of the camera must be greater than `near` (0.1)",
        "far",
    );
}

/// Camera animation: an orbit, or a path whose keys must come at increasing times.
#[test]
fn camera_animation_is_checked() {
    let orbit = BASE.replace("far: 50.0)", "far: 50.0, animation: Orbit(center: (0.0, 1.0, 0.0), speed: 30.0))");
    assert!(located(&orbit).is_empty(), "{:?}", located(&orbit));
    let path = "far: 50.0, animation: Path(keys: [Key(time: 0.0, position: (0.0, 1.0, 3.0)), Key(time: 1.0, position: (1.0, 1.0, 3.0), yaw: 10.0)]))";
    let ok = BASE.replace("far: 50.0)", path);
    assert!(located(&ok).is_empty(), "{:?}", located(&ok));
    expect(
        "far: 50.0)",
        &path.replace("time: 1.0", "time: 0.0"),
        "value-out-of-range",
        "the camera's path keys must be at increasing times: key 1 at 0 s follows 0 s",
        "animation",
    );
    expect(
        "far: 50.0)",
        "far: 50.0, animation: Path(keys: []))",
        "value-out-of-range",
        "the camera's path has no keys",
        "animation",
    );
    // A finite angle of 3e38° is all rounding (a black frame): refused, as the camera's own.
    expect(
        "far: 50.0)",
        &path.replace("yaw: 10.0", "yaw: 3e38"),
        "value-out-of-range",
        "must be a path whose key angles are within ±1e6 degrees",
        "animation",
    );
    expect(
        "far: 50.0)",
        "far: 50.0, animation: Orbit(centre: (0.0, 1.0, 0.0), speed: 30.0))",
        "unknown-key",
        "centre",
        "centre",
    );
}

#[test]
fn light_values_out_of_range() {
    expect(
        "range: 6.0",
        "range: 0.0",
        "value-out-of-range",
        "`range` of light 1 (point) must be greater than 0",
        "range",
    );
    expect(
        "intensity: 4.0",
        "intensity: -1.0",
        "value-out-of-range",
        "`intensity` of light 1 (point) must be 0 or more",
        "intensity",
    );
    expect(
        "direction: (0.0, -1.0, 0.0)",
        "direction: (0.0, 0.0, 0.0)",
        "value-out-of-range",
        "`direction` of light 2 (spot) is the zero vector",
        "direction",
    );
    expect(
        "inner: 18.0",
        "inner: 25.0",
        "value-out-of-range",
        "`inner` of light 2 (spot) must be at most `outer` (20)",
        "inner",
    );
    expect(
        "outer: 20.0",
        "outer: 90.0",
        "value-out-of-range",
        "`outer` of light 2 (spot) must be between 0 and 90",
        "outer",
    );
    expect(
        "Directional(direction",
        "Directional(color: (1.0, -0.5, 1.0), direction",
        "value-out-of-range",
        "`color` of light 3 (directional) must be 0 or more in every component",
        "color",
    );
}

#[test]
fn model_and_size_values_out_of_range() {
    expect(
        "scale: 0.5",
        "scale: 0.0",
        "value-out-of-range",
        "`scale` of model `chair.gltf` must be greater than 0",
        "scale",
    );
    expect(
        "triangles: 0.5",
        "triangles: 0.0",
        "value-out-of-range",
        "`triangles` of model `chair.gltf` must be in (0, 1]",
        "triangles",
    );
    expect(
        "triangles: 0.5",
        "triangles: 1.5",
        "value-out-of-range",
        "must be in (0, 1]",
        "triangles",
    );
    expect(
        "size: (64, 48)",
        "size: (0, 48)",
        "value-out-of-range",
        "scene size (0, 48) is out of range",
        "(0, 48)",
    );
    expect(
        "size: (64, 48)",
        "size: (64, 99999)",
        "value-out-of-range",
        "width and height must be 1 to 16384",
        "(64, 99999)",
    );
    expect(
        "size: (64, 48)",
        "size: (64, -1)",
        "bad-number",
        "`-1` is not a 32-bit whole number",
        "-1",
    );
}

#[test]
fn structure_errors_suggest_and_locate() {
    expect("lights: [", "lihgts: [", "unknown-key", "unknown key `lihgts` in scene", "lihgts");
    expect(
        "range: 6.0)",
        "rnage: 6.0)",
        "unknown-key",
        "unknown key `rnage` in point light",
        "rnage",
    );
    expect("Point(", "Pointt(", "unknown-kind", "unknown light kind `Pointt`", "Pointt");
    // Area lights are emissive meshes, never written as lights.
    expect("Point(", "Area(", "unknown-kind", "unknown light kind `Area`", "Area");
    expect(
        "Point(position",
        "Point(inner: 3.0, position",
        "misplaced",
        "`inner` is not a property of point lights",
        "inner",
    );
    expect(
        "effects: [Shadows]",
        "effects: [Shadow]",
        "unknown-effect",
        "unknown effect `Shadow`",
        "Shadow",
    );
    expect(
        "size: (64, 48),",
        "size: (64, 48), builtin: \"cornel\",",
        "unknown-value",
        "unknown built-in scene `cornel`",
        "\"cornel\"",
    );
    expect(
        "(path: \"chair.gltf\", ",
        "(",
        "missing-key",
        "model is missing required key `path`",
        "(",
    );
    let (_, diags, _) = load(&BASE.replacen("range: 6.0)", "rnage: 6.0)", 1));
    assert!(
        diags.list[0].notes.iter().any(|n| n.contains("did you mean `range`?")),
        "{:?}",
        diags.list[0]
    );
}

#[test]
fn builtin_base_is_merged_and_names_work_everywhere() {
    let text = "Scene(builtin: \"cornell\", lights: [Spot(on: false)], effects: [Ssr])";
    let d = load(text).0.expect("valid");
    assert_eq!(d.geometry.as_deref(), Some("cornell"));
    assert_eq!(d.lights.len(), 2, "the built-in's point light, then the file's spot light");
    assert_eq!(d.camera.fov, 40.0, "the built-in's camera");
    assert!(d.effects.contains(&Effect::Shadows) && d.effects.contains(&Effect::Ssr));
    let f = d.features([]);
    assert_eq!(f.lights.get(&LightKind::Point), Some(&1));
    assert_eq!(f.lights.get(&LightKind::Spot), None, "a light that is off is not counted");
    let mut s = lightbench_compiler::Session::new();
    assert_eq!(s.load_scene("colonnade").unwrap().features([]).light_count(&LightKind::ALL), 2);
    assert!(s.load_scene("cornel").is_none());
    let d = &s.diags.list[0];
    assert!(d.message.contains("neither a scene file nor a built-in scene"), "{}", d.message);
    assert!(d.notes[0].contains("did you mean `cornell`?"), "{:?}", d.notes);
}

/// `builtin_lights: false` drops the built-in's lights, so the file's light the scene alone;
/// a value that is not a boolean is located.
#[test]
fn builtin_lights_false_keeps_only_the_files_lights() {
    let text = "Scene(builtin: \"cornell\", builtin_lights: false, lights: [Spot()])";
    let d = load(text).0.expect("valid");
    assert_eq!(d.lights.len(), 1, "the file's spot light alone");
    assert_eq!(d.features([]).lights.get(&LightKind::Point), None);
    let bad = "Scene(builtin: \"cornell\", builtin_lights: 0)";
    let found = located(bad);
    assert!(
        found
            .iter()
            .any(|(_, m, l, c)| m.contains("`true` or `false`") && (*l, *c) == (1, 43)),
        "{found:?}"
    );
    // The double_sided override of a model is a boolean too.
    let found = located("Scene(models: [(path: \"m.gltf\", double_sided: 1)])");
    assert!(
        found
            .iter()
            .any(|(_, m, l, c)| m.contains("`true` or `false`") && (*l, *c) == (1, 47)),
        "{found:?}"
    );
}

/// The README's scene example and every bundled scene file load; the runtime's tests
/// render them.
#[test]
fn readme_and_bundled_scenes_load() {
    let readme = common::manual();
    let examples: Vec<&str> = readme
        .split("```ron\n")
        .skip(1)
        .filter_map(|b| b.split("```").next())
        .filter(|b| b.trim_start().starts_with("Scene("))
        .collect();
    assert!(!examples.is_empty(), "the manual shows a scene file");
    for ex in examples {
        let (d, diags, _) = load(ex);
        assert!(d.is_some(), "the manual's example: {:?}", diags.list);
    }
    for entry in std::fs::read_dir(repo_root().join("scenes")).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().and_then(|e| e.to_str()) == Some("ron") {
            let mut s = lightbench_compiler::Session::new();
            assert!(s.load_scene(p.to_str().unwrap()).is_some(), "{}: {}", p.display(), s.render());
        }
    }
}

/// The old light form `Point((...))` is told to drop a pair of parentheses, not that a
/// directional light was expected.
#[test]
fn the_old_double_parenthesised_light_is_named() {
    expect(
        "Point(position: (0.0, 1.8, 0.0), intensity: 4.0, range: 6.0)",
        "Point((position: (0.0, 1.8, 0.0), intensity: 4.0, range: 6.0))",
        "type-mismatch",
        "`Point((...))` has one pair of parentheses too many: write `Point(key: value, ...)`",
        "Point",
    );
}
