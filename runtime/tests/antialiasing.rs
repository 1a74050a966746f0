//! Anti-aliasing of the bundled pipelines (`aa` variant), judged as issue 29 asks: against a
//! 16× supersampled render of the same frame (4×4 samples per pixel, averaged in linear
//! light), FXAA lowers the error at the edges, and leaves flat regions exactly unchanged.

mod gpu_common;

use gpu_common::*;
use lightbench::io::{srgb_to_linear, Image};
use lightbench::scene::builtin;

/// The displayed image (sRGB-encoded, as stored) of the Cornell box at `size`.
fn render(size: u32, aa: &str) -> Image {
    let g = gpu();
    let mut scene = builtin::cornell();
    scene.size = (size, size);
    let ex = render_with(&g, &deferred(), &scene, &[("aa", aa)], 1);
    output(&g, &ex)
}

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
    let (plain, fxaa, fine) = (render(n, "none"), render(n, "fxaa"), render(4 * n, "none"));
    // The supersampled reference: each pixel the mean of its 4×4 fine pixels, in linear light.
    let reference = |x: u32, y: u32| {
        let mut sum = [0.0; 3];
        for (dx, dy) in (0..16).map(|i| (i % 4, i / 4)) {
            let c = linear(&fine, 4 * x + dx, 4 * y + dy);
            (0..3).for_each(|k| sum[k] += c[k] / 16.0);
        }
        sum
    };
    let (mut err_plain, mut err_fxaa, mut edges, mut flat) = (0.0, 0.0, 0, 0);
    for y in 0..n {
        for x in 0..n {
            let r = reference(x, y);
            let d = |img: &Image| (0..3).map(|k| (linear(img, x, y)[k] - r[k]).powi(2)).sum::<f64>() / 3.0;
            let (e_plain, e_fxaa) = (d(&plain), d(&fxaa));
            // Edge pixels: where one sample per pixel misses the area average visibly.
            if e_plain.sqrt() > 0.05 {
                err_plain += e_plain;
                err_fxaa += e_fxaa;
                edges += 1;
            }
            // Flat: the 3×3 luma contrast well under FXAA's thresholds (defaults 0.125, 0.0312).
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
    }
    let (rmse_plain, rmse_fxaa) = ((err_plain / edges as f64).sqrt(), (err_fxaa / edges as f64).sqrt());
    eprintln!(
        "{edges} edge pixels: RMSE vs 16× supersampling {rmse_plain:.4} without AA, {rmse_fxaa:.4} with FXAA; {flat} flat pixels unchanged"
    );
    assert!(edges > 50 && flat > 1000, "{edges} edges, {flat} flat");
    assert!(rmse_fxaa < 0.85 * rmse_plain, "FXAA {rmse_fxaa} vs none {rmse_plain}");
}
