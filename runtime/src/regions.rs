//! Regional comparison, shared by `sweep`'s measure and `diff`'s metrics: the ratios of one
//! image's 8×8-block means to another's (a reference, with its noise where it has any), over
//! the blocks the reference lights and knows — what a right mean can hide.

use crate::io::Image;
use crate::reference::TermImage;
use serde::{Deserialize, Serialize};

/// The ratios of 8×8-block means, estimate over reference (channels summed), over the blocks
/// the reference lights (a mean of at least 1% of its image's) and knows (a standard error of
/// at most 5% of that mean, so that its noise does not make the ratio): their 10th and 90th
/// percentiles, extremes and count. A mean right overall can hide a band of the image at 0.1×
/// and another at 2×; these do not.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BlockRatios {
    pub p10: f64,
    pub p90: f64,
    pub min: f64,
    pub max: f64,
    pub blocks: usize,
}

/// Side of the blocks `BlockRatios` compares.
pub const BLOCK: usize = 8;

/// Sums over the pixels of one region (a block, a surface), channels summed.
#[derive(Clone, Copy, Default)]
pub struct Region {
    pub estimate: f64,
    pub reference: f64,
    /// Of the reference's per-pixel variances: the variance of its sum.
    pub variance: f64,
    pub non_finite: bool,
    pub pixels: usize,
}

/// What estimates are measured against: an image, with its per-pixel noise where it has any
/// (a reference's variance of the mean; none for a rendered image, as `diff`'s side A).
#[derive(Clone, Copy)]
pub struct Against<'a> {
    pub mean: &'a Image,
    pub variance: Option<&'a Image>,
}

impl<'a> From<&'a TermImage> for Against<'a> {
    fn from(t: &'a TermImage) -> Self {
        Against {
            mean: &t.mean,
            variance: Some(&t.variance),
        }
    }
}

impl Region {
    pub fn add(&mut self, estimate: &[f32], reference: Against, n: usize, p: usize) {
        self.pixels += 1;
        for c in 0..n {
            let e = estimate[p * 4 + c];
            self.non_finite |= !e.is_finite();
            self.estimate += e as f64;
            self.reference += reference.mean.rgba[p * 4 + c] as f64;
            self.variance += reference.variance.map_or(0.0, |v| v.rgba[p * 4 + c] as f64);
        }
    }

    /// Whether the region is judged: its estimate finite, its reference lit (at least 1% of
    /// the image's mean pixel, `mean_pixel`, per pixel) and known (a standard error of at most
    /// 5% of its sum, so that the reference's noise does not make the ratio).
    pub fn judged(&self, mean_pixel: f64) -> bool {
        !self.non_finite
            && self.reference > 0.0
            && self.reference > 0.01 * mean_pixel * self.pixels as f64
            && self.variance.sqrt() <= 0.05 * self.reference
    }

    pub fn ratio(&self) -> f64 {
        self.estimate / self.reference
    }
}

/// The reference's mean pixel, channels summed.
pub fn mean_pixel(reference: &Image, n: usize) -> f64 {
    let sum: f64 = reference
        .rgba
        .chunks_exact(4)
        .map(|p| p[..n].iter().map(|&v| v as f64).sum::<f64>())
        .sum();
    sum / (reference.rgba.len() / 4).max(1) as f64
}

/// The block ratios of `estimate` (linear RGBA, the reference's size) against `reference`,
/// over its first `n` channels.
pub fn block_ratios(estimate: &[f32], reference: Against, n: usize) -> Option<BlockRatios> {
    let (w, h) = (reference.mean.width as usize, reference.mean.height as usize);
    let (bw, bh) = (w.div_ceil(BLOCK), h.div_ceil(BLOCK));
    let mut blocks = vec![Region::default(); bw * bh];
    for p in 0..w * h {
        blocks[(p / w / BLOCK) * bw + (p % w) / BLOCK].add(estimate, reference, n, p);
    }
    let mean = mean_pixel(reference.mean, n);
    let mut ratios: Vec<f64> = blocks.iter().filter(|b| b.judged(mean)).map(Region::ratio).collect();
    if ratios.is_empty() {
        return None;
    }
    ratios.sort_by(f64::total_cmp);
    let pick = |q: f64| crate::reference::percentile_of(&ratios, q);
    Some(BlockRatios {
        p10: pick(10.0),
        p90: pick(90.0),
        min: ratios[0],
        max: ratios[ratios.len() - 1],
        blocks: ratios.len(),
    })
}
