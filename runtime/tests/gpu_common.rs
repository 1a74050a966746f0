//! Shared by the GPU tests: one device per test binary, compile + render helpers.
//! These tests need a real adapter (lavapipe in CI) and fail, never skip, without one.

#![allow(dead_code)]

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::io::Image;
use lightbench::scene::Scene;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// The device is shared; tests take turns (lavapipe renders on the CPU anyway).
pub fn gpu() -> std::sync::MutexGuard<'static, Gpu> {
    static GPU: OnceLock<Mutex<Gpu>> = OnceLock::new();
    GPU.get_or_init(|| {
        Mutex::new(Gpu::new(&DeviceOptions::default()).unwrap_or_else(|e| panic!("GPU tests need an adapter (CI installs lavapipe): {e}")))
    })
    .lock()
    .unwrap_or_else(|e| e.into_inner())
}

pub fn deferred() -> PathBuf {
    root().join("pipelines/deferred.ron")
}

pub fn render_with(gpu: &Gpu, pipeline: &Path, scene: &Scene, variants: &[(&str, &str)], frames: u32) -> Executor {
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let (exe, _) = lightbench::render::compile(gpu, pipeline, None, scene, &v).unwrap_or_else(|e| panic!("{e}"));
    lightbench::render::render(gpu, &exe, scene, frames).unwrap_or_else(|e| panic!("{e}"))
}

pub fn output(gpu: &Gpu, ex: &Executor) -> Image {
    ex.read_texture(gpu, &ex.plan().output_resource().name, 0, 0).unwrap()
}

/// The bundled pipelines and shaders in memory, under `mem/` (edit them without touching disk).
pub fn memory_project() -> std::sync::Arc<lightbench_compiler::vfs::MemoryVfs> {
    fn add(vfs: &lightbench_compiler::vfs::MemoryVfs, from: &Path, to: &Path) {
        for e in std::fs::read_dir(from).unwrap() {
            let p = e.unwrap().path();
            let dest = to.join(p.file_name().unwrap());
            if p.is_dir() {
                add(vfs, &p, &dest);
            } else {
                vfs.write(&dest, std::fs::read_to_string(&p).unwrap());
            }
        }
    }
    let vfs = std::sync::Arc::new(lightbench_compiler::vfs::MemoryVfs::new());
    add(&vfs, &root().join("pipelines"), Path::new("mem/pipelines"));
    add(&vfs, &root().join("shaders"), Path::new("mem/shaders"));
    vfs
}

/// A scratch folder for scene files written by a test (`tag` names it), holding copies of
/// the bundled models a scene there refers to.
pub fn scene_dir(tag: &str, models: &[&str]) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("lightbench-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    for f in models {
        std::fs::copy(root().join("scenes").join(f), d.join(f)).unwrap();
    }
    d
}

/// A mesh of the first material, placed by `transform`.
pub fn mesh(
    name: &str,
    (vertices, indices): (Vec<lightbench::blocks::Vertex>, Vec<u32>),
    transform: glam::Mat4,
) -> lightbench::scene::Mesh {
    lightbench::scene::Mesh {
        name: name.into(),
        vertices,
        indices,
        material: 0,
        transform,
        triangle_fraction: 1.0,
        reflective: false,
    }
}

/// The colonnade (128×64) with a point light among its columns, which has none of its own:
/// what cube-shadow comparisons render besides the Cornell box.
pub fn colonnade_with_point_light() -> Scene {
    let mut colonnade = lightbench::scene::builtin::colonnade();
    colonnade.size = (128, 64);
    colonnade.lights.push(lightbench::scene::Light::point(
        glam::Vec3::new(0.0, 2.0, 0.0),
        glam::Vec3::ONE,
        20.0,
        12.0,
    ));
    colonnade
}
