//! Stage `images` of `diff`: what a compared resource looks like side by side — A, B and the
//! error heat-map (magma, FLIP's colour map) in one PNG, and the heat-map alone.

use crate::error::Result;
use crate::io::{write_atomic, Image};
use std::path::Path;

/// A display version of a read-back image: colour as stored (PNG encodes linear values to
/// sRGB); other data stretched from the lowest to the highest value seen in either image,
/// single-channel data as grey. `range` is that (min, max).
fn display(img: &Image, channels: usize, range: Option<(f32, f32)>) -> Image {
    let mut out = img.clone();
    if let Some((lo, hi)) = range {
        let span = if hi > lo { hi - lo } else { 1.0 };
        for (i, v) in out.rgba.iter_mut().enumerate() {
            if i % 4 != 3 {
                *v = if v.is_finite() { (*v - lo) / span } else { 1.0 };
            }
        }
        out.srgb = true;
    }
    if channels == 1 {
        out.grey_from_red();
    }
    for px in out.rgba.chunks_mut(4) {
        px[3] = 1.0;
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

/// The error map (0..1 per pixel) through the magma colour map, as 8-bit RGB.
fn heat_rgb(map: &[f32], (w, h): (u32, u32)) -> Vec<u8> {
    let values = nv_flip::FlipImageFloat::with_data(w, h, map);
    values.apply_color_lut(&nv_flip::magma_lut()).to_vec()
}

fn png(rgb: Vec<u8>, (w, h): (u32, u32), path: &Path) -> Result<()> {
    let img = image::RgbImage::from_raw(w, h, rgb).ok_or_else(|| crate::error::Error::io(path, "image size mismatch"))?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| crate::error::Error::io(path, e))?;
    write_atomic(path, &bytes.into_inner())
}

/// 8-bit RGB of a display image (sRGB-encoded as PNG stores it).
fn rgb8(img: &Image) -> Vec<u8> {
    img.rgba
        .chunks(4)
        .flat_map(|p| {
            [0, 1, 2].map(|c| {
                let v = if img.srgb { p[c] } else { crate::io::linear_to_srgb(p[c]) };
                (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
            })
        })
        .collect()
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
    let heat = heat_rgb(map, (w, h));
    let panels = [rgb8(&display(a, channels, range)), rgb8(&display(b, channels, range)), heat.clone()];
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
