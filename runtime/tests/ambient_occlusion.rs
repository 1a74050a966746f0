//! Ambient occlusion in `pipelines/deferred_gi.ron` (variant `ao`), driven as a user runs it,
//! asserting on the occlusion buffers.

mod gpu_common;

use gpu_common::*;
use lightbench::io::Image;
use lightbench_compiler::ir::ParamValue;

fn cornell_ao() -> lightbench::scene::Scene {
    let d = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("lightbench-ao-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(
        d.join("ao.ron"),
        "Scene(name: \"ao\", size: (64, 64), builtin: \"cornell\", effects: [AmbientOcclusion])\n",
    )
    .unwrap();
    lightbench::scene::load(d.join("ao.ron").to_str().unwrap()).unwrap()
}

/// World positions of the pixels (None: background), from the depth buffer and the camera.
fn world_positions(ex: &lightbench::gpu::Executor, depth: &Image) -> Vec<Option<glam::Vec3>> {
    let cam = &ex.scene().camera;
    let inv = (cam.proj(depth.width as f32 / depth.height as f32) * cam.view()).inverse();
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

/// Occlusion values of the pixels whose world position satisfies `pick`.
fn values(ao: &Image, world: &[Option<glam::Vec3>], pick: impl Fn(glam::Vec3) -> bool) -> Vec<f32> {
    world
        .iter()
        .enumerate()
        .filter(|(_, w)| w.is_some_and(&pick))
        .map(|(i, _)| ao.rgba[4 * i])
        .collect()
}

fn mean(v: &[f32]) -> f32 {
    v.iter().sum::<f32>() / v.len().max(1) as f32
}

fn variance(v: &[f32]) -> f32 {
    let m = mean(v);
    v.iter().map(|x| (x - m) * (x - m)).sum::<f32>() / v.len().max(1) as f32
}

/// The floor along the red wall and around the boxes' feet is more occluded than the open
/// floor in front; a darker ambient term follows.
#[test]
fn ssao_darkens_corners_and_contacts_more_than_the_open_floor() {
    let g = gpu();
    let scene = cornell_ao();
    let ex = render_with(&g, &root().join("pipelines/deferred_gi.ron"), &scene, &[], 1);
    let ao = ex.read_texture(&g, "ao.blurred", 0, 0).unwrap();
    let world = world_positions(&ex, &ex.read_texture(&g, "gbuf.depth", 0, 0).unwrap());
    let floor = |p: glam::Vec3| p.y.abs() < 0.01;
    let corner = values(&ao, &world, |p| floor(p) && p.x < -0.93);
    let open = values(&ao, &world, |p| floor(p) && p.x.abs() < 0.25 && p.z > 0.75);
    assert!(
        corner.len() > 5 && open.len() > 5,
        "{} corner, {} open pixels",
        corner.len(),
        open.len()
    );
    assert!(
        mean(&corner) < mean(&open) - 0.05,
        "corner {} vs open floor {}",
        mean(&corner),
        mean(&open)
    );
    assert!(ao.rgba.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)));
}

/// More kernel samples give less noise: on a strip of floor at a constant distance from the
/// red wall (constant occlusion in expectation), the unblurred variance falls from 8 to 64.
#[test]
fn more_samples_mean_less_noise() {
    let g = gpu();
    let scene = cornell_ao();
    let p = root().join("pipelines/deferred_gi.ron");
    let (exe, _) = lightbench::render::compile(&g, &p, None, &scene, &[]).unwrap();
    let mut var = vec![];
    for samples in [8, 64] {
        let params = [("ao.samples".to_string(), ParamValue::Int(samples))];
        let ex = lightbench::render::render_with(&g, &exe, &scene, 1, &params).unwrap();
        let raw = ex.read_texture(&g, "ao.raw", 0, 0).unwrap();
        let world = world_positions(&ex, &ex.read_texture(&g, "gbuf.depth", 0, 0).unwrap());
        let strip = values(&raw, &world, |q| q.y.abs() < 0.01 && q.x > -0.9 && q.x < -0.8 && q.z > 0.0);
        assert!(strip.len() > 5, "{} strip pixels", strip.len());
        var.push(variance(&strip));
    }
    eprintln!("variance on the strip with 8 and 64 samples: {var:?}");
    assert!(var[1] < var[0], "{var:?}");
}

/// At depth edges (a neighbour more than 10% farther or nearer), the cross-bilateral blur
/// keeps each side's occlusion: it changes the raw occlusion there less than the box blur,
/// which mixes the two sides.
#[test]
fn the_bilateral_blur_leaks_less_across_depth_edges() {
    let g = gpu();
    let scene = cornell_ao();
    let p = root().join("pipelines/deferred_gi.ron");
    let mut leak = vec![];
    for blur in ["box", "bilateral"] {
        let ex = render_with(&g, &p, &scene, &[("ao_blur", blur)], 1);
        let raw = ex.read_texture(&g, "ao.raw", 0, 0).unwrap();
        let blurred = ex.read_texture(&g, "ao.blurred", 0, 0).unwrap();
        let world = world_positions(&ex, &ex.read_texture(&g, "gbuf.depth", 0, 0).unwrap());
        let cam = ex.scene().camera.position;
        let dist = |i: usize| world[i].map(|w| (w - cam).length());
        let (w, h) = (raw.width as usize, raw.height as usize);
        let mut diffs = vec![];
        for y in 1..h - 1 {
            for x in 1..w - 1 {
                let i = y * w + x;
                let Some(d) = dist(i) else { continue };
                let edge = [i - 1, i + 1, i - w, i + w]
                    .iter()
                    .any(|&j| dist(j).is_some_and(|e| (e - d).abs() > 0.1 * d));
                if edge {
                    diffs.push((blurred.rgba[4 * i] - raw.rgba[4 * i]).abs());
                }
            }
        }
        assert!(diffs.len() > 20, "{} edge pixels", diffs.len());
        leak.push(mean(&diffs));
    }
    eprintln!("mean |blurred - raw| at depth edges, box vs bilateral: {leak:?}");
    assert!(leak[1] < leak[0], "{leak:?}");
}
