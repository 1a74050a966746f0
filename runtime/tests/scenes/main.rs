//! Scenes rendered: glTF coverage, real assets, scene files, glTF scenes and their scale.
//! One test binary per area; each file below is a module of it.

#[path = "../cli_common/mod.rs"]
mod cli_common;
#[path = "../gpu_common/mod.rs"]
mod gpu_common;
#[path = "../mutate/mod.rs"]
mod mutate;

mod gltf_coverage;
mod real_assets;
mod scene_files;
mod scenes_gltf;
