//! Stage `metrics` of `diff`: how far apart two images of one resource are — RMSE, largest
//! difference, PSNR, region by region the ratios of B's 8×8-block means to A's (as `sweep`
//! measures an estimate against the reference), and for 8-bit colour images mean FLIP
//! (`nv-flip`, NVIDIA's perceptual metric) and SSIM (`image-compare`, mean over 8×8 windows) —
//! and a per-pixel error map.

use super::images::display_rgb8;
use crate::io::Image;
use serde::Serialize;

#[derive(Clone, Debug, Serialize)]
pub struct Metrics {
    /// Over the first `channels` channels, in the stored encoding.
    pub rmse: f64,
    pub max_abs: f64,
    /// Against the larger of 1 and A's largest magnitude; `None` when the images are equal.
    pub psnr_db: Option<f64>,
    pub flip_mean: Option<f64>,
    pub ssim: Option<f64>,
    /// B's 8×8-block means over A's (channels up to three summed), over the blocks A lights
    /// (at least 1% of its mean): where a change moves light between regions that the RMSE
    /// alone would not place. `None` where no block qualifies.
    pub blocks: Option<crate::regions::BlockRatios>,
}

pub struct Compared {
    pub metrics: Metrics,
    /// Per pixel, 0..1: FLIP's error for colour images, else the largest channel difference
    /// over the image's largest (all 0 when equal).
    pub error_map: Vec<f32>,
}

/// Mean FLIP of two colour images (as displayed: 8-bit sRGB) and its error map.
pub fn flip(a: &Image, b: &Image) -> (f64, Vec<f32>) {
    let (ra, rb) = (display_rgb8(a, 3, None), display_rgb8(b, 3, None));
    flip_rgb8((&ra, &rb), (a.width, a.height))
}

/// `flip` of images already as displayed.
fn flip_rgb8((ra, rb): (&[u8], &[u8]), (w, h): (u32, u32)) -> (f64, Vec<f32>) {
    let fa = nv_flip::FlipImageRgb8::with_data(w, h, ra);
    let fb = nv_flip::FlipImageRgb8::with_data(w, h, rb);
    let map = nv_flip::flip(fa, fb, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    (nv_flip::FlipPool::from_image(&map).mean() as f64, map.to_vec())
}

/// Mean FLIP and its error map; SSIM (both on 8-bit sRGB).
fn perceptual(a: &Image, b: &Image) -> (f64, Vec<f32>, Option<f64>) {
    // FLIP and SSIM take display images: 8-bit sRGB.
    let (ra, rb) = (display_rgb8(a, 3, None), display_rgb8(b, 3, None));
    let (mean, map) = flip_rgb8((&ra, &rb), (a.width, a.height));
    let ssim = match (
        image::RgbImage::from_raw(a.width, a.height, ra),
        image::RgbImage::from_raw(b.width, b.height, rb),
    ) {
        // SSIM's windows need the image to hold one.
        (Some(x), Some(y)) if a.width >= 8 && a.height >= 8 => {
            image_compare::rgb_similarity_structure(&image_compare::Algorithm::MSSIMSimple, &x, &y)
                .ok()
                .map(|s| s.score)
        }
        _ => None,
    };
    (mean, map, ssim)
}

/// Whether two images hold the same bits (a NaN equals the same NaN).
pub fn same_bits(a: &Image, b: &Image) -> bool {
    std::ptr::eq(a, b) || (a.rgba.len() == b.rgba.len() && a.rgba.iter().zip(&b.rgba).all(|(x, y)| x.to_bits() == y.to_bits()))
}

/// What two equal images measure: nothing apart anywhere; FLIP 0 and SSIM 1 for colour by
/// their definitions (SSIM where the image holds one of its 8×8 windows).
fn equal(a: &Image, n: usize, colour: bool) -> Compared {
    let against = crate::regions::Against { mean: a, variance: None };
    Compared {
        metrics: Metrics {
            rmse: 0.0,
            max_abs: 0.0,
            psnr_db: None,
            flip_mean: colour.then_some(0.0),
            ssim: (colour && a.width >= 8 && a.height >= 8).then_some(1.0),
            blocks: crate::regions::block_ratios(&a.rgba, against, n.min(3)),
        },
        error_map: vec![0.0; (a.width * a.height) as usize],
    }
}

/// Compare B against A (same size). `channels`: how many channels the format has;
/// `colour`: an image meant for display (an sRGB format), which gets FLIP and SSIM — both
/// measure what a viewer sees, which data such as normals or albedo are not.
pub fn compare(a: &Image, b: &Image, channels: usize, colour: bool) -> Compared {
    let n = channels.clamp(1, 4);
    if same_bits(a, b) {
        return equal(a, n, colour);
    }
    let (mut sum, mut max_abs, mut peak) = (0.0f64, 0.0f64, 1.0f64);
    let mut diff_map = Vec::with_capacity((a.width * a.height) as usize);
    for (pa, pb) in a.rgba.chunks(4).zip(b.rgba.chunks(4)) {
        let mut px = 0.0f64;
        for c in 0..n {
            let d = (pa[c] as f64 - pb[c] as f64).abs();
            // NaN compares as the largest difference there is.
            let d = if d.is_nan() { f64::INFINITY } else { d };
            sum += d * d;
            px = px.max(d);
            peak = peak.max((pa[c] as f64).abs());
        }
        max_abs = max_abs.max(px);
        diff_map.push(px);
    }
    let rmse = (sum / (diff_map.len() * n).max(1) as f64).sqrt();
    let psnr_db = (rmse > 0.0).then(|| 20.0 * (peak / rmse).log10());
    let (flip_mean, error_map, ssim) = if colour {
        let (m, map, s) = perceptual(a, b);
        (Some(m), map, s)
    } else {
        let scale = if max_abs > 0.0 && max_abs.is_finite() { max_abs } else { 1.0 };
        (None, diff_map.iter().map(|d| (d / scale).min(1.0) as f32).collect(), None)
    };
    let against = crate::regions::Against { mean: a, variance: None };
    let blocks = crate::regions::block_ratios(&b.rgba, against, n.min(3));
    Compared {
        metrics: Metrics {
            rmse,
            max_abs,
            psnr_db,
            flip_mean,
            ssim,
            blocks,
        },
        error_map,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> [f32; 4]) -> Image {
        let mut rgba = vec![];
        for y in 0..h {
            for x in 0..w {
                rgba.extend(f(x, y));
            }
        }
        Image {
            width: w,
            height: h,
            rgba,
            srgb: true,
        }
    }

    #[test]
    fn equal_images_measure_zero_and_a_change_shows_where_it_is() {
        let a = image(32, 32, |x, y| [x as f32 / 32.0, y as f32 / 32.0, 0.5, 1.0]);
        let same = compare(&a, &a.clone(), 4, true);
        assert_eq!((same.metrics.rmse, same.metrics.max_abs, same.metrics.psnr_db), (0.0, 0.0, None));
        assert_eq!(same.metrics.flip_mean, Some(0.0));
        assert_eq!(same.metrics.ssim, Some(1.0));
        assert!(same.error_map.iter().all(|e| *e == 0.0));
        // What equal images are said to measure is what FLIP and SSIM measure on them.
        let (flip, map, ssim) = perceptual(&a, &a.clone());
        assert_eq!(flip, 0.0);
        assert!(map.iter().all(|e| *e == 0.0));
        assert!((ssim.unwrap() - 1.0).abs() < 1e-9, "{ssim:?}");
        // A bright square in the top-left corner.
        let b = image(32, 32, |x, y| if x < 8 && y < 8 { [1.0, 1.0, 1.0, 1.0] } else { a.pixel(x, y) });
        let d = compare(&a, &b, 4, true);
        assert!(d.metrics.flip_mean.unwrap() > 0.01 && d.metrics.rmse > 0.05 && d.metrics.max_abs > 0.5);
        assert!(d.error_map[0] > 0.5 && d.error_map[31 * 32 + 31] < 0.05, "hot where it changed");
        let f = compare(&a, &b, 1, false);
        assert_eq!(f.metrics.flip_mean, None);
        assert_eq!(f.error_map[0], 1.0);
        assert!(f.metrics.psnr_db.unwrap() > 0.0);
    }

    /// B/A block ratios say where light moved: B moves half of A's light from the right half
    /// to the left (the mean unchanged) — left blocks 1.5, right 0.5.
    #[test]
    fn block_ratios_show_where_light_moved() {
        let a = image(16, 16, |_, _| [0.4, 0.4, 0.4, 1.0]);
        let b = image(16, 16, |x, _| if x < 8 { [0.6, 0.6, 0.6, 1.0] } else { [0.2, 0.2, 0.2, 1.0] });
        let blocks = compare(&a, &b, 4, false).metrics.blocks.unwrap();
        assert!((blocks.min - 0.5).abs() < 1e-6 && (blocks.max - 1.5).abs() < 1e-6, "{blocks:?}");
        assert_eq!(blocks.blocks, 4);
        let same = compare(&a, &a.clone(), 4, false).metrics.blocks.unwrap();
        assert_eq!((same.p10, same.p90), (1.0, 1.0));
    }
}
