//! Stage `measure` of `sweep`: how far a raster estimate is from the reference term — RMSE
//! corrected for the reference's own noise, bias, and for colour terms mean FLIP — over the
//! pixels both images have.

use crate::error::{Error, Result};
use crate::io::Image;
use crate::reference::{Term, TermImage};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
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

pub fn error(estimate: &Image, reference: &TermImage, resource: &str) -> Result<ErrorMetrics> {
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
        let m = error(&est, &r, "ao").unwrap();
        assert!((m.rmse_raw - 0.1).abs() < 1e-6 && m.rmse.abs() < 1e-3, "{m:?}");
        assert!((m.bias - 0.1).abs() < 1e-6 && m.flip.is_none());
        let (est, _) = flat(0.8, 0.0);
        let m = error(&est, &r, "ao").unwrap();
        assert!((m.rmse - (0.09f64 - 0.01).sqrt()).abs() < 1e-5, "{m:?}");
        let small = Image { width: 4, ..est };
        assert!(error(&small, &r, "ao").unwrap_err().to_string().contains("size of the viewport"));
    }

    /// An estimate without one finite value has no error to state: NaN (not 0, which would
    /// put it on the Pareto front), and it survives a round trip through a row's JSON.
    #[test]
    fn an_error_over_no_finite_value_is_nan() {
        let r = ao_reference(0.5, 0.01);
        let (est, _) = flat(f32::NAN, 0.0);
        let m = error(&est, &r, "ao").unwrap();
        assert!(m.rmse.is_nan() && m.rmse_raw.is_nan() && m.bias.is_nan(), "{m:?}");
        assert_eq!(m.non_finite, 64);
        let json = serde_json::to_string(&m).unwrap();
        let back: ErrorMetrics = serde_json::from_str(&json).unwrap();
        assert!(back.rmse.is_nan() && back.non_finite == 64, "{json}");
    }
}
