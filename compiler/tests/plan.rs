//! Plans of the bundled pipelines: snapshots (reviewed, committed) and the properties the
//! runtime relies on: layouts, offsets, sample types, culling reasons, fallbacks, memory.

mod common;

use common::*;
use lightbench_compiler::ir::{LightKind, ParamValue, SamplerKind, Stage};
use lightbench_compiler::layout::{BindSource, BindingType, FieldType, SampleType, ShaderDim};
use lightbench_compiler::plan::{self, Plan, Usage};
use lightbench_compiler::profile::Profile;
use lightbench_compiler::scene::SceneFeatures;
use lightbench_compiler::Session;

fn deferred() -> std::path::PathBuf {
    repo_root().join("pipelines/deferred.ron")
}

fn plan_with(profile: &str, scene: Option<&str>, variants: &[(&str, &str)]) -> Plan {
    let mut s = Session::new();
    let profile = Profile::offline(profile).unwrap();
    let scene = match scene {
        Some(p) => s
            .load_scene(&repo_root().join(p).display().to_string())
            .expect("scene")
            .features([]),
        None => SceneFeatures::everything(),
    };
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let plan = s.plan_file(&deferred(), None, &profile, &scene, &v);
    assert!(!s.diags.has_errors(), "{}", s.render());
    plan.expect("plan")
}

fn binding<'a>(plan: &'a Plan, pass: &str, name: &str) -> &'a plan::PlanBinding {
    plan.pass(pass)
        .unwrap_or_else(|| panic!("no pass {pass}"))
        .bind_groups
        .iter()
        .flat_map(|g| g.entries.iter())
        .find(|e| e.name == name)
        .unwrap_or_else(|| panic!("no binding {name} in {pass}"))
}

#[test]
fn snapshot_deferred_all_features() {
    insta::assert_snapshot!("deferred_all_features", plan::to_text(&plan_with("vulkan", None, &[]), true));
}

#[test]
fn snapshot_deferred_sun_only_scene_culls_passes() {
    let plan = plan_with("vulkan", Some("scenes/sun_only.ron"), &[]);
    let text = plan::to_text(&plan, true);
    insta::assert_snapshot!("deferred_sun_only", text);
    let culled: Vec<(&str, &str)> = plan.culled.iter().map(|c| (c.name.as_str(), c.reason.as_str())).collect();
    assert!(
        culled.contains(&("shadow_cube_classic", "runs per Point light and the scene has none")),
        "{culled:?}"
    );
    assert!(culled.contains(&("light_point", "runs per Point light and the scene has none")));
    assert!(culled.contains(&(
        "shadow_cube_multiview",
        "variant not chosen: `cube_shadow` is `classic`, this pass belongs to `multiview`"
    )));
    // A condition naming several options of one variant (`variant(v, a | b)`, directly or
    // through a `let`) is one reason naming them all.
    assert!(culled.contains(&(
        "area_rt",
        "variant not chosen: `area_lights` is `off`, this pass belongs to `rt` or `rt_temporal`"
    )));
    assert!(plan.pass("light_directional_spot").is_some_and(|p| p.repetitions == 1));
    assert!(
        plan.resource("shadow.cube").is_none(),
        "unused per-light resources are not allocated"
    );
}

#[test]
fn snapshot_deferred_gl_falls_back_from_multiview() {
    let plan = plan_with("gl", None, &[("cube_shadow", "multiview"), ("tonemap", "simple")]);
    insta::assert_snapshot!("deferred_gl_multiview_simple", plan::to_text(&plan, true));
    let v = plan.variants.iter().find(|v| v.variant == "cube_shadow").unwrap();
    assert_eq!(v.option, "instanced");
    assert!(
        v.reason.as_deref().unwrap().contains("`multiview` needs feature Multiview"),
        "{v:?}"
    );
    // The GLSL substitute is used for the tone map.
    assert_eq!(plan.pass("tonemap").unwrap().stages[1].file, "tonemap_simple.frag");
    assert_eq!(plan.pass("tonemap").unwrap().stages[1].entry, "main");
}

#[test]
fn webgpu_falls_back_twice_with_reasons() {
    let plan = plan_with("webgpu", None, &[("cube_shadow", "multiview")]);
    let v = plan.variants.iter().find(|v| v.variant == "cube_shadow").unwrap();
    assert_eq!(v.option, "classic");
    let r = v.reason.as_deref().unwrap();
    assert!(
        r.contains("falling back to `instanced`") && r.contains("`instanced` needs feature ClipDistances"),
        "{r}"
    );
    assert!(plan.pass("shadow_cube_classic").is_some());
}

/// `multiview!` asks for the option with fallbacks refused: where the profile lacks what it
/// needs, that is an error naming what is missing; where it has it, the option runs.
#[test]
fn a_forced_option_does_not_fall_back() {
    let mut s = Session::new();
    let gl = Profile::offline("gl").unwrap();
    let v = vec![("cube_shadow".to_string(), "multiview!".to_string())];
    let plan = s.plan_file(&deferred(), None, &gl, &SceneFeatures::everything(), &v);
    assert!(plan.is_none());
    let d = s
        .diags
        .errors()
        .find(|d| d.code.as_str() == "variant-unsupported")
        .unwrap_or_else(|| panic!("{}", s.render()));
    assert!(
        d.message
            .contains("option `multiview` was asked for without fallback (`multiview!`) but needs feature Multiview"),
        "{}",
        d.message
    );
    let plan = plan_with("vulkan", None, &[("cube_shadow", "multiview!")]);
    let chosen = plan.variants.iter().find(|v| v.variant == "cube_shadow").unwrap();
    assert_eq!(chosen.option, "multiview");
}

#[test]
fn layouts_come_from_formats_and_shader_use() {
    let plan = plan_with("vulkan", None, &[]);
    // Depth texture read through texture_depth_2d with a comparison sampler.
    assert_eq!(
        binding(&plan, "light_directional_spot", "shadow_map").ty,
        BindingType::Texture {
            sample_type: SampleType::Depth,
            view_dimension: ShaderDim::D2,
            multisampled: false
        }
    );
    assert_eq!(
        binding(&plan, "light_directional_spot", "shadow_cmp").ty,
        BindingType::Sampler(SamplerKind::Comparison)
    );
    // Depth32Float read as texture_2d<f32> (textureLoad): an unfilterable float, as wgpu requires.
    assert!(matches!(
        binding(&plan, "light_point", "gbuf_depth").ty,
        BindingType::Texture {
            sample_type: SampleType::Float { filterable: false },
            ..
        }
    ));
    // Rgba8Unorm is filterable by format.
    assert!(matches!(
        binding(&plan, "ambient", "gbuf_albedo").ty,
        BindingType::Texture {
            sample_type: SampleType::Float { filterable: true },
            ..
        }
    ));
    // Cube view for point shadows.
    assert!(matches!(
        binding(&plan, "light_point", "shadow_cube").ty,
        BindingType::Texture {
            view_dimension: ShaderDim::Cube,
            ..
        }
    ));
    // Visibility from actual entry-point use.
    assert_eq!(binding(&plan, "shadow_map", "mesh").visibility, vec![Stage::Vertex]);
    // The G-buffer's fragments read the model's handedness (sidedness, lib/material.wgsl).
    assert_eq!(binding(&plan, "gbuffer", "mesh").visibility, vec![Stage::Vertex, Stage::Fragment]);
    assert_eq!(binding(&plan, "gbuffer", "material").visibility, vec![Stage::Fragment]);
    assert_eq!(
        binding(&plan, "luminance", "lum").ty,
        BindingType::Storage {
            read_only: false,
            min_binding_size: 28
        }
    );
    assert_eq!(
        binding(&plan, "tonemap", "lum").ty,
        BindingType::Storage {
            read_only: true,
            min_binding_size: 28
        }
    );
    assert_eq!(binding(&plan, "shadow_map", "lights").source, BindSource::Lights);
    // Globals declared by an include but unused by the entry point are not bound.
    assert!(plan
        .pass("shadow_map")
        .unwrap()
        .bind_groups
        .iter()
        .flat_map(|g| &g.entries)
        .all(|e| e.name != "frame"));
}

#[test]
fn uniform_block_offsets_follow_the_shader_struct() {
    let plan = plan_with("vulkan", None, &[]);
    let b = &plan.pass("light_directional_spot").unwrap().uniform_blocks[0];
    let fields: Vec<(&str, &str, u32, u32, &str)> = b
        .fields
        .iter()
        .map(|f| {
            let lightbench_compiler::layout::FieldSource::Param(id) = f.source else {
                panic!("{f:?}")
            };
            (f.name.as_str(), plan.param(id).name.as_str(), f.offset, f.size, f.ty.wgsl())
        })
        .collect();
    assert_eq!(
        fields,
        vec![
            ("bias_texels", "shadow.bias_texels", 0, 4, "f32"),
            ("pcf", "shadow.pcf", 4, 4, "u32"),
            ("normal_offset_texels", "shadow.normal_offset_texels", 8, 4, "f32")
        ]
    );
    assert_eq!((b.size, b.align, b.group, b.binding), (12, 4, 2, 5));
    let a = &plan.pass("ambient").unwrap().uniform_blocks[0];
    assert_eq!((a.size, a.align), (16, 16), "vec3<f32> is 16-aligned in uniform space");
    assert_eq!(a.fields[0].ty, FieldType::Vec3F32);
}

#[test]
fn resources_memory_and_usage() {
    let plan = plan_with("vulkan", None, &[]);
    let normal = plan.resource("gbuf.normal").unwrap();
    assert_eq!(normal.bytes, 1280 * 720 * 8);
    let usage = |name: &str| plan.resource(name).unwrap().usage.iter().copied().collect::<Vec<_>>();
    assert_eq!(usage("gbuf.normal"), vec![Usage::RenderAttachment, Usage::TextureBinding]);
    assert_eq!(usage("gbuf.depth"), vec![Usage::RenderAttachment, Usage::TextureBinding]);
    let cube = plan.resource("shadow.cube").unwrap();
    assert_eq!((cube.layers(), cube.instances, cube.bytes), (6, 1, 512 * 512 * 4 * 6));
    assert_eq!(usage("ldr"), vec![Usage::RenderAttachment, Usage::CopySrc]);
    assert_eq!(usage("lum"), vec![Usage::Storage]);
    assert_eq!(plan.memory_bytes, plan.resources.iter().map(|r| r.bytes).sum::<u64>());
}

#[test]
fn memory_scales_with_lights_and_resolution() {
    let mut s = Session::new();
    let mut scene = SceneFeatures::everything();
    scene.size = (1920, 1080);
    scene.lights.insert(LightKind::Point, 4);
    scene.casters.insert(LightKind::Point, 4);
    let plan = s.plan_file(&deferred(), None, &Profile::vulkan(), &scene, &[]).unwrap();
    let cube = plan.resource("shadow.cube").unwrap();
    assert_eq!((cube.instances, cube.bytes), (4, 4 * 512 * 512 * 4 * 6));
    assert_eq!(plan.resource("hdr").unwrap().bytes, 1920 * 1080 * 8);
    assert_eq!(plan.pass("shadow_cube_classic").unwrap().repetitions, 24);
}

/// Shadow passes (`shadow_casters`) repeat for the lights that cast shadows only; with none,
/// they are culled, saying why. Shadow maps get an instance per casting light only.
#[test]
fn shadow_passes_run_for_casting_lights_only() {
    let mut s = Session::new();
    let mut scene = SceneFeatures::everything();
    scene.lights.insert(LightKind::Point, 4);
    scene.casters.insert(LightKind::Point, 1);
    let plan = s.plan_file(&deferred(), None, &Profile::vulkan(), &scene, &[]).unwrap();
    assert_eq!(plan.pass("shadow_cube_classic").unwrap().repetitions, 6);
    assert_eq!(plan.pass("light_point").unwrap().repetitions, 4);
    // The cube maps follow the casting lights: one, not four.
    let cube = plan.resource("shadow.cube").unwrap();
    assert!(cube.casters_only);
    assert_eq!((cube.instances, cube.bytes), (1, 512 * 512 * 4 * 6));
    assert!(plan::to_text(&plan, false).contains("Scene ×6 (per Point light casting shadows, per face)"));
    scene.casters.clear();
    let plan = s.plan_file(&deferred(), None, &Profile::vulkan(), &scene, &[]);
    assert!(!s.diags.has_errors(), "{}", s.render());
    let plan = plan.unwrap();
    let why = |name: &str| plan.culled.iter().find(|c| c.name == name).map(|c| c.reason.clone());
    assert_eq!(
        why("shadow_cube_classic").as_deref(),
        Some("runs per shadow-casting Point light and no such light casts shadows")
    );
    assert!(why("shadow_map").is_some());
}

#[test]
fn execution_order_respects_dependencies() {
    let plan = plan_with("vulkan", None, &[]);
    let names: Vec<&str> = plan.passes.iter().map(|p| p.name.as_str()).collect();
    let pos = |n: &str| names.iter().position(|x| *x == n).unwrap();
    assert!(pos("gbuffer") < pos("ambient"));
    assert!(pos("ambient") < pos("light_directional_spot"), "lights load what ambient cleared");
    assert!(pos("light_point") < pos("transparent"), "blended surfaces go over the lit image");
    assert!(pos("transparent") < pos("luminance"));
    assert!(pos("luminance") < pos("tonemap"));
    let after: Vec<&str> = plan
        .pass("tonemap")
        .unwrap()
        .after
        .iter()
        .map(|a| plan.passes[a.0 as usize].name.as_str())
        .collect();
    assert_eq!(
        after,
        vec![
            "ambient",
            "light_directional_spot",
            "light_point",
            "transparent",
            "bloom_add",
            "luminance"
        ]
    );
    // Bloom reads the lit image and adds to it: after every earlier writer of `hdr`, and
    // before the exposure is measured.
    assert!(pos("transparent") < pos("bloom_bright") && pos("bloom_bright") < pos("bloom_down"));
    assert!(pos("bloom_down") < pos("bloom_up") && pos("bloom_up") < pos("bloom_add"));
    assert!(pos("bloom_add") < pos("luminance"));
}

#[test]
fn plan_round_trips_through_json() {
    let plan = plan_with("vulkan", None, &[]);
    let json = serde_json::to_string(&plan).unwrap();
    let back: Plan = serde_json::from_str(&json).unwrap();
    assert_eq!(back, plan);
}

#[test]
fn bundled_pipelines_check_clean_on_every_profile() {
    for profile in Profile::OFFLINE {
        for f in lightbench_compiler::pipeline_files(&repo_root().join("pipelines")).unwrap() {
            let mut s = Session::new();
            s.check_file(&f, None, &Profile::offline(profile).unwrap(), None);
            // Except: on GL, `deferred_gi`'s RSM and temporal depth need 32-bit float targets
            // (warned about; see `formats_gl_cannot_render_to_fall_back_or_fail_where_kept`);
            // and the path tracer needs ray queries, which only the Vulkan profile has: every
            // option of its one variant is refused there, naming the feature.
            let ray_queries = Profile::offline(profile)
                .unwrap()
                .has(lightbench_compiler::profile::Feature::ExperimentalRayQuery);
            let path_tracer = f.file_stem().is_some_and(|n| n == "pathtrace");
            let unexpected = s.diags.list.iter().any(|d| {
                let gl_formats = profile == "gl"
                    && d.severity == lightbench_compiler::diag::Severity::Warning
                    && d.code.as_str() == "format-not-renderable";
                let no_rays =
                    path_tracer && !ray_queries && d.code.as_str() == "variant-unsupported" && d.message.contains("ExperimentalRayQuery");
                !(gl_formats || no_rays)
            });
            if path_tracer && !ray_queries {
                assert!(s.diags.has_errors(), "{} on {profile}: refused", f.display());
            }
            assert!(!unexpected, "{} on {profile}:\n{}", f.display(), s.render());
        }
    }
}

/// The extent of a texture in a plan.
fn extent(plan: &Plan, name: &str) -> (u32, u32) {
    match &plan.resource(name).unwrap_or_else(|| panic!("no {name}")).shape {
        plan::ResourceShape::Texture { extent, .. } => *extent,
        _ => panic!("{name} is a buffer"),
    }
}

/// A variant option's preset replaces the parameters' defaults in the Plan (and says so);
/// a resource scaled by a preset parameter takes its size; a user's override still wins.
#[test]
fn presets_set_defaults_and_sizes_and_overrides_win() {
    let gi = repo_root().join("pipelines/deferred_gi.ron");
    let profile = Profile::offline("vulkan").unwrap();
    let mut scene = SceneFeatures::everything();
    scene.size = (64, 48);
    let plan_of = |variants: &[(&str, &str)], params: &[(&str, &str)]| {
        let mut s = Session::new();
        let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
        let declared = s.load_pipeline(&gi).expect("pipeline");
        let decl: Vec<_> = declared.params.iter().map(plan::declared_param).collect();
        let mut values = plan::ParamValues::new();
        for (k, t) in params {
            let value = plan::ParamValues::parse_text(&decl, k, t).unwrap();
            values.set(&decl, k, value).unwrap();
        }
        let e = s.executable_with(&gi, None, (&profile, &scene), &v, &values);
        assert!(!s.diags.has_errors(), "{}", s.render());
        e.expect("plan").plan
    };
    let param = |plan: &Plan, name: &str| plan.params.iter().find(|p| p.name == name).unwrap().clone();

    let custom = plan_of(&[], &[]);
    assert_eq!(param(&custom, "ao.samples").default, ParamValue::Int(64));
    assert_eq!(param(&custom, "ao.samples").preset, None);
    assert_eq!(extent(&custom, "ao.raw"), (64, 48));

    let p1 = plan_of(&[("ao_preset", "ssao1")], &[]);
    assert_eq!(param(&p1, "ao.samples").default, ParamValue::Int(8));
    assert_eq!(param(&p1, "ao.samples").preset.as_deref(), Some("ao_preset=ssao1"));
    assert_eq!(param(&p1, "ao.radius").default, ParamValue::Float(1.0));
    assert_eq!(extent(&p1, "ao.raw"), (16, 12), "w/4 × h/4");
    assert_eq!(extent(&p1, "ao.full"), (64, 48));
    assert!(plan::to_text(&p1, false).contains("presets:\n  ao.radius = 1  (ao_preset=ssao1)"));

    let p3 = plan_of(&[("ao_preset", "ssao3")], &[]);
    assert_eq!(extent(&p3, "ao.raw"), (32, 24), "w/2 × h/2");

    // The user's own value sizes the buffer, whatever the preset says.
    let own = plan_of(&[("ao_preset", "ssao1")], &[("ao.scale", "0.5")]);
    assert_eq!(extent(&own, "ao.raw"), (32, 24));
    assert_eq!(param(&own, "ao.scale").sizes, Some(ParamValue::Float(0.5)));
}

/// GL cannot render to 32-bit float formats: the fat G-buffer falls back to packed there with
/// its reason, and a plan of `deferred_gi.ron` that keeps a pass rendering to one (the RSM,
/// for a scene with indirect light) fails at that pass's target; `check` without a scene
/// warns (the pass may be culled), and a scene that culls it plans fine.
#[test]
fn formats_gl_cannot_render_to_fall_back_or_fail_where_kept() {
    let plan = plan_with("gl", None, &[("gbuffer", "fat")]);
    let v = plan.variants.iter().find(|v| v.variant == "gbuffer").unwrap();
    assert_eq!(v.option, "packed");
    assert!(v.reason.as_deref().unwrap().contains("needs feature Float32Renderable"), "{v:?}");

    let gi = repo_root().join("pipelines/deferred_gi.ron");
    let gl = Profile::offline("gl").unwrap();
    let mut s = Session::new();
    s.check_file(&gi, None, &gl, None);
    assert!(!s.diags.has_errors(), "{}", s.render());
    assert!(
        s.render()
            .contains("warning[format-not-renderable]: format Rgba32Float of `rsm.position` cannot be rendered to on profile `gl`: a plan that keeps pass `rsm` fails"),
        "{}",
        s.render()
    );
    let mut s = Session::new();
    let mut indirect = SceneFeatures::everything();
    indirect.name = "indirect".into();
    assert!(s.plan_file(&gi, None, &gl, &indirect, &[]).is_none());
    let text = s.render();
    assert!(
        text.contains(
            "error[format-not-renderable]: pass `rsm` renders to `rsm.position`, whose format Rgba32Float profile `gl` cannot render to"
        ),
        "{text}"
    );
    assert!(text.contains("deferred_gi.ron:"), "located in the pipeline file: {text}");
    let mut s = Session::new();
    let mut plain = SceneFeatures::everything();
    plain.effects.clear();
    plain.reflective = false;
    assert!(s.plan_file(&gi, None, &gl, &plain, &[]).is_some(), "{}", s.render());
}

/// `docs/plan.md` specifies `plan --json`: it names the format version the Plan carries and
/// every key a Plan of the bundled pipelines has (in every configuration `check` plans).
#[test]
fn the_plan_format_document_names_every_key() {
    let doc = std::fs::read_to_string(repo_root().join("docs/plan.md")).unwrap();
    assert!(doc.starts_with(&format!("# The Plan format (`lightbench plan --json`), format {}", plan::FORMAT)));
    assert!(doc.contains(&format!("`format` is `{}`", plan::FORMAT)));
    fn keys(v: &serde_json::Value, out: &mut std::collections::BTreeSet<String>) {
        match v {
            serde_json::Value::Object(m) => m.iter().for_each(|(k, x)| {
                out.insert(k.clone());
                keys(x, out);
            }),
            serde_json::Value::Array(a) => a.iter().for_each(|x| keys(x, out)),
            _ => {}
        }
    }
    let mut all = std::collections::BTreeSet::new();
    let profile = Profile::offline("vulkan").unwrap();
    for file in ["pipelines/deferred.lbp", "pipelines/deferred_gi.lbp"] {
        let mut s = Session::new();
        let checked = s.load_checked(&repo_root().join(file), None, &profile).unwrap();
        let mut configs: Vec<Vec<(String, String)>> = vec![vec![]];
        for v in &checked.pipeline.variants {
            configs.extend(v.options.iter().map(|o| vec![(v.name.value.clone(), o.name.value.clone())]));
        }
        for c in configs {
            let Some(p) = s.plan(&checked, &profile, &SceneFeatures::everything(), &c) else {
                continue;
            };
            assert_eq!(p.format, plan::FORMAT);
            keys(&serde_json::to_value(&p).unwrap(), &mut all);
        }
    }
    // Enum variant names are keys too (`{"Raster": ...}`): the document names those as well.
    let missing: Vec<&String> = all
        .iter()
        .filter(|k| !doc.contains(&format!("`{k}`")) && !doc.contains(&format!("\"{k}\"")))
        .collect();
    assert!(missing.is_empty(), "docs/plan.md does not name {missing:?}");
}

/// The Plan lists every run of a pass for the scene's lights in order: a per-light pass runs
/// for the lights of its kinds (casting ones for `shadow_casters`), by their index in the
/// light array; faces and runs nest inside.
#[test]
fn repetitions_name_the_scene_lights_by_index() {
    use lightbench_compiler::ir::LightKind::*;
    let scene = lightbench_compiler::scene::SceneFeatures::everything().with_order([
        (Point, true),
        (Spot, false),
        (Point, false),
        (Directional, true),
    ]);
    let mut s = lightbench_compiler::Session::new();
    let path = repo_root().join("pipelines/deferred.lbp");
    let plan = s
        .plan_file(&path, None, &lightbench_compiler::profile::Profile::vulkan(), &scene, &[])
        .unwrap_or_else(|| panic!("{}", s.render()));
    let reps = |name: &str| plan.passes.iter().find(|p| p.name == name).unwrap().reps.clone();
    let lights = |name: &str| reps(name).iter().map(|r| r.light).collect::<Vec<_>>();
    assert_eq!(lights("light_point"), [Some(0), Some(2)]);
    assert_eq!(lights("light_directional_spot"), [Some(1), Some(3)]);
    // Shadow maps only for the casting lights: the spot casts none.
    assert_eq!(lights("shadow_map"), [Some(3)]);
    let cube = reps("shadow_cube_classic");
    assert_eq!(cube.len(), 6, "one casting point light, six faces");
    assert!(cube.iter().enumerate().all(|(f, r)| r.light == Some(0) && r.face == f as u32));
    for p in &plan.passes {
        assert_eq!(p.reps.len() as u32, p.repetitions, "{}", p.name);
    }
}

/// Each repetition names the copy of every per-light resource it uses (`copies`): a light's
/// rank among the lights the resource has copies for, the casting ones for a shadow map; a
/// light that casts no shadow binds copy 0, unread.
#[test]
fn repetitions_name_the_copy_of_each_per_light_resource() {
    use lightbench_compiler::ir::LightKind::*;
    let scene = lightbench_compiler::scene::SceneFeatures::everything().with_order([
        (Point, true),
        (Spot, false),
        (Point, false),
        (Directional, true),
        (Point, true),
    ]);
    let mut s = lightbench_compiler::Session::new();
    let path = repo_root().join("pipelines/deferred.lbp");
    let plan = s
        .plan_file(&path, None, &lightbench_compiler::profile::Profile::vulkan(), &scene, &[])
        .unwrap_or_else(|| panic!("{}", s.render()));
    let cube = plan.resource_id("shadow.cube").unwrap();
    assert_eq!(plan.res(cube).instances, 2, "two casting point lights");
    let copies = |pass: &str| -> Vec<(Option<u32>, u32)> {
        let p = plan.passes.iter().find(|p| p.name == pass).unwrap();
        p.reps.iter().map(|r| (r.light, r.copy_of(cube))).collect()
    };
    // The lighting pass reads the cube map of its light: the third point light has the second.
    assert_eq!(copies("light_point"), [(Some(0), 0), (Some(2), 0), (Some(4), 1)]);
    // The shadow pass renders into it, six faces per casting light.
    let shadow = copies("shadow_cube_classic");
    assert_eq!(shadow.len(), 12);
    assert!(
        shadow[..6].iter().all(|c| *c == (Some(0), 0)) && shadow[6..].iter().all(|c| *c == (Some(4), 1)),
        "{shadow:?}"
    );
    // A run without a light names no copies; every copy named exists.
    for p in &plan.passes {
        for r in &p.reps {
            assert!(r.light.is_some() || r.copies.is_empty(), "{}", p.name);
            assert!(r.copies.iter().all(|c| c.instance < plan.res(c.resource).instances), "{}", p.name);
        }
    }
}

/// The Plan carries the text of every shader file its stages name, once each, as the compiler
/// read it: `#include`s spliced in (an executor needs no shader files), the built-in
/// full-screen vertex shader too.
#[test]
fn the_plan_carries_each_stage_s_shader_text_once() {
    let plan = plan_with("vulkan", None, &[]);
    let files: std::collections::BTreeSet<&str> = plan.passes.iter().flat_map(|p| &p.stages).map(|s| s.file.as_str()).collect();
    let carried: Vec<&str> = plan.shaders.iter().map(|s| s.file.as_str()).collect();
    assert_eq!(carried.len(), files.len(), "each file once: {carried:?}");
    assert!(files.iter().all(|f| carried.contains(f)), "{files:?} vs {carried:?}");
    let light = plan.shader("light_point.wgsl").expect("light_point.wgsl");
    assert_eq!(light.language, plan::ShaderLanguage::Wgsl);
    assert!(!light.text.contains("#include"), "includes are spliced in");
    let on_disk = std::fs::read_to_string(repo_root().join("shaders/lib/light_entries.wgsl")).unwrap();
    let first = on_disk.lines().find(|l| l.starts_with("fn ") || l.starts_with("@")).unwrap();
    assert!(light.text.contains(first), "the included library is in the text: {first}");
    let fullscreen = plan.shader("<builtin>/fullscreen.wgsl").expect("the built-in vertex shader");
    assert!(fullscreen.text.contains("fullscreen_vs"));
    // And it survives `plan --json`: what a second executor reads.
    let back: Plan = serde_json::from_str(&serde_json::to_string(&plan).unwrap()).unwrap();
    assert_eq!(back.shaders, plan.shaders);
}
