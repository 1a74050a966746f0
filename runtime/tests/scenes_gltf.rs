//! glTF round trip through the loader, and clear errors for broken glTF files.

mod gpu_common;

use gpu_common::*;
use lightbench::io::rmse;
use lightbench::scene::{builtin, export, file};
use std::path::PathBuf;
use std::process::Command;

fn temp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lightbench-gltf-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

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
    let loaded = file::load_file(&scene_file(&dir, "cornell.gltf")).unwrap();
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
    let err = file::load_file(&p).unwrap_err();
    assert!(err.starts_with(&format!("{}:3:", p.display())), "{err}");
    assert!(err.contains("lightz"), "{err}");
    let (code, err) = render_cli(&p, &dir);
    assert_eq!(code, 1, "{err}");
    let missing = file::load("no_such_scene").unwrap_err();
    assert!(missing.contains("cornell, colonnade, many_lights"), "{missing}");
}
