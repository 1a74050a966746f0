//! Stage `images` of `diff`: what a compared resource looks like side by side — A, B and the
//! error heat-map (magma, FLIP's colour map) in one PNG, and the heat-map alone.

use crate::error::Result;
use crate::io::{write_atomic, Image};
use std::path::Path;

/// A read-back image as 8-bit sRGB RGB for display: colour as stored (linear values are
/// sRGB-encoded, as PNG stores them); with `range`, data stretched from its lowest to its
/// highest value; single-channel data as grey; non-finite values white.
pub fn display_rgb8(img: &Image, channels: usize, range: Option<(f32, f32)>) -> Vec<u8> {
    let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    // The encoding chosen once, each a loop of its own.
    match range {
        Some((lo, hi)) => {
            let span = if hi > lo { hi - lo } else { 1.0 };
            rgb8(img, channels, |v| if v.is_finite() { byte((v - lo) / span) } else { 255 })
        }
        None if img.srgb => rgb8(img, channels, byte),
        None => rgb8(img, channels, |v| byte(crate::io::linear_to_srgb(v))),
    }
}

/// Each pixel's first three channels (or its first as grey) through `encode`.
fn rgb8(img: &Image, channels: usize, encode: impl Fn(f32) -> u8) -> Vec<u8> {
    let mut out = vec![0u8; img.rgba.len() / 4 * 3];
    for (o, p) in out.chunks_exact_mut(3).zip(img.rgba.chunks_exact(4)) {
        match channels {
            1 => o.fill(encode(p[0])),
            _ => o.copy_from_slice(&[encode(p[0]), encode(p[1]), encode(p[2])]),
        }
    }
    out
}

/// Lowest and highest finite value of the first `channels` channels of both images.
pub fn value_range(a: &Image, b: &Image, channels: usize) -> (f32, f32) {
    let n = channels.clamp(1, 3);
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    // One image twice (equal sides) is scanned once.
    let images: &[&Image] = if std::ptr::eq(a, b) { &[a] } else { &[a, b] };
    for img in images {
        for p in img.rgba.chunks_exact(4) {
            for &v in p[..n].iter().filter(|v| v.is_finite()) {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    (lo, hi)
}

/// The error map (0..1 per pixel) through the magma colour map (FLIP's), as 8-bit RGB.
fn heat_rgb(map: &[f32]) -> Vec<u8> {
    static LUT: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    let lut = LUT.get_or_init(|| nv_flip::magma_lut().to_vec());
    let entries = (lut.len() / 3).max(1);
    let mut out = vec![0u8; map.len() * 3];
    for (o, &v) in out.chunks_exact_mut(3).zip(map) {
        let i = ((v.clamp(0.0, 1.0) * (entries - 1) as f32).round() as usize).min(entries - 1) * 3;
        o.copy_from_slice(&lut[i..i + 3]);
    }
    out
}

/// An 8-bit RGB image as a PNG file (atomic).
pub fn png(rgb: Vec<u8>, (w, h): (u32, u32), path: &Path) -> Result<()> {
    let img = image::RgbImage::from_raw(w, h, rgb).ok_or_else(|| crate::error::Error::io(path, "image size mismatch"))?;
    // Fast compression: a report writes a few dozen of these.
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    let mut bytes = vec![];
    img.write_with_encoder(PngEncoder::new_with_quality(&mut bytes, CompressionType::Fast, FilterType::Sub))
        .map_err(|e| crate::error::Error::io(path, e))?;
    Ok(write_atomic(path, &bytes)?)
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
    let shown_a = display_rgb8(a, channels, range);
    // Equal sides (`diff` passes one image twice) are shown from one conversion.
    let shown_b = if std::ptr::eq(a, b) {
        shown_a.clone()
    } else {
        display_rgb8(b, channels, range)
    };
    let panels = [shown_a, shown_b, heat.clone()];
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
