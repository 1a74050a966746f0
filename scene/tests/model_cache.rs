//! Loading a scene again keeps its models whose files did not change: the scene file with
//! two models, loaded, loaded again (both kept), one model edited (that one parsed again, its
//! change seen), a model dropped from the scene (no longer kept).

use lightbench_scene::load::load_with;
use lightbench_scene::model_cache::ModelCache;
use lightbench_scene::Scene;
use std::path::{Path, PathBuf};

fn project() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().join("scenes");
    let dir = std::env::temp_dir().join(format!("lightbench-models-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for f in ["ground.gltf", "red_box.gltf"] {
        std::fs::copy(root.join(f), dir.join(f)).unwrap();
    }
    dir
}

/// The scene at `spec` loaded again with `models`, and how many models it kept, of all.
fn load_again(spec: &str, models: &mut ModelCache) -> (Scene, (usize, usize)) {
    let scene = load_with(spec, models).unwrap();
    (scene, models.last())
}

const SCENE: &str = "Scene(name: \"two\", models: [(path: \"ground.gltf\"), (path: \"red_box.gltf\", translation: (0, 0.5, 0))])\n";

#[test]
fn a_scene_loaded_again_parses_only_the_models_that_changed() {
    let dir = project();
    let file = dir.join("two.ron");
    std::fs::write(&file, SCENE).unwrap();
    let spec = file.display().to_string();
    let mut models = ModelCache::keeping();
    let (first, kept) = load_again(&spec, &mut models);
    assert_eq!(kept, (0, 2), "the first load parses both");
    let (again, kept) = load_again(&spec, &mut models);
    assert_eq!(kept, (2, 2), "nothing changed: both kept");
    assert_eq!(again.meshes.len(), first.meshes.len());
    // The ground's colour edited: it is parsed again, the box kept, and the change is there.
    let ground = dir.join("ground.gltf");
    let mut doc: serde_json::Value = serde_json::from_slice(&std::fs::read(&ground).unwrap()).unwrap();
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = serde_json::json!([0.05, 0.05, 0.05, 1.0]);
    std::fs::write(&ground, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    let (edited, kept) = load_again(&spec, &mut models);
    assert_eq!(kept, (1, 2));
    assert_ne!(
        edited.materials[0].base_color, first.materials[0].base_color,
        "the edited colour is loaded"
    );
    // The box removed from the scene: one model, parsed before and unchanged, kept.
    std::fs::write(&file, "Scene(name: \"one\", models: [(path: \"ground.gltf\")])\n").unwrap();
    let (_, kept) = load_again(&spec, &mut models);
    assert_eq!(kept, (1, 1));
    // A cache that keeps nothing (what a single load uses) parses every time.
    let mut once = ModelCache::default();
    for _ in 0..2 {
        assert_eq!(load_again(&spec, &mut once).1, (0, 1));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
