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

/// The raster `hdr` of `pipeline` (with `variants` and `params`; ambient 0 among them to
/// compare direct light) and the reference's `direct` term (1 spp: it is exact) of `s`.
pub fn raster_and_direct(s: &Scene, pipeline: &Path, variants: &[(&str, &str)], params: &[(&str, &str)]) -> (Image, Image) {
    use lightbench::reference::{Budget, Settings, Term};
    let settings = Settings {
        budget: Budget::Spp(1),
        terms: vec![Term::Direct],
        ..Settings::default()
    };
    let r = lightbench::reference::render(s, &settings, false);
    let reference = r.term(Term::Direct).unwrap().mean.clone();
    let gpu = gpu();
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let (exe, _) = lightbench::render::compile(&gpu, pipeline, None, s, &v).unwrap_or_else(|e| panic!("{e}"));
    let set: Vec<(String, String)> = params.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
    let params = lightbench::render::parse_params(&exe.plan, &set).unwrap();
    let ex = lightbench::render::render_with(&gpu, &exe, s, 1, &params).unwrap();
    (ex.read_texture(&gpu, "hdr", 0, 0).unwrap(), reference)
}

/// Two images value by value (RGB): the share of values within `tolerance` (relative, against
/// at least 0.02) and the median relative difference.
pub fn agreement(raster: &Image, reference: &Image, tolerance: f64) -> (f64, f64) {
    let mut rel: Vec<f64> = raster
        .rgba
        .chunks_exact(4)
        .zip(reference.rgba.chunks_exact(4))
        .flat_map(|(g, f)| (0..3).map(move |c| (g[c] - f[c]).abs() as f64 / (f[c].abs() as f64).max(0.02)))
        .collect();
    rel.sort_by(f64::total_cmp);
    let share = rel.iter().filter(|&&x| x < tolerance).count() as f64 / rel.len() as f64;
    let median = rel[rel.len() / 2];
    eprintln!("within {tolerance}: {:.2}%, median relative difference {median:.5}", share * 100.0);
    (share, median)
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

/// A camera at `position`, facing -z tilted by `pitch` degrees, 60° field of view.
pub fn camera(position: glam::Vec3, pitch: f32) -> lightbench::scene::Camera {
    lightbench::scene::Camera {
        position,
        yaw: 0.0,
        pitch,
        fov: 60.0,
        near: 0.01,
        far: 100.0,
        animation: None,
    }
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

/// World positions of a depth buffer's pixels (None: background) as `camera` saw them.
pub fn world_positions(camera: &lightbench::scene::Camera, depth: &lightbench::io::Image) -> Vec<Option<glam::Vec3>> {
    let inv = (camera.proj(depth.width as f32 / depth.height as f32) * camera.view()).inverse();
    let (w, h) = (depth.width as f32, depth.height as f32);
    (0..depth.height)
        .flat_map(|y| (0..depth.width).map(move |x| (x, y)))
        .map(|(x, y)| {
            let d = depth.pixel(x, y)[0];
            (d < 1.0).then(|| {
                let ndc = glam::Vec4::new((x as f32 + 0.5) / w * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / h * 2.0, d, 1.0);
                let p = inv * ndc;
                p.truncate() / p.w
            })
        })
        .collect()
}

/// A lamp's material: black, emitting `emission`, from its front only unless `double_sided`.
pub fn lamp_material(emission: [f32; 3], double_sided: bool) -> lightbench::scene::Material {
    let mut lamp = lightbench::scene::Material::color("lamp", [0.0; 3], 1.0);
    lamp.emissive = emission;
    lamp.double_sided = double_sided;
    lamp
}

/// A camera at `position` facing −z, pitched by `pitch` degrees (negative: down), 60° across,
/// with the given near and far planes.
pub fn looking_down(position: glam::Vec3, pitch: f32, (near, far): (f32, f32)) -> lightbench::scene::Camera {
    lightbench::scene::Camera {
        position,
        yaw: 0.0,
        pitch,
        fov: 60.0,
        near,
        far,
        animation: None,
    }
}

/// A large floor (y = 0, 40 units across) of material `floor` and a quad lamp of material
/// `lamp` (centre `c`, half extents `u` and `w`; its front faces along u × w), `size` pixels
/// seen by `camera`, no other light.
pub fn lamp_over_floor(
    (floor, lamp): (lightbench::scene::Material, lightbench::scene::Material),
    (c, u, w): (glam::Vec3, glam::Vec3, glam::Vec3),
    camera: lightbench::scene::Camera,
    size: (u32, u32),
) -> Scene {
    use lightbench::scene::geometry::quad;
    let (mut fv, mut fi) = (vec![], vec![]);
    quad(glam::Vec3::ZERO, glam::Vec3::X * 20.0, glam::Vec3::NEG_Z * 20.0, &mut fv, &mut fi);
    let (mut lv, mut li) = (vec![], vec![]);
    quad(c, u, w, &mut lv, &mut li);
    Scene {
        name: "lamp".into(),
        size,
        camera,
        meshes: vec![
            mesh("floor", (fv, fi), glam::Mat4::IDENTITY),
            lightbench::scene::Mesh {
                material: 1,
                ..mesh("lamp", (lv, li), glam::Mat4::IDENTITY)
            },
        ],
        materials: vec![floor, lamp],
        textures: vec![],
        lights: vec![],
        effects: Default::default(),
    }
}

/// A pipeline with two external inputs, `weights` (a 16-byte buffer) and `noise` (a 4×4
/// RGBA8 texture), shown side by side in `out`: `pipelines/show.ron`, its shader
/// `shaders/show.wgsl`. The pipeline's path.
pub fn external_inputs_pipeline(pipelines: &Path, shaders: &Path) -> PathBuf {
    std::fs::create_dir_all(shaders).unwrap();
    std::fs::write(
        shaders.join("show.wgsl"),
        "@group(2) @binding(0) var<storage, read> weights: array<vec4<f32>>;\n@group(2) @binding(1) var noise: texture_2d<f32>;\n\n@fragment\nfn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {\n    let n = textureLoad(noise, vec2<i32>(pos.xy), 0);\n    return select(weights[0], n, pos.x > 2.0);\n}\n",
    )
    .unwrap();
    let pipeline = pipelines.join("show.ron");
    std::fs::write(
        &pipeline,
        "Pipeline(\n    name: \"show\",\n    resources: {\n        \"weights\": Buffer(size: 16, external: true),\n        \"noise\": Texture(format: Rgba8Unorm, size: Fixed(4, 4), external: true),\n        \"out\": Texture(format: Rgba16Float, size: Viewport),\n    },\n    passes: [Fullscreen(name: \"show\", shader: \"show.wgsl\", reads: [\"weights\", \"noise\"], color: [\"out\"])],\n    output: \"out\",\n)\n",
    )
    .unwrap();
    pipeline
}
