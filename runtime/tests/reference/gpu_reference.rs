//! The GPU path tracer (`pipelines/pathtrace.lbp`, `reference --device gpu`) against the CPU
//! reference: pixel by pixel within the noise both estimate, on the scenes the reference is
//! checked on; a deliberately wrong copy fails the same comparison.

use super::agreement::{load, settings};
use crate::gpu_common;
use lightbench::gpu_reference::{self, Tracer};
use lightbench::reference::{self, Reference, Settings, Term};
use lightbench::scene::Scene;
use std::path::Path;

/// The GPU path tracer at `pipeline` against the CPU reference on `scene` with `s`: the
/// failures, named (see `agreement::judge`).
fn judge(scene: &Scene, s: &Settings, pipeline: &Path) -> Vec<String> {
    super::agreement::judge(scene, s, |s| reference::render(scene, s, false), |s| on_gpu(scene, s, pipeline))
}

/// The GPU reference of `scene` by the path tracer at `pipeline` (in `root`'s workspace).
fn on_gpu(scene: &Scene, s: &Settings, pipeline: &Path) -> Reference {
    let gpu = gpu_common::gpu();
    let ws = lightbench_compiler::Workspace::disk();
    let tracer = Tracer { ws: &ws, pipeline };
    gpu_reference::render(&gpu, &tracer, scene, s, false).unwrap_or_else(|e| panic!("{}: {e}", scene.name))
}

/// The scenes and terms of the comparison: the Cornell box lit by a point light, a sun, a
/// spot and an emitter, and six hard cases.
const CASES: [(&str, &[Term]); 10] = [
    ("cornell", &[Term::Direct, Term::Ao, Term::Full]),
    ("scenes/cornell_sun.ron", &[Term::Full]),
    ("scenes/cornell_spot.ron", &[Term::Full]),
    ("cornell_lamp", &[Term::Direct, Term::Full]),
    ("scenes/hard/point_in_box.ron", &[Term::Full]),
    ("scenes/hard/spot_wide.ron", &[Term::Direct, Term::Full]),
    ("scenes/hard/mirror_floor.ron", &[Term::Full]),
    ("scenes/hard/deep_range.ron", &[Term::Direct, Term::Ao]),
    ("scenes/hard/tiny_scale.ron", &[Term::Full]),
    ("scenes/hard/zero_normals.ron", &[Term::Full]),
];

#[test]
fn the_gpu_path_tracer_equals_the_cpu_reference_within_noise() {
    let pipeline = gpu_common::root().join("pipelines/pathtrace.lbp");
    let mut bad = vec![];
    for (spec, terms) in CASES {
        bad.extend(judge(&load(spec, (64, 64)), &settings(terms, 128), &pipeline));
    }
    assert!(bad.is_empty(), "the GPU path tracer differs from the CPU reference: {bad:?}");
}

/// The emitter-lit box with maps on its materials: a checkered floor (sRGB base colour, UV
/// transform, repeat and mirror), the tall box's metallic-roughness map (and it blended), a
/// normal-mapped back wall, a lamp emitting through a map dark on one side, and the short
/// box alpha-masked by a checker of holes (camera, bounce and shadow rays pass through them).
fn textured_box(size: (u32, u32)) -> Scene {
    use lightbench::scene::{AlphaMode, ImageData, Material, Wrap};
    let mut s = load("cornell_lamp", size);
    let checker = |n: u32, a: [u8; 4], b: [u8; 4], srgb: bool| ImageData {
        width: n,
        height: n,
        rgba: (0..n * n)
            .flat_map(|i| if (i % n + i / n).is_multiple_of(2) { a } else { b })
            .collect(),
        srgb,
    };
    s.textures.push(checker(8, [240, 240, 240, 255], [40, 60, 200, 255], true));
    let image = |width, height, rgba: Vec<u8>, srgb| ImageData {
        width,
        height,
        rgba: rgba.into(),
        srgb,
    };
    // Roughness (green) no sharper than 0.47: a sharp metal makes caustics of the lamp, whose
    // rare bright paths 128 samples' variance estimates miss.
    s.textures.push(image(
        4,
        1,
        vec![0, 120, 0, 255, 0, 255, 255, 255, 0, 160, 128, 255, 0, 200, 30, 255],
        false,
    ));
    s.textures.push(image(2, 1, vec![255, 255, 255, 255, 30, 30, 30, 255], true));
    s.textures.push(checker(4, [200, 200, 200, 255], [200, 200, 200, 0], true));
    // Normals tilted left, right, up and down in turn (tangent space, linear).
    s.textures.push(image(
        2,
        2,
        vec![60, 128, 230, 255, 196, 128, 230, 255, 128, 60, 230, 255, 128, 196, 230, 255],
        false,
    ));
    let lamp = s.materials[s.meshes.iter().find(|m| m.name == "lamp").unwrap().material].clone();
    let mut add = |m: Material, mesh: &str| {
        s.materials.push(m);
        let i = s.materials.len() - 1;
        s.meshes.iter_mut().find(|x| x.name == mesh).unwrap().material = i;
    };
    let mut floor = Material::color("floor", [1.0; 3], 0.6);
    (floor.base_color_texture, floor.uv_transform) = (Some(0), [[2.0, 0.0, 0.25], [0.0, 2.0, 0.0]]);
    floor.sampler.wrap = [Wrap::Repeat, Wrap::Mirror];
    add(floor, "floor");
    let mut tall = Material::color("tall", [0.8, 0.7, 0.5], 1.0);
    (tall.metallic, tall.metallic_roughness_texture) = (1.0, Some(1));
    // Blended: seen through, shadows let through, by coins (stochastic transparency).
    (tall.base_color[3], tall.alpha, tall.double_sided) = (0.6, AlphaMode::Blend, true);
    add(tall, "tall_box");
    let mut back = Material::color("back", [0.73; 3], 0.4);
    (back.normal_texture, back.normal_scale) = (Some(4), 0.8);
    add(back, "back");
    let mut lamp = lamp;
    lamp.emissive_texture = Some(2);
    add(lamp, "lamp");
    let mut short = Material::color("short", [1.0; 3], 0.5);
    (short.base_color_texture, short.alpha) = (Some(3), AlphaMode::Mask(0.5));
    add(short, "short_box");
    s
}

#[test]
fn the_gpu_path_tracer_looks_maps_up_as_the_cpu_reference_does() {
    let scene = textured_box((64, 64));
    let s = settings(&[Term::Direct, Term::Ao, Term::Full], 128);
    let bad = judge(&scene, &s, &gpu_common::root().join("pipelines/pathtrace.lbp"));
    assert!(bad.is_empty(), "with maps: {bad:?}");
}

/// A copy of the path tracer (its pipeline and every shader) in a folder of its own, with
/// `from` replaced by `to` in `shaders/lib/FILE`: a deliberately wrong path tracer.
fn mutant(tag: &str, file: &str, (from, to): (&str, &str)) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("lightbench-pt-mutant-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    copy_tree(&gpu_common::root().join("shaders"), &dir.join("shaders"));
    std::fs::create_dir_all(dir.join("pipelines")).unwrap();
    std::fs::copy(
        gpu_common::root().join("pipelines/pathtrace.lbp"),
        dir.join("pipelines/pathtrace.lbp"),
    )
    .unwrap();
    let lib = dir.join("shaders/lib").join(file);
    let text = std::fs::read_to_string(&lib).unwrap();
    let wrong = text.replace(from, to);
    assert_ne!(wrong, text, "the line the mutant changes is gone");
    std::fs::write(&lib, wrong).unwrap();
    dir
}

/// The same comparison catches a path tracer that lets single-sided emitters light what lies
/// behind them (next-event estimation counting both sides), one that shades hits with their
/// maps' means, and one that cuts nothing out (masked and blended surfaces solid).
#[test]
fn deliberately_wrong_path_tracers_fail_the_comparison() {
    let two_sided = mutant(
        "two-sided",
        "hit_emitters.wgsl",
        ("let facing = select(c, abs(c), tri.double_sided != 0u);", "let facing = abs(c);"),
    );
    let means = mutant("means", "hit_maps.wgsl", ("        look_up_maps(&h, dir);\n", ""));
    let solid = mutant("solid", "hit_maps.wgsl", ("    if m.cutoff == 0.0 {", "    if true {"));
    // The lamp lowered to mid-height and turned to face the ceiling: below it, only its back.
    let mut scene = load("cornell_lamp", (32, 32));
    let lamp = scene.meshes.iter_mut().find(|m| m.name == "lamp").unwrap();
    lamp.transform = glam::Mat4::from_translation(glam::Vec3::new(0.0, -0.6, 0.0)) * lamp.transform;
    for t in lamp.indices.chunks_exact_mut(3) {
        t.swap(1, 2);
    }
    let textured = textured_box((32, 32));
    let s = settings(&[Term::Full], 128);
    let pipeline = |dir: &Path| dir.join("pipelines/pathtrace.lbp");
    for (scene, dirs) in [(&scene, vec![&two_sided]), (&textured, vec![&means, &solid])] {
        let right = judge(scene, &s, &gpu_common::root().join("pipelines/pathtrace.lbp"));
        assert!(right.is_empty(), "{}: the right path tracer: {right:?}", scene.name);
        for dir in dirs {
            assert!(!judge(scene, &s, &pipeline(dir)).is_empty(), "{} passed as equal", dir.display());
        }
    }
    for dir in [two_sided, means, solid] {
        let _ = std::fs::remove_dir_all(dir);
    }
}

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_dir() {
            copy_tree(&e.path(), &to.join(e.file_name()));
        } else {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

/// Samples spread over frames give the image of the same samples in one frame.
#[test]
fn progressive_accumulation_is_independent_of_the_frame_pacing() {
    let scene = load("cornell_lamp", (16, 16));
    let gpu = gpu_common::gpu();
    let pipeline = gpu_common::root().join("pipelines/pathtrace.lbp");
    let read = |per_frame: i64, frames: u32| {
        let (exe, _) = lightbench::render::compile(&gpu, &pipeline, None, &scene, &[]).unwrap();
        let params = [("pt.samples".to_string(), lightbench_compiler::ir::ParamValue::Int(per_frame))];
        let ex = lightbench::render::render_with(&gpu, &exe, &scene, frames, &params).unwrap();
        (
            ex.read_texture(&gpu, "pt.mean", 0, 0).unwrap(),
            ex.read_texture(&gpu, "pt.m2", 0, 0).unwrap(),
        )
    };
    let (once, once_m2) = read(256, 1);
    let (spread, spread_m2) = read(16, 16);
    assert!(once.rgba.chunks_exact(4).all(|p| p[3] == 256.0));
    assert_eq!(once.rgba, spread.rgba, "mean and count");
    assert_eq!(once_m2.rgba, spread_m2.rgba, "squared deviations");
}

/// The smooth-normal convention on the GPU as on the CPU (`lib/lobes.wgsl`, `reflects` in
/// reference/src/shading.rs): shading normals leaning 60° from their face, seen from above
/// their hemisphere and from below it (where nothing is reflected, the sky's light included).
#[test]
fn the_gpu_path_tracer_keeps_the_smooth_normal_convention() {
    let pipeline = gpu_common::root().join("pipelines/pathtrace.lbp");
    for eye in [glam::Vec3::new(3.0, 2.0, 0.0), glam::Vec3::new(-2.0, 1.0, 0.0)] {
        // 64²: the mean z-score of the comparison is judged over enough pixels.
        let scene = Scene {
            size: (64, 64),
            ..crate::reference::leaning_normals(eye)
        };
        let s = settings(&[Term::Full], 128);
        assert_eq!(judge(&scene, &s, &pipeline), Vec::<String>::new(), "from {eye}");
        if eye.x < 0.0 {
            let gpu = on_gpu(&scene, &s, &pipeline);
            assert!(gpu.terms[0].mean.rgba.chunks_exact(4).all(|p| p[..3] == [0.0; 3]), "from {eye}");
        }
    }
}
