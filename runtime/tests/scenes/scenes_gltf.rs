//! glTF round trip through the loader, and clear errors for broken glTF files.

use crate::cli_common;
use crate::gpu_common;

use cli_common::scratch as temp;
use gpu_common::*;
use lightbench::io::rmse;
use lightbench::scene::{self, builtin, export};
use std::path::PathBuf;
use std::process::Command;

/// A scene file placing `model` with the Cornell box's camera and nothing else.
fn scene_file(dir: &std::path::Path, model: &str) -> PathBuf {
    let p = dir.join("scene.ron");
    std::fs::write(
        &p,
        format!(
            "Scene(\n    name: \"roundtrip\",\n    size: (128, 128),\n    camera: (position: (0.0, 1.0, 3.6), yaw: 0.0, pitch: 0.0, fov: 40.0, near: 0.05, far: 20.0),\n    models: [(path: \"{model}\")],\n    effects: [Shadows],\n)\n"
        ),
    )
    .unwrap();
    p
}

#[test]
fn exported_builtin_scene_renders_the_same_after_loading() {
    let dir = temp("roundtrip");
    let original = builtin::cornell();
    export::export(&original, &dir.join("cornell.gltf")).unwrap();
    let loaded = scene::load(scene_file(&dir, "cornell.gltf").to_str().unwrap()).unwrap();
    assert_eq!(loaded.meshes.len(), original.meshes.len());
    assert_eq!(loaded.lights.len(), 1, "the KHR_lights_punctual light comes back");
    assert!((loaded.lights[0].position - original.lights[0].position).length() < 1e-5);
    let g = gpu();
    let a = render_with(&g, &deferred(), &original, &[], 1)
        .read_texture(&g, "hdr", 0, 0)
        .unwrap();
    let b = render_with(&g, &deferred(), &loaded, &[], 1).read_texture(&g, "hdr", 0, 0).unwrap();
    let e = rmse(&a, &b).unwrap();
    assert!(e < 1e-3, "round trip changed the image: RMSE {e}");
}

fn render_cli(scene: &std::path::Path, dir: &std::path::Path) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .args([
            "render",
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            dir.join("x.png").to_str().unwrap(),
        ])
        .current_dir(root())
        .output()
        .unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into_owned())
}

fn broken(tag: &str, edit: impl Fn(&mut serde_json::Value, &mut Vec<u8>)) -> (i32, String, PathBuf) {
    let dir = temp(tag);
    export::export(&builtin::cornell(), &dir.join("model.gltf")).unwrap();
    let mut doc: serde_json::Value = serde_json::from_slice(&std::fs::read(dir.join("model.gltf")).unwrap()).unwrap();
    let mut bin = std::fs::read(dir.join("model.bin")).unwrap();
    edit(&mut doc, &mut bin);
    std::fs::write(dir.join("model.gltf"), serde_json::to_vec(&doc).unwrap()).unwrap();
    std::fs::write(dir.join("model.bin"), bin).unwrap();
    let (code, err) = render_cli(&scene_file(&dir, "model.gltf"), &dir);
    (code, err, dir.join("model.gltf"))
}

#[test]
fn unsupported_required_extension_is_a_clear_error() {
    let (code, err, file) = broken("draco", |doc, _| {
        doc["extensionsUsed"] = serde_json::json!(["KHR_draco_mesh_compression"]);
        doc["extensionsRequired"] = serde_json::json!(["KHR_draco_mesh_compression"]);
    });
    assert_eq!(code, 1, "{err}");
    assert!(err.contains(&file.display().to_string()), "{err}");
    assert!(
        err.contains("requires the unsupported extension `KHR_draco_mesh_compression`"),
        "{err}"
    );
}

/// A buffer URI naming a device would read forever; a model that is a FIFO would block.
#[cfg(unix)]
#[test]
fn devices_and_pipes_are_refused_not_read() {
    let (code, err, _) = broken("device", |doc, _| {
        doc["buffers"][0]["uri"] = serde_json::json!("/dev/zero");
    });
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("`/dev/zero`: not a regular file"), "{err}");
    let dir = temp("fifo");
    assert!(Command::new("mkfifo").arg(dir.join("pipe.gltf")).status().unwrap().success());
    let (code, err) = render_cli(&scene_file(&dir, "pipe.gltf"), &dir);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("error[model-load]") && err.contains(": not a regular file"), "{err}");
}

#[test]
fn truncated_bin_is_a_clear_error() {
    let (code, err, file) = broken("truncated", |_, bin| bin.truncate(bin.len() / 2));
    assert_eq!(code, 1, "{err}");
    assert!(err.contains(&file.display().to_string()), "{err}");
    assert!(err.contains("truncated") || err.contains("buffer"), "{err}");
}

#[test]
fn wrong_accessor_count_is_a_clear_error() {
    let (code, err, file) = broken("count", |doc, _| {
        doc["accessors"][0]["count"] = serde_json::json!(100_000);
    });
    assert_eq!(code, 1, "{err}");
    assert!(err.contains(&file.display().to_string()), "{err}");
    assert!(err.contains("accessor 0 has count 100000"), "{err}");
}

#[test]
fn scene_file_errors_name_the_file_and_position() {
    let dir = temp("scene");
    let p = dir.join("bad.ron");
    std::fs::write(&p, "Scene(\n    size: (64, 64),\n    lightz: [],\n)\n").unwrap();
    let err = scene::load(p.to_str().unwrap()).unwrap_err().to_string();
    assert!(err.contains(&format!("{}:3:5", p.display())), "{err}");
    assert!(err.contains("error[unknown-key]: unknown key `lightz` in scene"), "{err}");
    assert!(err.contains("did you mean `lights`?"), "{err}");
    let (code, err) = render_cli(&p, &dir);
    assert_eq!(code, 1, "{err}");
    let missing = scene::load("no_such_scene").unwrap_err().to_string();
    assert!(missing.contains("cornell, cornell_lamp, colonnade, many_lights"), "{missing}");
}

/// Standard base64 (RFC 4648) for data URIs in the test file.
fn base64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for i in 0..4 {
            if i <= c.len() {
                out.push(T[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[test]
fn embedded_buffers_images_and_materials_are_loaded() {
    // A floor quad whose base colour comes from an embedded 8×2 PNG: left half red, right half blue.
    let png = {
        let img = image::RgbaImage::from_fn(8, 2, |x, _| {
            if x < 4 {
                image::Rgba([255, 0, 0, 255])
            } else {
                image::Rgba([0, 0, 255, 255])
            }
        });
        let mut bytes = std::io::Cursor::new(vec![]);
        img.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
        bytes.into_inner()
    };
    let pos: [f32; 12] = [-2.0, 0.0, 2.0, 2.0, 0.0, 2.0, 2.0, 0.0, -2.0, -2.0, 0.0, -2.0];
    let uv: [f32; 8] = [0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let idx: [u32; 6] = [0, 1, 2, 0, 2, 3];
    let mut bin: Vec<u8> = vec![];
    bin.extend_from_slice(bytemuck::cast_slice(&pos));
    bin.extend_from_slice(bytemuck::cast_slice(&uv));
    bin.extend_from_slice(bytemuck::cast_slice(&idx));
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            {"translation": [0.0, 3.0, 0.0], "rotation": [-0.70710677, 0.0, 0.0, 0.70710677], "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 3.0, "color": [1.0, 1.0, 1.0]}]}},
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "images": [{"uri": format!("data:image/png;base64,{}", base64(&png))}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2.0, 0.0, -2.0], "max": [2.0, 0.0, 2.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 24}
        ],
        "buffers": [{"byteLength": bin.len(), "uri": format!("data:application/octet-stream;base64,{}", base64(&bin))}]
    });
    let dir = temp("embedded");
    std::fs::write(dir.join("floor.gltf"), serde_json::to_vec(&doc).unwrap()).unwrap();
    let scene_path = dir.join("scene.ron");
    std::fs::write(
        &scene_path,
        "Scene(\n    size: (64, 64),\n    camera: (position: (0.0, 6.0, 0.01), pitch: -89.0, fov: 40.0, near: 0.1, far: 20.0),\n    models: [(path: \"floor.gltf\")],\n)\n",
    )
    .unwrap();
    let scene = scene::load(scene_path.to_str().unwrap()).unwrap();
    assert_eq!(scene.textures.len(), 1);
    assert!(scene.textures[0].srgb, "base colour textures are sRGB");
    assert_eq!(scene.lights.len(), 1);
    assert!(
        (scene.lights[0].direction - glam::Vec3::NEG_Y).length() < 1e-4,
        "node -Z turned to point down: {}",
        scene.lights[0].direction
    );
    let g = gpu();
    let ex = render_with(&g, &deferred(), &scene, &[], 1);
    let albedo = ex.read_texture(&g, "gbuf.albedo", 0, 0).unwrap();
    // Texels are filtered linearly with repeat (glTF sampler settings are not applied), so look
    // in the middle of each half, where the colour is pure.
    let at = |x: f32| {
        let (px, py) = scene.project(glam::Vec3::new(x, 0.0, 0.0)).unwrap();
        albedo.pixel(px as u32, py as u32)
    };
    let (neg_x, pos_x) = (at(-1.0), at(1.0));
    assert!(neg_x[0] > 0.9 && neg_x[2] < 0.1, "the u < 0.5 half (x < 0) is red: {neg_x:?}");
    assert!(pos_x[2] > 0.9 && pos_x[0] < 0.1, "the u > 0.5 half (x > 0) is blue: {pos_x:?}");
    let img = output(&g, &ex);
    assert_eq!(img.non_finite(), 0);
}
