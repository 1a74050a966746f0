//! Culling and configuration checks on a small pipeline with effect conditions, a toggle,
//! a pass whose output nothing needs, and mutually exclusive writers.

mod common;

use common::*;
use lightbench_compiler::ir::{Effect, LightKind};
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;

const PIPELINE: &str = r#"Pipeline(
    name: "cull",
    params: {
        "debug.enabled": Bool(default: false),
    },
    resources: {
        "a": Texture(format: Rgba16Float),
        "ao": Texture(format: R8Unorm),
        "debug": Texture(format: Rgba8Unorm),
        "out": Texture(format: Rgba8Unorm),
    },
    passes: [
        Fullscreen(name: "base", shader: "fill.wgsl", color: ["a"]),
        Fullscreen(name: "ssao", shader: "fill.wgsl", color: ["ao"], when: Effect(AmbientOcclusion)),
        Fullscreen(name: "ao_off", shader: "fill.wgsl", color: ["ao"], when: Not(Effect(AmbientOcclusion))),
        Fullscreen(name: "debug_view", shader: "fill.wgsl", color: ["debug"], when: Toggle("debug.enabled")),
        Fullscreen(name: "stats", shader: "fill.wgsl", color: ["debug"]),
        Fullscreen(name: "compose", shader: "compose.wgsl", reads: ["a", "ao"], color: ["out"]),
    ],
    output: "out",
)
"#;

const FILL: &str = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(0.5);\n}\n";
const COMPOSE: &str = "@group(0) @binding(0) var a: texture_2d<f32>;\n@group(0) @binding(1) var ao: texture_2d<f32>;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    let i = vec2<i32>(p.xy);\n    return textureLoad(a, i, 0) * textureLoad(ao, i, 0).r;\n}\n";

fn project() -> std::path::PathBuf {
    write_project(
        "cull",
        &[
            ("pipelines/cull.ron", PIPELINE),
            ("shaders/fill.wgsl", FILL),
            ("shaders/compose.wgsl", COMPOSE),
        ],
    )
}

fn scene(effects: &[Effect]) -> SceneFeatures {
    SceneFeatures {
        name: "test".into(),
        lights: [(LightKind::Point, 1)].into_iter().collect(),
        casters: [(LightKind::Point, 1)].into_iter().collect(),
        effects: effects.iter().copied().collect(),
        reflective: false,
        transparent: false,
        size: (64, 64),
        order: vec![],
    }
}

#[test]
fn culled_passes_name_their_reason() {
    let dir = project();
    let mut s = Session::new();
    let plan = s
        .plan_file(&dir.join("pipelines/cull.ron"), None, &Profile::vulkan(), &scene(&[]), &[])
        .unwrap_or_else(|| panic!("{}", s.render()));
    let culled: Vec<(&str, &str)> = plan.culled.iter().map(|c| (c.name.as_str(), c.reason.as_str())).collect();
    assert_eq!(
        culled,
        vec![
            (
                "ssao",
                "condition `Effect(AmbientOcclusion)` is false: the scene does not call for AmbientOcclusion"
            ),
            (
                "debug_view",
                "condition `Toggle(\"debug.enabled\")` is false: toggle `debug.enabled` is off"
            ),
            ("stats", "output unreachable: nothing on the way to `out` reads `debug`"),
        ]
    );
    let kept: Vec<&str> = plan.passes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(kept, vec!["base", "ao_off", "compose"]);
    // What `render` notes: the effect a culled pass asks for (not `ao_off`'s `Not`).
    assert_eq!(plan.uncalled_effects, vec![Effect::AmbientOcclusion]);
    let text = lightbench_compiler::plan::to_text(&plan, true);
    assert!(text.contains("stats                      output unreachable"), "{text}");
}

#[test]
fn the_scene_decides_which_writer_runs() {
    let dir = project();
    let mut s = Session::new();
    let plan = s
        .plan_file(
            &dir.join("pipelines/cull.ron"),
            None,
            &Profile::vulkan(),
            &scene(&[Effect::AmbientOcclusion]),
            &[],
        )
        .unwrap();
    assert!(plan.pass("ssao").is_some() && plan.pass("ao_off").is_none());
    // `ao_off` is culled by `Not(Effect(AmbientOcclusion))`: no effect is missing.
    assert!(plan.uncalled_effects.is_empty(), "{:?}", plan.uncalled_effects);
    assert_eq!(
        plan.culled.iter().find(|c| c.name == "ao_off").unwrap().reason,
        "condition `Not(Effect(AmbientOcclusion))` is false: Effect(AmbientOcclusion) holds"
    );
}

#[test]
fn check_covers_every_configuration_without_a_scene() {
    let dir = project();
    let out = check_project(&dir, "pipelines/cull.ron", &Profile::vulkan(), None);
    assert!(out.session.diags.list.is_empty(), "{}", out.dump());
}

#[test]
fn missing_producer_names_the_culled_writer() {
    let p = PIPELINE.replace(", when: Not(Effect(AmbientOcclusion))", ", when: Effect(Bloom)");
    let dir = write_project(
        "cull2",
        &[
            ("pipelines/cull.ron", &p),
            ("shaders/fill.wgsl", FILL),
            ("shaders/compose.wgsl", COMPOSE),
        ],
    );
    let mut s = Session::new();
    assert!(s
        .plan_file(&dir.join("pipelines/cull.ron"), None, &Profile::vulkan(), &scene(&[]), &[])
        .is_none());
    let d = s.diags.errors().next().unwrap();
    assert_eq!(d.code, "read-before-write");
    assert!(
        d.notes
            .iter()
            .any(|n| n.contains("its writer `ssao` was culled: condition `Effect(AmbientOcclusion)` is false")),
        "{:?}",
        d.notes
    );
}

#[test]
fn scene_file_features_and_errors() {
    let dir = temp_dir("scene");
    let good = dir.join("s.ron");
    std::fs::write(&good, "Scene(name: \"x\", size: (64, 32), lights: [Point(on: true), Spot(), Point(on: false)], effects: [Ssr], models: [(path: \"m.gltf\", reflective: true)])").unwrap();
    let mut s = Session::new();
    let sf = s.load_scene(&good.display().to_string()).unwrap().features([]);
    assert_eq!(sf.size, (64, 32));
    assert_eq!(sf.lights.get(&LightKind::Point), Some(&1));
    assert_eq!(sf.lights.get(&LightKind::Spot), Some(&1));
    assert!(sf.reflective && sf.effects.contains(&Effect::Ssr));
    let bad = dir.join("bad.ron");
    std::fs::write(&bad, "Scene(\n    effects: [Ssrr],\n)").unwrap();
    let mut s = Session::new();
    assert!(s.load_scene(&bad.display().to_string()).is_none());
    let d = &s.diags.list[0];
    assert_eq!((d.code.as_str(), d.message.as_str()), ("unknown-effect", "unknown effect `Ssrr`"));
    assert_eq!(d.location(&s.sources).map(|(_, l, c)| (l, c)), Some((2, 15)));
    assert!(d.notes[0].contains("did you mean `Ssr`?"));
}

/// A scene calling for an effect whose passes all run per light kinds it lacks (a box lit
/// only by a point light calling for indirect light, which the bundled RSM options gather
/// from directional and spot lights and emissive meshes) gets a note naming the pass and why,
/// instead of a silent 0; choosing the option off culls by condition and says nothing more.
#[test]
fn an_effect_no_kept_pass_serves_is_named_with_why() {
    let mut s = Session::new();
    let gi = repo_root().join("pipelines/deferred_gi.lbp");
    let point_lit = SceneFeatures {
        lights: [(LightKind::Point, 1)].into_iter().collect(),
        casters: [(LightKind::Point, 1)].into_iter().collect(),
        ..scene(&[Effect::IndirectDiffuse])
    };
    let plan = s
        .plan_file(&gi, None, &Profile::vulkan(), &point_lit, &[])
        .unwrap_or_else(|| panic!("{}", s.render()));
    let unserved: Vec<(Effect, &str, &str)> = plan
        .unserved_effects
        .iter()
        .map(|u| (u.effect, u.pass.as_str(), u.reason.as_str()))
        .collect();
    assert_eq!(
        unserved,
        [(
            Effect::IndirectDiffuse,
            "rsm",
            "runs per Directional, Spot or Area light and the scene has none"
        )]
    );
    let off = [("indirect_diffuse".to_string(), "off".to_string())];
    let plan = s.plan_file(&gi, None, &Profile::vulkan(), &point_lit, &off).unwrap();
    assert!(plan.unserved_effects.is_empty(), "{:?}", plan.unserved_effects);
    // With a spot light, or an emissive mesh (an `Area` light), the effect is served.
    for kind in [LightKind::Spot, LightKind::Area] {
        let lit = SceneFeatures {
            lights: [(kind, 1)].into_iter().collect(),
            ..point_lit.clone()
        };
        let plan = s.plan_file(&gi, None, &Profile::vulkan(), &lit, &[]).unwrap();
        assert!(plan.unserved_effects.is_empty(), "{kind:?}: {:?}", plan.unserved_effects);
    }
}
