//! Stage `measure` of `sweep`: how far a raster estimate is from the reference term — RMSE
//! corrected for the reference's own noise, bias, for colour terms mean FLIP, and region by
//! region the ratios of 8×8-block means and of each labelled surface's mean — over the pixels
//! both images have.

use crate::error::{Error, Result};
use crate::io::Image;
use crate::reference::{Term, TermImage};
use crate::regions::{block_ratios, BlockRatios};
use crate::regions::{mean_pixel, Region};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorMetrics {
    /// √max(0, MSE − mean reference variance): the error the estimate would have against a
    /// noise-free reference (the reference's noise adds its variance to the expected MSE).
    /// NaN (`null` in rows) when no value of the estimate was finite.
    #[serde(deserialize_with = "nan_if_null")]
    pub rmse: f64,
    /// √MSE against the reference as it is.
    #[serde(deserialize_with = "nan_if_null")]
    pub rmse_raw: f64,
    /// Mean of (estimate − reference): negative where the effect darkens too much.
    #[serde(deserialize_with = "nan_if_null")]
    pub bias: f64,
    /// Mean FLIP of both images mapped by L/(1+L) to 8-bit sRGB (colour terms only).
    pub flip: Option<f64>,
    /// Estimate values that are NaN or infinite (left out of the means above).
    pub non_finite: usize,
    /// Region by region: the ratios of the estimate's 8×8-block means to the reference's
    /// (none where no block qualifies; rows written before had none).
    #[serde(default)]
    pub blocks: Option<BlockRatios>,
    /// Surface by surface (the scene's mesh names): the ratio of the estimate's mean over the
    /// pixels showing it to the reference's, for the surfaces judged as blocks are (at least
    /// `MIN_SURFACE_PIXELS`, lit, known); lowest ratio first. Empty where none qualifies.
    #[serde(default)]
    pub surfaces: Vec<SurfaceRatio>,
}

/// One labelled surface's ratio of means, estimate over reference, and the pixels it covers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SurfaceRatio {
    pub name: String,
    pub ratio: f64,
    pub pixels: usize,
}

impl ErrorMetrics {
    /// The surfaces with the lowest and the highest ratio.
    pub fn surface_extremes(&self) -> Option<(&SurfaceRatio, &SurfaceRatio)> {
        Some((self.surfaces.first()?, self.surfaces.last()?))
    }
}

/// Which surface each pixel shows (row by row; `None`: the background) and the surfaces'
/// names: meshes of one name are one surface.
pub struct Surfaces {
    pub seen: Vec<Option<usize>>,
    pub names: Vec<String>,
}

/// Fewest pixels a surface must cover to be judged (a 4×4 patch): fewer say more about the
/// raster's and the reference's edges than about the effect.
pub const MIN_SURFACE_PIXELS: usize = 16;

/// The ratio of each labelled surface's mean to the reference's (channels summed), lowest
/// first.
fn surface_ratios(estimate: &[f32], reference: &TermImage, n: usize, labels: &Surfaces) -> Vec<SurfaceRatio> {
    let mut names: Vec<&String> = labels.names.iter().collect();
    names.sort();
    names.dedup();
    let mut surfaces = vec![Region::default(); names.len()];
    for (p, seen) in labels.seen.iter().enumerate().take(estimate.len() / 4) {
        if let Some(i) = seen
            .and_then(|m| labels.names.get(m))
            .and_then(|name| names.binary_search(&name).ok())
        {
            surfaces[i].add(estimate, reference.into(), n, p);
        }
    }
    let mean = mean_pixel(&reference.mean, n);
    let mut ratios: Vec<SurfaceRatio> = names
        .iter()
        .zip(&surfaces)
        .filter(|(_, s)| s.pixels >= MIN_SURFACE_PIXELS && s.judged(mean))
        .map(|(name, s)| SurfaceRatio {
            name: name.to_string(),
            ratio: s.ratio(),
            pixels: s.pixels,
        })
        .collect();
    ratios.sort_by(|a, b| a.ratio.total_cmp(&b.ratio));
    ratios
}

/// JSON has no NaN: serde_json writes it as `null`, read back here as NaN.
fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Channels a term has: AO is one (red), the others are colour.
pub fn channels(term: Term) -> usize {
    if term == Term::Ao {
        1
    } else {
        3
    }
}

/// The error of `estimate` against the reference term; per surface where `labels` says which
/// surface each pixel shows.
pub fn error(estimate: &Image, reference: &TermImage, resource: &str, labels: Option<&Surfaces>) -> Result<ErrorMetrics> {
    let r = &reference.mean;
    if (estimate.width, estimate.height) != (r.width, r.height) {
        return Err(Error::Input(format!(
            "`{resource}` is {}x{} but the reference is {}x{}: compare a resource the size of the viewport",
            estimate.width, estimate.height, r.width, r.height
        )));
    }
    let n = channels(reference.term);
    let est = estimate.linear();
    let (mut se, mut var, mut diff, mut count, mut non_finite) = (0.0f64, 0.0f64, 0.0f64, 0usize, 0usize);
    for ((e, f), v) in est
        .chunks_exact(4)
        .zip(r.rgba.chunks_exact(4))
        .zip(reference.variance.rgba.chunks_exact(4))
    {
        for c in 0..n {
            if !e[c].is_finite() {
                non_finite += 1;
                continue;
            }
            let d = e[c] as f64 - f[c] as f64;
            se += d * d;
            diff += d;
            var += v[c] as f64;
            count += 1;
        }
    }
    // Over no finite value there is no error to state: NaN, never a perfect 0.
    let k = if count == 0 { f64::NAN } else { count as f64 };
    let mse = se / k;
    Ok(ErrorMetrics {
        // (f64::max drops a NaN: keep it.)
        rmse: if count == 0 { f64::NAN } else { (mse - var / k).max(0.0).sqrt() },
        rmse_raw: mse.sqrt(),
        bias: diff / k,
        blocks: block_ratios(&est, reference.into(), n),
        surfaces: labels.map(|l| surface_ratios(&est, reference, n, l)).unwrap_or_default(),
        flip: (n == 3).then(|| flip(est, r)),
        non_finite,
    })
}

/// Mean FLIP of the two (linear) images, each mapped by L/(1+L).
fn flip(estimate: Vec<f32>, reference: &Image) -> f64 {
    let estimate = Image {
        width: reference.width,
        height: reference.height,
        rgba: estimate,
        srgb: false,
    };
    crate::diff::metrics::flip(&estimate.tone_mapped(), &reference.tone_mapped()).0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(v: f32, var: f32) -> (Image, Image) {
        let img = |x: f32| Image {
            width: 8,
            height: 8,
            rgba: [x, x, x, 1.0].repeat(64),
            srgb: false,
        };
        (img(v), img(var))
    }

    /// A flat AO reference of `v` with variance `var`.
    fn ao_reference(v: f32, var: f32) -> TermImage {
        let (mean, variance) = flat(v, var);
        TermImage {
            term: Term::Ao,
            samples: 64,
            mean,
            variance,
        }
    }

    /// A reference whose noise (its variance) explains all of the difference measures 0.
    #[test]
    fn the_reference_noise_is_subtracted() {
        let r = ao_reference(0.5, 0.01);
        let (est, _) = flat(0.6, 0.0);
        let m = error(&est, &r, "ao", None).unwrap();
        assert!((m.rmse_raw - 0.1).abs() < 1e-6 && m.rmse.abs() < 1e-3, "{m:?}");
        assert!((m.bias - 0.1).abs() < 1e-6 && m.flip.is_none());
        let (est, _) = flat(0.8, 0.0);
        let m = error(&est, &r, "ao", None).unwrap();
        assert!((m.rmse - (0.09f64 - 0.01).sqrt()).abs() < 1e-5, "{m:?}");
        let small = Image { width: 4, ..est };
        assert!(error(&small, &r, "ao", None)
            .unwrap_err()
            .to_string()
            .contains("size of the viewport"));
    }

    /// Block ratios find what the mean hides: half the image at twice the reference and half
    /// at none has a ratio of 1 on the whole but 0 and 2 by block; dark blocks and blocks the
    /// reference does not know are left out.
    #[test]
    fn block_ratios_show_regions_the_mean_hides() {
        let mut r = ao_reference(0.5, 0.0);
        r.term = Term::Direct;
        r.mean = Image {
            width: 16,
            height: 16,
            rgba: [0.5, 0.5, 0.5, 1.0].repeat(256),
            srgb: false,
        };
        r.variance = Image {
            rgba: [0.0; 4].repeat(256),
            ..r.mean.clone()
        };
        let mut est = r.mean.clone();
        for p in 0..256 {
            let v = if p % 16 < 8 { 1.0 } else { 0.0 };
            est.rgba[p * 4..p * 4 + 3].copy_from_slice(&[v; 3]);
        }
        let m = error(&est, &r, "hdr", None).unwrap();
        assert!(m.bias.abs() < 1e-9, "{m:?}");
        let b = m.blocks.unwrap();
        assert_eq!((b.min, b.max, b.blocks), (0.0, 2.0, 4), "{b:?}");
        assert_eq!((b.p10, b.p90), (0.0, 2.0));
        // A dark block and a noisy one are not judged.
        for p in 0..64 {
            let (x, y) = (p % 8, p / 8);
            r.mean.rgba[(y * 16 + x) * 4..][..3].copy_from_slice(&[0.0; 3]);
            r.variance.rgba[(y * 16 + x + 8) * 4..][..3].copy_from_slice(&[1.0; 3]);
        }
        assert_eq!(error(&est, &r, "hdr", None).unwrap().blocks.unwrap().blocks, 2);
        // Rows written before block ratios existed still load.
        let old = r#"{"rmse":0.1,"rmse_raw":0.1,"bias":0.0,"flip":null,"non_finite":0}"#;
        assert!(serde_json::from_str::<ErrorMetrics>(old).unwrap().blocks.is_none());
    }

    /// Surface ratios group pixels by the name of the surface they show (meshes of one name
    /// are one surface), leave out the background and surfaces under 16 pixels, and come
    /// lowest first.
    #[test]
    fn surface_ratios_group_pixels_by_name() {
        let mut r = ao_reference(0.5, 0.0);
        r.term = Term::Direct;
        let mut est = r.mean.clone();
        // Rows 0–3: "wall" (meshes 0 and 2) at 2×; rows 4–6: "floor" at 0.5×; row 7: one
        // "box" pixel, the rest background.
        let seen: Vec<Option<usize>> = (0..64)
            .map(|p| match p / 8 {
                0..=3 => Some(if p % 2 == 0 { 0 } else { 2 }),
                4..=6 => Some(1),
                _ => (p == 56).then_some(3),
            })
            .collect();
        for (p, s) in seen.iter().enumerate() {
            let v = match s {
                Some(0 | 2) => 1.0,
                Some(1) => 0.25,
                _ => 0.5,
            };
            est.rgba[p * 4..p * 4 + 3].copy_from_slice(&[v; 3]);
        }
        let labels = Surfaces {
            seen,
            names: ["wall", "floor", "wall", "box"].map(String::from).to_vec(),
        };
        let m = error(&est, &r, "hdr", Some(&labels)).unwrap();
        let got: Vec<(&str, f64, usize)> = m.surfaces.iter().map(|s| (s.name.as_str(), s.ratio, s.pixels)).collect();
        assert_eq!(got, [("floor", 0.5, 24), ("wall", 2.0, 32)]);
        let (low, high) = m.surface_extremes().unwrap();
        assert_eq!((low.name.as_str(), high.name.as_str()), ("floor", "wall"));
        assert!(error(&est, &r, "hdr", None).unwrap().surfaces.is_empty());
    }

    /// An estimate without one finite value has no error to state: NaN (not 0, which would
    /// put it on the Pareto front), and it survives a round trip through a row's JSON.
    #[test]
    fn an_error_over_no_finite_value_is_nan() {
        let r = ao_reference(0.5, 0.01);
        let (est, _) = flat(f32::NAN, 0.0);
        let m = error(&est, &r, "ao", None).unwrap();
        assert!(m.rmse.is_nan() && m.rmse_raw.is_nan() && m.bias.is_nan(), "{m:?}");
        assert_eq!(m.non_finite, 64);
        let json = serde_json::to_string(&m).unwrap();
        let back: ErrorMetrics = serde_json::from_str(&json).unwrap();
        assert!(back.rmse.is_nan() && back.non_finite == 64, "{json}");
    }
}
