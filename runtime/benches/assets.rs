//! `cargo bench -p lightbench --bench assets`: load time and peak memory of a generated
//! 100k-triangle glTF model with four 2048² textures, rendered once. Compares the executor
//! that copies the caller's scene (`Executor::new`, the old path) with the one that takes
//! it and drops each decoded texture once uploaded (`Executor::with_scene`, what `render`
//! uses), against the bytes the GPU holds (textures with mips + mesh). Goal: peak ≤ 1.5×
//! those bytes. Needs a GPU adapter (lavapipe is enough: there "GPU" memory is this
//! process's memory too, so the goal is strict). `cargo test` runs it at
//! its smallest (`Size::Smoke`: a 16² grid, 64² textures, one round). Then the model's load with its
//! textures decoded (an empty texture cache) against read from the cache a first load kept,
//! interleaved rounds: the cached load's share of the decoding one (goal ≤ 0.10). The
//! executor runs load through an empty cache of their own each time, so both decode. Last,
//! a scene reload after a material edit keeping the unchanged meshes and textures resident
//! against uploading everything again (interleaved rounds).

use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::memory::{mib, peak_resident, reset_peak, resident};
use lightbench::render::compile;
use lightbench::scene;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::Size;

impl Size {
    /// Quads along the grid's side (224² quads: 100,352 triangles).
    fn grid(self) -> u32 {
        self.pick(224, 16)
    }
    /// The textures' side.
    fn texture(self) -> u32 {
        self.pick(2048, 64)
    }
    /// Rounds of the cached-against-decoded comparison.
    fn rounds(self) -> usize {
        self.pick(7, 1)
    }
}

/// A height-field grid with four textures (base colour, metallic-roughness, normal, occlusion).
fn write_model(dir: &Path, size: Size) -> (PathBuf, u64) {
    let (grid, texture) = (size.grid(), size.texture());
    let n = grid + 1;
    let mut bin: Vec<u8> = vec![];
    for j in 0..n {
        for i in 0..n {
            let (u, v) = (i as f32 / grid as f32, j as f32 / grid as f32);
            let h = 0.05 * ((u * 20.0).sin() + (v * 17.0).cos());
            bin.extend([u * 2.0 - 1.0, h, v * 2.0 - 1.0].iter().flat_map(|x| x.to_le_bytes()));
        }
    }
    let uv_at = bin.len();
    for j in 0..n {
        for i in 0..n {
            bin.extend(
                [i as f32 / grid as f32, j as f32 / grid as f32]
                    .iter()
                    .flat_map(|x| x.to_le_bytes()),
            );
        }
    }
    let idx_at = bin.len();
    for j in 0..grid {
        for i in 0..grid {
            let a = j * n + i;
            for k in [a, a + n, a + 1, a + 1, a + n, a + n + 1] {
                bin.extend(k.to_le_bytes());
            }
        }
    }
    std::fs::write(dir.join("grid.bin"), &bin).expect("write buffer");
    for (k, name) in ["base", "mr", "normal", "ao"].iter().enumerate() {
        // Gradients with grain, as a photographed texture has: PNG keeps about half of it.
        let img = image::RgbImage::from_fn(texture, texture, |x, y| {
            let grain = (x.wrapping_mul(374_761_393) ^ y.wrapping_mul(668_265_263)).wrapping_mul(1_274_126_177) >> 28;
            image::Rgb([((x >> 3) + grain) as u8, ((y >> 3) + grain) as u8, (k as u32 * 60 + grain) as u8])
        });
        img.save(dir.join(format!("{name}.png"))).expect("write texture");
        img.save(dir.join(format!("{name}.jpg"))).expect("write texture");
    }
    let (verts, indices) = ((n * n) as usize, (grid * grid * 6) as usize);
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{
            "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1}},
            "normalTexture": {"index": 2}, "occlusionTexture": {"index": 3}
        }],
        "textures": [{"source": 0}, {"source": 1}, {"source": 2}, {"source": 3}],
        "images": [{"uri": "base.png"}, {"uri": "mr.png"}, {"uri": "normal.png"}, {"uri": "ao.png"}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": verts, "type": "VEC3", "min": [-1.0, -0.1, -1.0], "max": [1.0, 0.1, 1.0]},
            {"bufferView": 1, "componentType": 5126, "count": verts, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": indices, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": uv_at},
            {"buffer": 0, "byteOffset": uv_at, "byteLength": idx_at - uv_at},
            {"buffer": 0, "byteOffset": idx_at, "byteLength": bin.len() - idx_at}
        ],
        "buffers": [{"byteLength": bin.len(), "uri": "grid.bin"}]
    });
    let path = dir.join("grid.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).expect("json")).expect("write model");
    // The same with JPEG textures (what most photographed textures are: smaller files, slower
    // to decode), and without textures: what a load costs beside its images.
    let mut jpeg = doc.clone();
    jpeg["images"] = serde_json::json!([{"uri": "base.jpg"}, {"uri": "mr.jpg"}, {"uri": "normal.jpg"}, {"uri": "ao.jpg"}]);
    std::fs::write(dir.join("grid_jpeg.gltf"), serde_json::to_vec(&jpeg).expect("json")).expect("write model");
    let mut bare = doc.clone();
    for key in ["textures", "images"] {
        bare.as_object_mut().expect("object").remove(key);
    }
    bare["materials"] = serde_json::json!([{}]);
    std::fs::write(dir.join("bare.gltf"), serde_json::to_vec(&bare).expect("json")).expect("write model");
    // What the GPU holds: four RGBA8 textures with full mip chains, and the mesh.
    let tex = 4 * (texture as u64 * texture as u64 * 4) * 4 / 3;
    let mesh = verts as u64 * std::mem::size_of::<lightbench::blocks::Vertex>() as u64 + indices as u64 * 4;
    (path, tex + mesh)
}

/// Load, compile and render once: load ms, and the peak bytes above the resident set at the
/// start while loading and over the whole run.
fn load_and_render(gpu: &Gpu, model: &Path, root: &Path, take: bool) -> (f64, u64, u64) {
    reset_peak();
    let base = resident().unwrap_or(0);
    let t = Instant::now();
    let s = scene::load(model.to_str().expect("utf-8 path")).expect("model loads");
    // Each run decodes: the cache `main` points the runs at is emptied.
    if let Some(cache) = std::env::var_os(scene::texture_cache::CACHE_ENV) {
        let _ = std::fs::remove_dir_all(cache);
    }
    let load_ms = t.elapsed().as_secs_f64() * 1e3;
    let load_peak = peak_resident().unwrap_or(0).saturating_sub(base);
    let (exe, _) = compile(gpu, &root.join("pipelines/deferred.ron"), None, &s, &[]).expect("compiles");
    let mut ex = if take {
        Executor::with_scene(gpu, &exe, s)
    } else {
        Executor::new(gpu, &exe, &s)
    }
    .expect("executor");
    ex.render_frame(gpu, &ex.inputs(0.0)).expect("frame");
    let peak = peak_resident().unwrap_or(0).saturating_sub(base);
    (load_ms, load_peak, peak)
}

fn main() {
    // The executor runs decode their textures: an empty cache of their own each time.
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bench-assets-run-cache");
    std::env::set_var(scene::texture_cache::CACHE_ENV, &dir);
    run(Size::from_args());
    let _ = std::fs::remove_dir_all(dir);
}

fn run(size: Size) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("repository root")
        .to_path_buf();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("bench-assets-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("bench directory");
    let (model, gpu_bytes) = write_model(&dir, size);
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    if !reset_peak() {
        println!("note: the peak cannot be reset here; figures include earlier allocations");
    }
    println!(
        "model: {} triangles, 4 textures of {}², GPU-resident {}",
        size.grid() * size.grid() * 2,
        size.texture(),
        mib(Some(gpu_bytes))
    );
    for (name, take) in [("copying executor (before)", false), ("taking executor (after)", true)] {
        let (load_ms, load_peak, peak) = load_and_render(&gpu, &model, &root, take);
        println!(
            "{name:<28} load {load_ms:>6.1} ms (peak +{})   run peak +{}   {:.2}× GPU-resident (goal ≤ 1.5×)",
            mib(Some(load_peak)),
            mib(Some(peak)),
            peak as f64 / gpu_bytes as f64
        );
    }
    decoded_once(&model, &dir, ("PNG", size.rounds()));
    decoded_once(&dir.join("grid_jpeg.gltf"), &dir, ("JPEG", size.rounds()));
    scene_reload(&gpu, &model, size.rounds());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A scene reload as `render --watch` does one after a model's material colour changed: the
/// model loaded again (textures from the cache a first load kept) and uploaded, keeping
/// resident what the scene on the GPU already holds (`SceneGpu::reusing`), against uploading
/// all of it (`SceneGpu::new`, what a reload did before), in interleaved rounds, each side
/// waiting for the GPU.
fn scene_reload(gpu: &Gpu, model: &Path, rounds: usize) {
    use lightbench::gpu::scene_gpu::SceneGpu;
    let load = || scene::load(model.to_str().expect("utf-8 path")).expect("model loads");
    let running = SceneGpu::new(&gpu.device, &gpu.queue, &mut load()).expect("upload");
    let reload = |keep: bool| {
        common::ms(|| {
            let mut s = load();
            s.materials[0].base_color[0] *= 0.5;
            let previous = keep.then_some(&running);
            let up = SceneGpu::reusing(&gpu.device, &gpu.queue, &mut s, previous).expect("upload");
            gpu.device.poll(wgpu::PollType::wait_indefinitely()).expect("the GPU");
            assert_eq!(up.kept.textures.0, if keep { up.kept.textures.1 } else { 0 });
        })
    };
    let paired = common::interleaved(rounds.max(2), || reload(true), || reload(false));
    println!("scene reload after a material edit (load from the texture cache, then upload):");
    println!("{}", paired.report(("keeping what is resident", "uploading everything"), "ms"));
}

/// Load ms of the model with an empty texture cache (every image decoded, in parallel, and
/// kept) against with the cache that load filled, in interleaved rounds; the texture time is
/// the load's beyond the same model without textures (`bare.gltf`), timed in each round too,
/// as is the load decoding without a cache (what it cost before there was one).
fn decoded_once(model: &Path, dir: &Path, (format, rounds): (&str, usize)) {
    use scene::gltf_load::load_with;
    use scene::texture_cache::TextureCache;
    let root = dir.join("texture-cache");
    let cache = TextureCache::at(Some(&root));
    let time = |model: &Path, c: &TextureCache| {
        let t = Instant::now();
        load_with(model, c).expect("model loads");
        t.elapsed().as_secs_f64() * 1e3
    };
    let (mut cold, mut warm, mut bare, mut uncached, mut ratios) = (vec![], vec![], vec![], vec![], vec![]);
    for round in 0..rounds {
        let b = time(&dir.join("bare.gltf"), &TextureCache::at(None));
        uncached.push(time(model, &TextureCache::at(None)));
        // Odd rounds time the cached load first, on the cache the round before filled.
        let (c, w) = if round % 2 == 0 {
            let _ = std::fs::remove_dir_all(&root);
            let c = time(model, &cache);
            (c, time(model, &cache))
        } else {
            let w = time(model, &cache);
            let _ = std::fs::remove_dir_all(&root);
            (time(model, &cache), w)
        };
        cold.push(c);
        warm.push(w);
        bare.push(b);
        ratios.push((w - b).max(0.0) / (c - b));
    }
    let q = |v: &mut Vec<f64>, f: f64| {
        v.sort_by(f64::total_cmp);
        v[((v.len() - 1) as f64 * f).round() as usize]
    };
    println!(
        "textures decoded once ({format}): load {:.1} ms decoding and keeping (empty cache), {:.1} ms cached, {:.1} ms decoding without a cache, {:.1} ms without textures; texture time cached / decoding and keeping {:.3} [{:.3}, {:.3}] (median [quartiles] of {rounds} rounds; goal ≤ 0.10)",
        q(&mut cold, 0.5),
        q(&mut warm, 0.5),
        q(&mut uncached, 0.5),
        q(&mut bare, 0.5),
        q(&mut ratios, 0.5),
        q(&mut ratios, 0.25),
        q(&mut ratios, 0.75)
    );
    let _ = std::fs::remove_dir_all(&root);
}
