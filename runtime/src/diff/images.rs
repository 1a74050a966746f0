//! Stage `images` of `diff`: what a compared resource looks like side by side — A, B and the
//! error heat-map (magma, FLIP's colour map) in one PNG, and the heat-map alone.

use crate::error::Result;
use crate::io::{write_atomic, Image};
use std::path::Path;

/// A read-back image as 8-bit sRGB RGB for display: colour as stored (linear values are
/// sRGB-encoded, as PNG stores them); with `range`, data stretched from its lowest to its
/// highest value; single-channel data as grey; non-finite values white.
pub fn display_rgb8(img: &Image, channels: usize, range: Option<(f32, f32)>) -> Vec<u8> {
    let encode = |v: f32| -> u8 {
        let v = match range {
            Some((lo, hi)) if v.is_finite() => (v - lo) / if hi > lo { hi - lo } else { 1.0 },
            Some(_) => 1.0,
            None if img.srgb => v,
            None => crate::io::linear_to_srgb(v),
        };
        (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
    };
    let mut out = Vec::with_capacity(img.rgba.len() / 4 * 3);
    for p in img.rgba.chunks(4) {
        match channels {
            1 => {
                let g = encode(p[0]);
                out.extend([g, g, g]);
            }
            _ => out.extend([encode(p[0]), encode(p[1]), encode(p[2])]),
        }
    }
    out
}

/// Lowest and highest finite value of the first `channels` channels of both images.
pub fn value_range(a: &Image, b: &Image, channels: usize) -> (f32, f32) {
    let n = channels.clamp(1, 3);
    a.rgba
        .chunks(4)
        .chain(b.rgba.chunks(4))
        .flat_map(|p| p[..n].iter().copied())
        .filter(|v| v.is_finite())
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
}

/// The error map (0..1 per pixel) through the magma colour map (FLIP's), as 8-bit RGB.
fn heat_rgb(map: &[f32]) -> Vec<u8> {
    static LUT: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    let lut = LUT.get_or_init(|| nv_flip::magma_lut().to_vec());
    let entries = (lut.len() / 3).max(1);
    map.iter()
        .flat_map(|&v| {
            let i = ((v.clamp(0.0, 1.0) * (entries - 1) as f32).round() as usize).min(entries - 1) * 3;
            [lut[i], lut[i + 1], lut[i + 2]]
        })
        .collect()
}

/// An 8-bit RGB image as a PNG file (atomic).
pub fn png(rgb: Vec<u8>, (w, h): (u32, u32), path: &Path) -> Result<()> {
    let img = image::RgbImage::from_raw(w, h, rgb).ok_or_else(|| crate::error::Error::io(path, "image size mismatch"))?;
    // Fast compression: a report writes a few dozen of these.
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    let mut bytes = vec![];
    img.write_with_encoder(PngEncoder::new_with_quality(&mut bytes, CompressionType::Fast, FilterType::Sub))
        .map_err(|e| crate::error::Error::io(path, e))?;
    write_atomic(path, &bytes)
}

/// Write `<stem>.heat.png` and `<stem>.side.png` (A | B | heat-map) into `dir`; returns their
/// file names. `stretch`: data rather than colour (stretched to its range for display).
pub fn write(
    dir: &Path,
    stem: &str,
    (a, b): (&Image, &Image),
    (channels, stretch): (usize, bool),
    map: &[f32],
) -> Result<(String, String)> {
    let (w, h) = (a.width, a.height);
    let range = stretch.then(|| value_range(a, b, channels));
    let heat = heat_rgb(map);
    let panels = [display_rgb8(a, channels, range), display_rgb8(b, channels, range), heat.clone()];
    // Three panels side by side, 2 px apart on grey.
    let gap = 2u32;
    let sw = 3 * w + 2 * gap;
    let mut side = vec![128u8; (sw * h * 3) as usize];
    for (k, panel) in panels.iter().enumerate() {
        let x0 = k as u32 * (w + gap);
        for y in 0..h {
            let src = (y * w * 3) as usize;
            let dst = ((y * sw + x0) * 3) as usize;
            side[dst..dst + (w * 3) as usize].copy_from_slice(&panel[src..src + (w * 3) as usize]);
        }
    }
    let (heat_name, side_name) = (format!("{stem}.heat.png"), format!("{stem}.side.png"));
    png(heat, (w, h), &dir.join(&heat_name))?;
    png(side, (sw, h), &dir.join(&side_name))?;
    Ok((heat_name, side_name))
}
