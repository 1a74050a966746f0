//! `cargo bench -p lightbench --bench rt`: what tracing rays costs beside the raster method it
//! replaces, on the adapter at hand — each ray-traced option's passes against its raster
//! counterpart's (shadows: `rt` against shadow maps; AO: `rtao` against GTAO; indirect diffuse:
//! `rt` against `filtered`), at three resolutions, on the spot-lit Cornell box
//! (`scenes/cornell_spot.ron`) and on a glTF model (`scenes/hard/bare.gltf`'s chair on the ground,
//! under a spot light: RSM's indirect light needs one) — and the acceleration structure's
//! build time against the triangle count. GPU time from timestamp queries: rounds interleave the two
//! sides (each renders a frame and waits for it), and the figure is the median and quartiles
//! of the per-round ratio. Needs a GPU adapter with ray queries (lavapipe is enough). Not a
//! test; `cargo test` runs it once at its smallest (`Size::Smoke`).

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::render::compile;
use std::path::{Path, PathBuf};

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::Size;
use common::{load_line, quartiles};

impl Size {
    fn rounds(self) -> usize {
        self.pick(9, 1)
    }
    fn resolutions(self) -> &'static [(u32, u32)] {
        self.pick(&[(128, 96), (256, 192), (512, 384)], &[(32, 24)])
    }
    fn copies(self) -> &'static [u32] {
        self.pick(&[1, 4, 16, 64], &[1, 2])
    }
}

/// One side of a comparison: a pipeline, its variants, and the passes whose time counts.
struct Side {
    pipeline: &'static str,
    variants: &'static [(&'static str, &'static str)],
    passes: &'static [&'static str],
}

/// One comparison: a ray-traced option and its raster counterpart.
struct Pair {
    what: &'static str,
    raster: Side,
    rt: Side,
}

const PAIRS: [Pair; 3] = [
    Pair {
        what: "shadows (maps → rt)",
        raster: Side {
            pipeline: "deferred.lbp",
            variants: &[("shadows", "maps")],
            passes: &["shadow_map", "shadow_cube_classic", "light_directional_spot", "light_point"],
        },
        rt: Side {
            pipeline: "deferred.lbp",
            variants: &[("shadows", "rt")],
            passes: &["light_rt"],
        },
    },
    Pair {
        what: "AO (gtao → rtao, 4 rays)",
        raster: Side {
            pipeline: "deferred_gi.lbp",
            variants: &[("ao", "gtao"), ("indirect_diffuse", "off")],
            passes: &["gtao", "ao_blur_h", "ao_blur_v", "ao_upsample"],
        },
        rt: Side {
            pipeline: "deferred_gi.lbp",
            variants: &[("ao", "rtao"), ("indirect_diffuse", "off")],
            passes: &["rtao", "ao_blur_h", "ao_blur_v", "ao_upsample"],
        },
    },
    Pair {
        what: "indirect diffuse (filtered → rt, 4 rays)",
        raster: Side {
            pipeline: "deferred_gi.lbp",
            variants: &[("indirect_diffuse", "filtered"), ("ao", "none")],
            passes: &["rsm", "gi_clear", "indirect_diffuse", "indirect_blur_h", "indirect_blur_v"],
        },
        rt: Side {
            pipeline: "deferred_gi.lbp",
            variants: &[("indirect_diffuse", "rt"), ("ao", "none")],
            passes: &["indirect_rt", "indirect_blur_h", "indirect_blur_v"],
        },
    },
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// An executor of `side` on `scene`, every pass every frame.
fn executor(gpu: &Gpu, side: &Side, scene: &lightbench::scene::Scene) -> Executor {
    let v: Vec<(String, String)> = side.variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let (exe, _) = compile(gpu, &root().join("pipelines").join(side.pipeline), None, scene, &v).expect("compile");
    let mut ex = Executor::new(gpu, &exe, scene).expect("executor");
    ex.set_reuse(false);
    ex.set_timing(true);
    ex.render_frame(gpu, &ex.inputs(0.0)).expect("warm-up frame");
    ex
}

/// GPU ms of one frame's counted passes (the frame waited for).
fn frame_ms(gpu: &Gpu, ex: &mut Executor, side: &Side) -> f64 {
    ex.render_frame(gpu, &ex.inputs(0.0)).expect("frame");
    ex.wait_idle(gpu).expect("wait");
    ex.last_timings
        .iter()
        .filter(|t| side.passes.contains(&t.pass.as_str()))
        .filter_map(|t| t.gpu_ms)
        .sum()
}

/// The chair of `scenes/hard/bare.gltf` on the ground under a spot light, as a scene file.
fn chair_scene(dir: &Path) -> String {
    let scenes = root().join("scenes");
    let text = format!(
        "Scene(name: \"chair\", size: (64, 64), camera: (position: (0.0, 1.6, 3.0), pitch: -20.0, fov: 50.0, near: 0.05, far: 100.0), \
         models: [(path: \"{}\"), (path: \"{}\")], \
         lights: [Spot(position: (0.5, 2.5, 1.0), direction: (-0.2, -1.0, -0.3), inner: 35.0, outer: 50.0, intensity: 8.0, range: 10.0)])\n",
        scenes.join("ground.gltf").display(),
        scenes.join("hard/bare.gltf").display()
    );
    let path = dir.join("chair.ron");
    std::fs::write(&path, text).expect("scene file");
    path.to_string_lossy().into_owned()
}

/// Scene file `spec` at this size, calling for AO and indirect diffuse.
fn scene(spec: &str, (w, h): (u32, u32)) -> lightbench::scene::Scene {
    use lightbench_compiler::ir::Effect;
    let mut s = lightbench::scene::load(spec).expect("scene");
    s.size = (w, h);
    s.effects.extend([Effect::AmbientOcclusion, Effect::IndirectDiffuse]);
    s
}

fn passes(gpu: &Gpu, size: Size, dir: &Path) {
    println!("ray-traced options against their raster counterparts: GPU ms of their passes, ratio rt / raster (median [quartiles] of {} interleaved rounds)", size.rounds());
    let cornell = root().join("scenes/cornell_spot.ron").to_string_lossy().into_owned();
    for base in [cornell, chair_scene(dir)] {
        for &(w, h) in size.resolutions() {
            let s = scene(&base, (w, h));
            for pair in &PAIRS {
                let (mut a, mut b) = (executor(gpu, &pair.raster, &s), executor(gpu, &pair.rt, &s));
                let (mut ms_a, mut ms_b, mut ratios) = (vec![], vec![], vec![]);
                for round in 0..size.rounds() {
                    // Alternate which side goes first, so that neither always follows the other.
                    let (x, y) = match round % 2 {
                        0 => (frame_ms(gpu, &mut a, &pair.raster), frame_ms(gpu, &mut b, &pair.rt)),
                        _ => {
                            let y = frame_ms(gpu, &mut b, &pair.rt);
                            (frame_ms(gpu, &mut a, &pair.raster), y)
                        }
                    };
                    ms_a.push(x);
                    ms_b.push(y);
                    ratios.push(y / x.max(1e-9));
                }
                let ((_, ma, _), (_, mb, _), (q1, r, q3)) = (quartiles(ms_a), quartiles(ms_b), quartiles(ratios));
                // A counterpart the scene culls (no light it serves) has nothing to compare.
                assert!(ma > 0.0, "{}: the raster side of {} ran no pass", s.name, pair.what);
                println!(
                    "  {:<28} {w:>4}×{h:<4} {:<42} raster {ma:>8.3} ms  rt {mb:>8.3} ms  ×{r:.2} [{q1:.2}, {q3:.2}]",
                    s.name, pair.what
                );
            }
        }
    }
}

/// Acceleration-structure build time (wall clock, the build waited for) against the triangle
/// count: spheres of 2 × 64 × 64 triangles each (`geometry::sphere`), one mesh each, in a grid.
fn builds(gpu: &Gpu, size: Size) {
    use lightbench::scene::{geometry, Material, Mesh, Scene};
    println!(
        "acceleration structure build (BLAS per mesh + TLAS), wall ms, median [quartiles] of {} builds:",
        size.rounds()
    );
    let (vertices, indices) = geometry::sphere(0.4, 64, 64);
    for &n in size.copies() {
        let per_row = (n as f32).sqrt().ceil() as u32;
        let meshes: Vec<Mesh> = (0..n)
            .map(|k| {
                let at = glam::Vec3::new((k % per_row) as f32, 0.0, (k / per_row) as f32);
                Mesh::new("sphere", vertices.clone(), indices.clone(), 0, glam::Mat4::from_translation(at))
            })
            .collect();
        let grey = Material::color("grey", [0.5; 3], 1.0);
        let s = Scene::from_meshes("spheres", (8, 8), meshes, vec![grey], vec![]).expect("scene");
        let triangles: usize = s.meshes.iter().map(|m| m.indices.len() / 3).sum();
        let mut times = vec![];
        for _ in 0..size.rounds() {
            let mut scene = s.clone();
            let gpu_scene = lightbench::gpu::scene_gpu::SceneGpu::new(&gpu.device, &gpu.queue, &mut scene).expect("upload");
            let start = std::time::Instant::now();
            lightbench::gpu::accel::Accel::build(&gpu.device, &gpu.queue, &gpu_scene.meshes, &scene, &[]).expect("build");
            times.push(start.elapsed().as_secs_f64() * 1e3);
        }
        let (q1, m, q3) = quartiles(times);
        println!(
            "  {triangles:>9} triangles in {n:>4} meshes: {m:>9.2} ms [{q1:.2}, {q3:.2}], {:.3} µs per triangle",
            m * 1e3 / triangles as f64
        );
    }
}

fn run(size: Size) {
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}\n{}", gpu.describe(), load_line());
    assert!(
        gpu.profile.has(lightbench_compiler::profile::Feature::ExperimentalRayQuery),
        "this adapter has no ray queries"
    );
    let dir = std::env::temp_dir().join(format!("lightbench-bench-rt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    passes(&gpu, size, &dir);
    builds(&gpu, size);
}

fn main() {
    run(Size::from_args());
}
