//! Anti-aliasing of the bundled pipelines (`aa` variant), judged as issue 29 asks: against a
//! 16× supersampled render of the same frame (4×4 samples per pixel, averaged in linear
//! light), FXAA and TAA lower the error at the edges and leave flat regions unchanged; TAA
//! converges on a still camera and leaves no ghost trails on an orbiting one.

use crate::gpu_common;

use gpu_common::*;
use lightbench::io::{srgb_to_linear, Image};
use lightbench::scene::{builtin, Scene};

fn linear(img: &Image, x: u32, y: u32) -> [f64; 3] {
    let p = img.pixel(x, y);
    [0, 1, 2].map(|c| srgb_to_linear(p[c]) as f64)
}

/// FXAA's own luma (lib of `fxaa.wgsl`): perceptual, of the linear colour.
fn luma(img: &Image, x: i64, y: i64) -> f64 {
    let (x, y) = (x.clamp(0, img.width as i64 - 1) as u32, y.clamp(0, img.height as i64 - 1) as u32);
    let [r, g, b] = linear(img, x, y);
    (0.299 * r + 0.587 * g + 0.114 * b).sqrt()
}

#[test]
fn fxaa_lowers_the_edge_error_and_leaves_flat_regions_alone() {
    let n = 64u32;
    let mut scene = builtin::cornell();
    scene.size = (n, n);
    let reference = supersampled(&scene);
    let (plain, fxaa) = (frames(&scene, "none", &[1]).remove(0), frames(&scene, "fxaa", &[1]).remove(0));
    let (edges, rmse) = edge_rmse(&plain, &[&fxaa], &reference);
    // Flat: the 3×3 luma contrast well under FXAA's thresholds (defaults 0.125, 0.0312).
    let mut flat = 0;
    for (x, y) in (0..n * n).map(|i| (i % n, i / n)) {
        let ls: Vec<f64> = [(0, 0), (0, -1), (0, 1), (1, 0), (-1, 0)]
            .iter()
            .map(|(dx, dy)| luma(&plain, x as i64 + dx, y as i64 + dy))
            .collect();
        let (lo, hi) = ls.iter().fold((f64::MAX, 0.0f64), |(a, b), &l| (a.min(l), b.max(l)));
        if hi - lo < 0.8 * (0.0312f64).max(hi * 0.125) {
            assert_eq!(plain.pixel(x, y), fxaa.pixel(x, y), "flat pixel ({x}, {y}) changed");
            flat += 1;
        }
    }
    eprintln!(
        "{edges} edge pixels: RMSE vs 16× supersampling {:.4} without AA, {:.4} with FXAA; {flat} flat pixels unchanged",
        rmse[0], rmse[1]
    );
    assert!(edges > 50 && flat > 1000, "{edges} edges, {flat} flat");
    assert!(rmse[1] < 0.85 * rmse[0], "FXAA {} vs none {}", rmse[1], rmse[0]);
}

/// The 16× supersampled reference of `scene` (at its own size): each pixel the mean of its
/// 4×4 pixels of a render at 4× the size without anti-aliasing, in linear light.
fn supersampled(scene: &Scene) -> Vec<[f64; 3]> {
    let (w, h) = scene.size;
    let mut big = scene.clone();
    big.size = (4 * w, 4 * h);
    let fine = {
        let g = gpu();
        output(&g, &render_with(&g, &deferred(), &big, &[("aa", "none")], 1))
    };
    let mut out = vec![[0.0; 3]; (w * h) as usize];
    for (i, px) in out.iter_mut().enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        for (dx, dy) in (0..16).map(|i| (i % 4, i / 4)) {
            let c = linear(&fine, 4 * x + dx, 4 * y + dy);
            (0..3).for_each(|k| px[k] += c[k] / 16.0);
        }
    }
    out
}

/// Mean squared error (over the three channels, linear light) of pixel `i` against the reference.
fn squared_error(img: &Image, reference: &[[f64; 3]], i: usize) -> f64 {
    let c = linear(img, i as u32 % img.width, i as u32 / img.width);
    (0..3).map(|k| (c[k] - reference[i][k]).powi(2)).sum::<f64>() / 3.0
}

/// The outputs of `scene` with `aa` after each frame in `at` (frame counts, increasing).
fn frames(scene: &Scene, aa: &str, at: &[u32]) -> Vec<Image> {
    let g = gpu();
    let v = [("aa".to_string(), aa.to_string())];
    let (exe, _) = lightbench::render::compile(&g, &deferred(), None, scene, &v).unwrap_or_else(|e| panic!("{e}"));
    let mut ex = lightbench::gpu::Executor::new(&g, &exe, scene).unwrap();
    let mut out = vec![];
    for f in 0..*at.last().unwrap() {
        ex.render_frame(&g, &ex.inputs(f as f32 / 60.0)).unwrap();
        if at.contains(&(f + 1)) {
            out.push(output(&g, &ex));
        }
    }
    out
}

/// Pixels whose 3×3 neighbourhood in the reference is flat: no channel differs from the
/// centre's by more than `tolerance` (linear light), so no edge passes within a pixel.
fn flat(reference: &[[f64; 3]], size: u32, tolerance: f64) -> Vec<usize> {
    let n = size as i64;
    (0..reference.len())
        .filter(|&i| {
            let (x, y) = (i as i64 % n, i as i64 / n);
            (0..9).all(|k| {
                let (qx, qy) = ((x + k % 3 - 1).clamp(0, n - 1), (y + k / 3 - 1).clamp(0, n - 1));
                let q = &reference[(qy * n + qx) as usize];
                (0..3).all(|c| (q[c] - reference[i][c]).abs() <= tolerance)
            })
        })
        .collect()
}

/// Edge pixels (where one sample per pixel misses the area average by more than 0.05) and
/// the RMSE of each image over them.
fn edge_rmse(plain: &Image, others: &[&Image], reference: &[[f64; 3]]) -> (usize, Vec<f64>) {
    let edges: Vec<usize> = (0..reference.len())
        .filter(|&i| squared_error(plain, reference, i).sqrt() > 0.05)
        .collect();
    let rmse = |img: &Image| (edges.iter().map(|&i| squared_error(img, reference, i)).sum::<f64>() / edges.len() as f64).sqrt();
    (
        edges.len(),
        std::iter::once(plain).chain(others.iter().copied()).map(rmse).collect(),
    )
}

#[test]
fn taa_converges_to_the_supersampled_image_on_a_still_camera() {
    let mut scene = builtin::cornell();
    scene.size = (64, 64);
    let reference = supersampled(&scene);
    let plain = frames(&scene, "none", &[1]).remove(0);
    let taa = frames(&scene, "taa", &[1, 4, 16, 32, 48]);
    let (edges, rmse) = edge_rmse(&plain, &taa.iter().collect::<Vec<_>>(), &reference);
    eprintln!(
        "{edges} edge pixels: RMSE vs 16× supersampling without AA {:.4}; TAA after 1, 4, 16, 32, 48 frames {:.4?}",
        rmse[0],
        &rmse[1..]
    );
    assert!(edges > 50, "{edges} edges");
    // The first frame has no history: it is the jittered frame alone.
    assert!((rmse[1] - rmse[0]).abs() < 0.5 * rmse[0], "frame 1: {} vs {}", rmse[1], rmse[0]);
    assert!(rmse[4] < 0.38 * rmse[0], "TAA after 32 frames {} vs none {}", rmse[4], rmse[0]);
    // Converged: 16 more frames change the error by little.
    assert!(
        (rmse[5] - rmse[4]).abs() < 0.1 * rmse[4],
        "32 frames {}, 48 frames {}",
        rmse[4],
        rmse[5]
    );
    // Flat regions: the jittered samples of a smooth gradient average to the pixel centre's value.
    let flat = flat(&reference, 64, 0.01);
    let flat_max = flat
        .iter()
        .map(|&i| {
            let (a, b) = (
                plain.pixel(i as u32 % 64, i as u32 / 64),
                taa[4].pixel(i as u32 % 64, i as u32 / 64),
            );
            (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0f32, f32::max)
        })
        .fold(0.0f32, f32::max);
    eprintln!("{} flat pixels: largest change by TAA {flat_max:.4} (stored sRGB)", flat.len());
    assert!(flat.len() > 800, "{} flat pixels", flat.len());
    // At most two steps of the 8-bit image TAA reads.
    assert!(flat_max <= 2.5 / 255.0, "a flat pixel changed by {flat_max}");
}

#[test]
fn taa_leaves_no_ghost_on_an_orbiting_camera() {
    use lightbench_compiler::scene::CameraAnimationDesc;
    let frames_run = 32;
    let mut scene = builtin::cornell();
    scene.size = (64, 64);
    scene.camera.animation = Some(CameraAnimationDesc::Orbit {
        center: [0.0, 1.0, 0.0],
        speed: 30.0,
    });
    let plain = frames(&scene, "none", &[frames_run]).remove(0);
    let taa = frames(&scene, "taa", &[frames_run]).remove(0);
    // The reference: the last frame's camera, still.
    let mut still = scene.clone();
    still.camera = scene.camera.at((frames_run - 1) as f32 / 60.0);
    let reference = supersampled(&still);
    let (edges, rmse) = edge_rmse(&plain, &[&taa], &reference);
    // A ghost: a pixel in a flat region of this frame (no edge within a pixel) that TAA gets
    // visibly wrong, because it kept what an earlier frame saw there.
    let ghosts = flat(&reference, 64, 0.01)
        .into_iter()
        .filter(|&i| squared_error(&taa, &reference, i).sqrt() > 0.05)
        .count();
    eprintln!(
        "orbit at 0.5°/frame, frame {frames_run}: {edges} edge pixels, RMSE without AA {:.4}, TAA {:.4}; {ghosts} ghost pixels",
        rmse[0], rmse[1]
    );
    assert!(rmse[1] < 0.8 * rmse[0], "TAA {} vs none {} on edges", rmse[1], rmse[0]);
    assert!(ghosts <= reference.len() / 200, "{ghosts} ghost pixels");
}
