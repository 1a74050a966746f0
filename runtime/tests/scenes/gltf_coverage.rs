//! glTF as real exports write it, with generated files: strips and fans become triangle
//! lists, points and lines are skipped with a warning naming the mesh, 16-bit and
//! grey-alpha PNGs load, a missing texture or a non-glTF model is named; texture transforms,
//! sampler wrap modes, alpha masks and occlusion reach the G-buffer.

use crate::cli_common;
use crate::gpu_common;

use cli_common::{lightbench, scratch};
use gpu_common::*;
use lightbench::scene;
use std::path::{Path, PathBuf};

/// A unit quad in the XZ plane (4 vertices) drawn by each `(mode, indices)` primitive, with
/// base-colour texture `image` (a file name) when given. Written as `dir/model.gltf`.
fn write_model(dir: &Path, prims: &[(u32, &[u32])], image: Option<&str>) -> PathBuf {
    write_model_with(dir, prims, image, |_| {})
}

/// `write_model`, then `edit` the document (materials, samplers, extensions).
fn write_model_with(dir: &Path, prims: &[(u32, &[u32])], image: Option<&str>, edit: impl Fn(&mut serde_json::Value)) -> PathBuf {
    let pos: [f32; 12] = [-1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0, 0.0, -1.0, -1.0, 0.0, -1.0];
    let uv: [f32; 8] = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let mut bin: Vec<u8> = vec![];
    bin.extend(pos.iter().flat_map(|v| v.to_le_bytes()));
    bin.extend(uv.iter().flat_map(|v| v.to_le_bytes()));
    // TEXCOORD_1 mirrors u: a map reading it sees the texture flipped left to right.
    let uv1: Vec<f32> = uv.chunks(2).flat_map(|c| [1.0 - c[0], c[1]]).collect();
    bin.extend(uv1.iter().flat_map(|v| v.to_le_bytes()));
    let mut views = vec![
        serde_json::json!({"buffer": 0, "byteOffset": 0, "byteLength": 48}),
        serde_json::json!({"buffer": 0, "byteOffset": 48, "byteLength": 32}),
        serde_json::json!({"buffer": 0, "byteOffset": 80, "byteLength": 32}),
    ];
    let mut accessors = vec![
        serde_json::json!({"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1.0, 0.0, -1.0], "max": [1.0, 0.0, 1.0]}),
        serde_json::json!({"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}),
        serde_json::json!({"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}),
    ];
    let mut primitives = vec![];
    for (mode, idx) in prims {
        views.push(serde_json::json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": idx.len() * 4}));
        bin.extend(idx.iter().flat_map(|v| v.to_le_bytes()));
        accessors.push(serde_json::json!({"bufferView": views.len() - 1, "componentType": 5125, "count": idx.len(), "type": "SCALAR"}));
        primitives.push(serde_json::json!({"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 2}, "indices": accessors.len() - 1, "mode": mode, "material": 0}));
    }
    std::fs::write(dir.join("model.bin"), &bin).unwrap();
    let mut doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "quad", "primitives": primitives}],
        "materials": [{"pbrMetallicRoughness": {"metallicFactor": 0.0}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len(), "uri": "model.bin"}],
    });
    if let Some(img) = image {
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = serde_json::json!({"index": 0});
        doc["textures"] = serde_json::json!([{"source": 0}]);
        doc["images"] = serde_json::json!([{"uri": img}]);
    }
    edit(&mut doc);
    let path = dir.join("model.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    path
}

/// A scene file placing `model` under a camera looking down at it.
fn scene_file(dir: &Path, model: &str) -> PathBuf {
    let p = dir.join("scene.ron");
    let text = format!(
        "Scene(\n    size: (32, 32),\n    camera: (position: (0.0, 3.0, 0.01), pitch: -89.0, fov: 60.0, near: 0.1, far: 10.0),\n    models: [(path: \"{model}\")],\n    lights: [Directional(direction: (0.0, -1.0, 0.0), intensity: 2.0)],\n)\n"
    );
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn strips_and_fans_become_triangle_lists() {
    let d = scratch("strip");
    // glTF mode 5 = TRIANGLE_STRIP, 6 = TRIANGLE_FAN.
    write_model(&d, &[(5, &[0, 1, 3, 2]), (6, &[0, 1, 2, 3])], None);
    let s = scene::load(scene_file(&d, "model.gltf").to_str().unwrap()).unwrap();
    // glTF §3.7.2.1: triangle i of a strip is {v_i, v_(i+1+i%2), v_(i+2-i%2)}; both face +Y.
    assert_eq!(s.meshes[0].indices, vec![0, 1, 3, 1, 2, 3]);
    assert_eq!(s.meshes[1].indices, vec![1, 2, 0, 2, 3, 0], "fan: around the first vertex");
}

#[test]
fn lines_and_points_are_skipped_with_a_warning_naming_the_mesh() {
    let d = scratch("lines");
    // mode 1 = LINES, 0 = POINTS, 4 = TRIANGLES.
    write_model(&d, &[(4, &[0, 1, 2, 0, 2, 3]), (1, &[0, 1, 1, 2]), (0, &[0, 1])], None);
    let scene_path = scene_file(&d, "model.gltf");
    let out = d.join("x.png");
    let (code, _, err) = lightbench(&["render", "--scene", scene_path.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("warning[skipped-primitive]: model `model.gltf`: mesh `quad` primitive 1 is Lines, which is not drawn"),
        "{err}"
    );
    assert!(err.contains("primitive 2 is Points"), "{err}");
    assert!(
        err.contains(&format!("{}:4:21", scene_path.display())),
        "located at the model's path: {err}"
    );
    let s = scene::load(scene_path.to_str().unwrap()).unwrap();
    assert_eq!(s.meshes.len(), 1, "the triangles are kept");
}

#[test]
fn sixteen_bit_and_grey_alpha_pngs_load() {
    let d = scratch("png16");
    // A 2×1 16-bit RGB image: full and half intensity.
    let img = image::ImageBuffer::<image::Rgb<u16>, Vec<u16>>::from_raw(2, 1, vec![65535, 32768, 0, 0, 257, 65535]).unwrap();
    image::DynamicImage::ImageRgb16(img).save(d.join("normal16.png")).unwrap();
    // Used as the material's normal map, as Substance exports do.
    write_model_with(&d, &[(4, &[0, 1, 2, 0, 2, 3])], Some("normal16.png"), |doc| {
        let pbr = &mut doc["materials"][0]["pbrMetallicRoughness"];
        let info = pbr["baseColorTexture"].take();
        pbr.as_object_mut().unwrap().remove("baseColorTexture");
        doc["materials"][0]["normalTexture"] = info;
    });
    let s = scene::load(scene_file(&d, "model.gltf").to_str().unwrap()).unwrap();
    assert_eq!(s.materials[0].normal_texture, Some(0));
    assert!(!s.textures[0].srgb, "normal maps are linear data");
    assert_eq!(s.textures[0].rgba, vec![255, 128, 0, 255, 0, 1, 255, 255]);
    let grey = image::GrayAlphaImage::from_raw(1, 1, vec![200, 100]).unwrap();
    image::DynamicImage::ImageLumaA8(grey).save(d.join("ga.png")).unwrap();
    write_model(&d, &[(4, &[0, 1, 2, 0, 2, 3])], Some("ga.png"));
    let s = scene::load(scene_file(&d, "model.gltf").to_str().unwrap()).unwrap();
    assert_eq!(s.textures[0].rgba, vec![200, 200, 200, 100], "grey and alpha, not red and green");
}

#[test]
fn a_missing_texture_and_a_non_gltf_model_are_named() {
    let d = scratch("missing");
    write_model(&d, &[(4, &[0, 1, 2, 0, 2, 3])], Some("textures/albedo%20map.png"));
    let scene_path = scene_file(&d, "model.gltf");
    let (code, _, err) = lightbench(&["check", "pipelines/deferred.ron", "--scene", scene_path.to_str().unwrap()]);
    assert_eq!(code, 1, "{err}");
    let missing = d.join("textures/albedo map.png");
    assert!(
        err.contains(&format!("image 0 refers to `{}`, which does not exist", missing.display())),
        "{err}"
    );
    std::fs::write(d.join("chair.obj"), "v 0 0 0\n").unwrap();
    let (code, _, err) = lightbench(&[
        "check",
        "pipelines/deferred.ron",
        "--scene",
        scene_file(&d, "chair.obj").to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("not a glTF file: models must be glTF 2.0 (.gltf or .glb)"), "{err}");
}

/// `check --scene` and `plan --scene` read only what planning needs: a texture file that is
/// not an image is not read by them (rc 0, the plan made), only by `render`, which names it
/// (rc 1). A missing texture is still named by `check` (above): files are checked, not decoded.
#[test]
fn planning_reads_no_texture_and_render_names_a_broken_one() {
    let d = scratch("plan-no-decode");
    write_model(&d, &[(4, &[0, 1, 2, 0, 2, 3])], Some("albedo.png"));
    std::fs::write(d.join("albedo.png"), b"not an image at all").unwrap();
    let scene_path = scene_file(&d, "model.gltf");
    let scene_arg = scene_path.to_str().unwrap();
    let (code, _, err) = lightbench(&["check", "pipelines/deferred.ron", "--scene", scene_arg]);
    assert_eq!(code, 0, "check decodes no texture: {err}");
    let (code, out, err) = lightbench(&["plan", "pipelines/deferred.ron", "--scene", scene_arg]);
    assert_eq!(code, 0, "plan decodes no texture: {err}");
    assert!(out.contains("gbuffer"), "the plan is printed: {out}");
    let image = d.join("frame.png");
    let (code, _, err) = lightbench(&[
        "render",
        "--pipeline",
        "pipelines/deferred.ron",
        "--scene",
        scene_arg,
        "--out",
        image.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("model.gltf: image 0 (`albedo.png`) cannot be decoded: Format error decoding Png"),
        "render names the broken texture: {err}"
    );
    assert!(!image.exists(), "nothing written");
}

/// Textures are decoded once (docs/scenes.md): a model's second load reads its texels from
/// the cache, equal to what decoding gave; an entry damaged on disk is decoded again and
/// rewritten; two images of the same bytes are one entry; without a cache nothing is kept.
#[test]
fn textures_are_decoded_once_and_a_damaged_entry_is_rebuilt() {
    use lightbench::scene::gltf_load::load_with;
    use lightbench::scene::texture_cache::{Key, Texels, TextureCache};
    let d = scratch("texture-cache");
    two_texels(&d, 128);
    std::fs::copy(d.join("two.png"), d.join("same.png")).unwrap();
    let model = write_model_with(&d, &[(4, &[0, 1, 2, 0, 2, 3])], Some("two.png"), |doc| {
        doc["images"] = serde_json::json!([{"uri": "two.png"}, {"uri": "same.png"}]);
        doc["textures"] = serde_json::json!([{"source": 0}, {"source": 1}]);
        doc["materials"][0]["emissiveTexture"] = serde_json::json!({"index": 1});
    });
    let texels = |l: &lightbench::scene::gltf_load::Loaded| l.textures.iter().map(|t| t.rgba.clone()).collect::<Vec<_>>();
    let decoded = load_with(&model, &TextureCache::at(None)).unwrap();
    assert_eq!(texels(&decoded)[0], vec![255, 0, 0, 128, 0, 0, 255, 255]);
    // An entry for the PNG's bytes that holds other texels: what a load then gets is the
    // entry's, so it decoded nothing.
    let png = std::fs::read(d.join("two.png")).unwrap();
    let seeded = TextureCache::at(Some(&d.join("seeded")));
    let other = Texels {
        width: 2,
        height: 1,
        rgba: vec![7; 8].into(),
    };
    seeded.get(Key::of("png", &png), || Ok(other.clone())).unwrap();
    assert_eq!(texels(&load_with(&model, &seeded).unwrap())[0], other.rgba);
    // A fresh cache: the first load keeps one entry for the two images of the same bytes, the
    // second reads it.
    let cache_root = d.join("cache");
    let cache = TextureCache::at(Some(&cache_root));
    let first = load_with(&model, &cache).unwrap();
    let entries: Vec<PathBuf> = std::fs::read_dir(cache_root.join("textures"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(entries.len(), 1, "one entry for two images of the same bytes: {entries:?}");
    let second = load_with(&model, &cache).unwrap();
    assert_eq!(texels(&first), texels(&decoded));
    assert_eq!(texels(&second), texels(&decoded));
    // The file edited: other bytes, another entry (these are no image).
    std::fs::write(d.join("two.png"), b"garbage").unwrap();
    assert!(load_with(&model, &cache).is_err());
    std::fs::write(d.join("two.png"), &png).unwrap();
    // A texel of the entry flipped: found out, decoded again, rewritten whole.
    let mut bytes = std::fs::read(&entries[0]).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 0xff;
    std::fs::write(&entries[0], &bytes).unwrap();
    let third = load_with(&model, &cache).unwrap();
    assert_eq!(texels(&third), texels(&decoded), "the damaged entry is not used");
    assert_ne!(std::fs::read(&entries[0]).unwrap(), bytes, "and it is rewritten");
}

/// `render` keeps the textures it decodes where docs/scenes.md says: under
/// `$LIGHTBENCH_CACHE_DIR/textures` when that is set (the same image once); an empty value
/// keeps nothing; a cache that cannot be written is a warning, and the frame is made.
#[test]
fn render_keeps_decoded_textures_where_the_environment_says() {
    let d = scratch("texture-cache-cli");
    two_texels(&d, 255);
    write_model(&d, &[(4, &[0, 1, 2, 0, 2, 3])], Some("two.png"));
    let scene_path = scene_file(&d, "model.gltf");
    let render = |cache: &std::ffi::OsStr| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_lightbench"))
            .args(["render", "--pipeline", "pipelines/deferred.ron", "--scene"])
            .arg(&scene_path)
            .arg("--out")
            .arg(d.join("frame.png"))
            .env("LIGHTBENCH_CACHE_DIR", cache)
            .current_dir(cli_common::root())
            .output()
            .unwrap();
        (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let entries = |dir: &Path| std::fs::read_dir(dir.join("textures")).map(|r| r.count()).unwrap_or(0);
    let (code, err) = render(d.join("cache").as_os_str());
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(entries(&d.join("cache")), 1);
    let (code, err) = render(d.join("cache").as_os_str());
    assert_eq!((code, entries(&d.join("cache"))), (Some(0), 1), "{err}");
    let (code, err) = render(std::ffi::OsStr::new(""));
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("not kept"), "{err}");
    std::fs::write(d.join("a-file"), b"").unwrap();
    let (code, err) = render(d.join("a-file").as_os_str());
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("decoded textures are not kept for the next run"), "{err}");
}

/// The first run of a scene shows its texture decoding on a terminal (docs/scenes.md): a
/// `textures` bar with what was decoded and what came from the cache; piped, nothing.
#[test]
fn texture_decoding_shows_progress_on_a_terminal_only() {
    let d = scratch("texture-progress");
    two_texels(&d, 255);
    write_model(&d, &[(4, &[0, 1, 2, 0, 2, 3])], Some("two.png"));
    let scene_path = scene_file(&d, "model.gltf");
    let cache = d.join("cache");
    let _ = std::fs::remove_dir_all(&cache);
    let render = format!(
        "'{}' render --pipeline pipelines/deferred.ron --scene '{}' --out '{}'",
        env!("CARGO_BIN_EXE_lightbench"),
        scene_path.display(),
        d.join("frame.png").display()
    );
    // `script` runs the command on a pseudo-terminal and copies what it shows to stdout.
    let on_terminal = || {
        let out = std::process::Command::new("script")
            .args(["-qec", &render, "/dev/null"])
            .env("LIGHTBENCH_CACHE_DIR", &cache)
            .current_dir(cli_common::root())
            .output()
            .expect("script (util-linux) runs a command on a terminal");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stdout));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let first = on_terminal();
    assert!(
        first.contains("textures") && first.contains("1/1 (1 decoded, 0 from the cache"),
        "{first}"
    );
    let second = on_terminal();
    assert!(second.contains("1/1 (0 decoded, 1 from the cache"), "{second}");
    let piped = std::process::Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .args(["render", "--pipeline", "pipelines/deferred.ron", "--scene"])
        .arg(&scene_path)
        .arg("--out")
        .arg(d.join("frame.png"))
        .env("LIGHTBENCH_CACHE_DIR", d.join("another cache"))
        .current_dir(cli_common::root())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&piped.stderr);
    assert!(piped.status.success() && !err.contains("textures"), "{err}");
}

/// What planning reads of a scene (`features_in`: models' JSON only) is what it reads of the
/// loaded scene: for every bundled scene file, built-in scene and model, a model whose pane
/// blends, and an emissive one whose points are skipped (the same warnings and emitter lights).
#[test]
fn scene_features_without_geometry_equal_those_of_the_loaded_scene() {
    let mut specs: Vec<String> = ["cornell", "cornell_lamp", "colonnade", "many_lights", "panes"]
        .map(String::from)
        .to_vec();
    for dir in ["scenes", "scenes/hard"] {
        for e in std::fs::read_dir(root().join(dir)).unwrap() {
            let p = e.unwrap().path();
            if matches!(p.extension().and_then(|e| e.to_str()), Some("ron" | "gltf" | "glb")) {
                specs.push(p.display().to_string());
            }
        }
    }
    let d = scratch("features");
    wall_and_pane(&d, Some(("BLEND", 0.4)));
    specs.push(d.join("quads.ron").display().to_string());
    // Points skipped, an emissive triangle (an emitter light) and a strip.
    let m = scratch("features-points");
    write_model_with(&m, &[(4, &[0, 1, 2]), (0, &[0, 1]), (5, &[0, 1, 3, 2])], None, |d| {
        d["materials"][0]["emissiveFactor"] = serde_json::json!([1.0, 0.5, 0.0]);
    });
    specs.push(scene_file(&m, "model.gltf").display().to_string());
    assert!(specs.len() > 30, "{specs:?}");
    for spec in &specs {
        let (mut a, mut b) = (lightbench_compiler::Session::new(), lightbench_compiler::Session::new());
        let planned = scene::features_in(&mut a, spec).unwrap_or_else(|| panic!("{spec}: {}", a.render()));
        let loaded = scene::load_in(&mut b, spec).unwrap_or_else(|| panic!("{spec}: {}", b.render()));
        assert_eq!(planned, loaded.features(), "{spec}");
        assert_eq!(a.render(), b.render(), "{spec}: the same warnings");
    }
}

/// A 2×1 texture: left texel red (alpha `left_alpha`), right texel blue; nearest filtering.
fn two_texels(dir: &Path, left_alpha: u8) {
    let img = image::RgbaImage::from_raw(2, 1, vec![255, 0, 0, left_alpha, 0, 0, 255, 255]).unwrap();
    img.save(dir.join("two.png")).unwrap();
}

/// The quad's G-buffer albedo and depth at world x = `x` (z = 0), seen from above (32×32).
fn albedo_at(dir: &Path, edit: impl Fn(&mut serde_json::Value), xs: &[f32]) -> Vec<([f32; 4], f32)> {
    write_model_with(dir, &[(4, &[0, 1, 2, 0, 2, 3])], Some("two.png"), |doc| {
        doc["samplers"] = serde_json::json!([{"magFilter": 9728, "minFilter": 9728}]);
        doc["textures"][0]["sampler"] = serde_json::json!(0);
        edit(doc);
    });
    let s = scene::load(scene_file(dir, "model.gltf").to_str().unwrap()).unwrap();
    let g = gpu();
    let ex = render_with(&g, &deferred(), &s, &[], 1);
    let albedo = ex.read_texture(&g, "gbuf.albedo", 0, 0).unwrap();
    let depth = ex.read_texture(&g, "gbuf.depth", 0, 0).unwrap();
    xs.iter()
        .map(|x| {
            let (px, _) = s.project(glam::Vec3::new(*x, 0.0, 0.0)).unwrap();
            (albedo.pixel(px as u32, 16), depth.pixel(px as u32, 16)[0])
        })
        .collect()
}

fn red(p: [f32; 4]) -> bool {
    p[0] > 0.9 && p[2] < 0.1
}
fn blue(p: [f32; 4]) -> bool {
    p[2] > 0.9 && p[0] < 0.1
}

#[test]
fn texture_transform_offset_moves_the_texture() {
    let d = scratch("transform");
    two_texels(&d, 255);
    // u runs from 0 at x = -1 to 1 at x = 1: red on the left half, blue on the right.
    let plain = albedo_at(&d, |_| {}, &[-0.5, 0.5]);
    assert!(red(plain[0].0) && blue(plain[1].0), "{plain:?}");
    let shifted = albedo_at(
        &d,
        |doc| {
            doc["extensionsUsed"] = serde_json::json!(["KHR_texture_transform"]);
            doc["extensionsRequired"] = serde_json::json!(["KHR_texture_transform"]);
            doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
                serde_json::json!({"KHR_texture_transform": {"offset": [0.5, 0.0]}});
        },
        &[-0.5, 0.5],
    );
    assert!(
        blue(shifted[0].0) && red(shifted[1].0),
        "offset 0.5 swaps the halves (repeat wraps): {shifted:?}"
    );
}

#[test]
fn clamp_and_repeat_differ_where_uvs_exceed_one() {
    let d = scratch("wrap");
    two_texels(&d, 255);
    let scaled = |wrap: u32| {
        move |doc: &mut serde_json::Value| {
            doc["extensionsUsed"] = serde_json::json!(["KHR_texture_transform"]);
            doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
                serde_json::json!({"KHR_texture_transform": {"scale": [2.0, 1.0]}});
            doc["samplers"][0]["wrapS"] = serde_json::json!(wrap);
        }
    };
    // At x = 0.2, u = 0.6 and u' = 1.2: REPEAT reads u 0.2 (red), CLAMP the right edge (blue).
    let repeat = albedo_at(&d, scaled(10497), &[0.2]);
    let clamp = albedo_at(&d, scaled(33071), &[0.2]);
    assert!(red(repeat[0].0), "{repeat:?}");
    assert!(blue(clamp[0].0), "{clamp:?}");
}

#[test]
fn alpha_mask_cuts_out() {
    let d = scratch("mask");
    two_texels(&d, 0); // the red half is fully transparent
    let masked = albedo_at(&d, |doc| doc["materials"][0]["alphaMode"] = serde_json::json!("MASK"), &[-0.5, 0.5]);
    assert_eq!(masked[0].1, 1.0, "the transparent half is cut out: nothing drawn there");
    assert!(masked[1].1 < 1.0 && blue(masked[1].0), "{masked:?}");
    let opaque = albedo_at(&d, |_| {}, &[-0.5]);
    assert!(opaque[0].1 < 1.0, "OPAQUE ignores alpha");
}

/// A map on TEXCOORD_1 reads the second UV set (here u mirrored: the halves swap); a set
/// beyond the second is read as the first, with a warning.
#[test]
fn texcoord_1_is_kept_per_map() {
    let d = scratch("uv1");
    two_texels(&d, 255);
    let second = albedo_at(
        &d,
        |doc| doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = serde_json::json!(1),
        &[-0.5, 0.5],
    );
    assert!(blue(second[0].0) && red(second[1].0), "{second:?}");
    write_model_with(&d, &[(4, &[0, 1, 2, 0, 2, 3])], Some("two.png"), |doc| {
        doc["materials"][0]["name"] = serde_json::json!("decal");
        doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = serde_json::json!(2);
    });
    let (code, _, err) = lightbench(&[
        "check",
        "pipelines/deferred.ron",
        "--scene",
        scene_file(&d, "model.gltf").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("material `decal` samples TEXCOORD_2 or higher, read as TEXCOORD_0"),
        "{err}"
    );
}

#[test]
fn occlusion_darkens_the_ambient_term_only() {
    let d = scratch("occlusion");
    image::RgbaImage::from_raw(1, 1, vec![0, 0, 0, 255])
        .unwrap()
        .save(d.join("ao.png"))
        .unwrap();
    let ambient = |occluded: bool| {
        write_model_with(&d, &[(4, &[0, 1, 2, 0, 2, 3])], None, |doc| {
            if occluded {
                doc["materials"][0]["occlusionTexture"] = serde_json::json!({"index": 0, "strength": 1.0});
                doc["textures"] = serde_json::json!([{"source": 0}]);
                doc["images"] = serde_json::json!([{"uri": "ao.png"}]);
            }
        });
        let mut s = scene::load(scene_file(&d, "model.gltf").to_str().unwrap()).unwrap();
        s.lights.clear(); // ambient only
        let g = gpu();
        let ex = render_with(&g, &deferred(), &s, &[], 1);
        ex.read_texture(&g, "hdr", 0, 0).unwrap().pixel(16, 16)
    };
    let (open, occluded) = (ambient(false), ambient(true));
    assert!(open[0] > 0.005, "ambient light reaches the open quad: {open:?}");
    assert!(occluded[0] < open[0] * 0.01, "full occlusion removes it: {occluded:?} vs {open:?}");
}

/// A red wall (a quad facing +Z at z = 0) and, unless `pane` is None, a smaller blue pane in
/// front of it (z = 0.5) with that alphaMode and alpha; seen head-on, lit from the camera.
fn wall_and_pane(dir: &Path, pane: Option<(&str, f32)>) -> lightbench::scene::Scene {
    let pos: [f32; 12] = [-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0];
    let nrm: [f32; 12] = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
    let idx: [u32; 6] = [0, 1, 2, 0, 2, 3];
    let mut bin: Vec<u8> = vec![];
    bin.extend(pos.iter().chain(&nrm).flat_map(|v| v.to_le_bytes()));
    bin.extend(idx.iter().flat_map(|v| v.to_le_bytes()));
    std::fs::write(dir.join("quads.bin"), &bin).unwrap();
    let prim = |material: usize| serde_json::json!({"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": material}]});
    let (mode, alpha) = pane.unwrap_or(("OPAQUE", 1.0));
    let mut nodes = vec![serde_json::json!({"mesh": 0, "scale": [2.0, 2.0, 1.0]})];
    if pane.is_some() {
        nodes.push(serde_json::json!({"mesh": 1, "translation": [0.0, 0.0, 0.5], "scale": [0.5, 0.5, 1.0]}));
    }
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}], "nodes": nodes,
        "meshes": [prim(0), prim(1)],
        "materials": [
            {"name": "wall", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}},
            {"name": "pane", "alphaMode": mode, "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 1.0, alpha], "metallicFactor": 0.0, "roughnessFactor": 1.0}}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1.0, -1.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 24}
        ],
        "buffers": [{"byteLength": bin.len(), "uri": "quads.bin"}]
    });
    std::fs::write(dir.join("quads.gltf"), serde_json::to_vec(&doc).unwrap()).unwrap();
    let p = dir.join("quads.ron");
    let text = "Scene(\n    size: (32, 32),\n    camera: (position: (0.0, 0.0, 3.0), fov: 50.0, near: 0.1, far: 10.0),\n    models: [(path: \"quads.gltf\")],\n    lights: [Directional(direction: (0.0, 0.0, -1.0), intensity: 2.0, shadows: false)],\n)\n";
    std::fs::write(&p, text).unwrap();
    scene::load(p.to_str().unwrap()).unwrap()
}

/// A BLEND pane with alpha 0.4 over a red wall: the HDR pixel behind it is 0.4 × the pane
/// lit on its own + 0.6 × the wall lit on its own, and the pane's pass is culled when nothing
/// blends.
#[test]
fn a_blend_pane_over_a_red_wall_blends_over() {
    let d = scratch("blend");
    let g = gpu();
    let hdr = |s: &lightbench::scene::Scene| {
        let ex = render_with(&g, &deferred(), s, &[], 1);
        let culled = ex.plan().culled.iter().any(|c| c.name == "transparent");
        (ex.read_texture(&g, "hdr", 0, 0).unwrap().pixel(16, 16), culled)
    };
    let (wall, culled) = hdr(&wall_and_pane(&d, None));
    assert!(culled, "no blended mesh: the transparent pass is culled");
    let (pane, _) = hdr(&wall_and_pane(&d, Some(("OPAQUE", 1.0))));
    let (blended, culled) = hdr(&wall_and_pane(&d, Some(("BLEND", 0.4))));
    assert!(!culled);
    for c in 0..3 {
        let expected = 0.4 * pane[c] + 0.6 * wall[c];
        assert!(
            (blended[c] - expected).abs() < 0.03 * expected.max(0.05),
            "channel {c}: {blended:?} vs {expected} (pane {pane:?}, wall {wall:?})"
        );
    }
    assert!(blended[0] > 0.1 && blended[2] > 0.1, "both show: {blended:?}");
}

/// glTF `doubleSided` decides whether a surface is seen from behind, and a scene file's model
/// `double_sided` overrides it: the quad turned over (its back to the camera and the sun
/// above) is drawn only when double-sided, lit as its own side (its normal flipped).
#[test]
fn double_sided_is_read_and_a_scene_file_overrides_it() {
    let d = scratch("double-sided");
    let seen = |double_sided: Option<bool>, scene_says: Option<bool>| -> Option<[f32; 4]> {
        write_model_with(&d, &[(4, &[0, 1, 2, 0, 2, 3])], None, |doc| {
            if let Some(v) = double_sided {
                doc["materials"][0]["doubleSided"] = serde_json::json!(v);
            }
        });
        let over = scene_says.map_or(String::new(), |v| format!(", double_sided: {v}"));
        let text = format!(
            "Scene(\n    size: (32, 32),\n    camera: (position: (0.0, 3.0, 0.01), pitch: -89.0, fov: 60.0, near: 0.1, far: 10.0),\n    models: [(path: \"model.gltf\", rotation: (0.0, 180.0, 0.0){over})],\n    lights: [Directional(direction: (0.0, -1.0, 0.0), intensity: 2.0)],\n)\n"
        );
        std::fs::write(d.join("turned.ron"), text).unwrap();
        let s = scene::load(d.join("turned.ron").to_str().unwrap()).unwrap();
        let g = gpu();
        let ex = render_with(&g, &deferred(), &s, &[], 1);
        let depth = ex.read_texture(&g, "gbuf.depth", 0, 0).unwrap().pixel(16, 16)[0];
        (depth < 1.0).then(|| ex.read_texture(&g, "hdr", 0, 0).unwrap().pixel(16, 16))
    };
    assert_eq!(seen(None, None), None, "single-sided by default: its back is not drawn");
    let lit = seen(Some(true), None).expect("doubleSided: its back is drawn");
    assert!(lit[0] > 0.3, "lit from above through its flipped normal: {lit:?}");
    assert_eq!(seen(Some(true), Some(false)), None, "the scene file makes it single-sided");
    assert!(seen(Some(false), Some(true)).is_some(), "the scene file makes it double-sided");
}
