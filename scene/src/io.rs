//! Images lightbench reads back and writes (PNG, EXR), and image comparisons. Files are
//! written through `files` (atomic, symlink- and mode-preserving).

use crate::error::{Error, Result};
pub use crate::files::write_atomic;
use std::path::Path;

/// A read-back image: RGBA f32 texels, row-major, top row first.
#[derive(Clone, Debug)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<f32>,
    /// The values are sRGB-encoded (an `*Srgb` format); PNG stores them as they are.
    pub srgb: bool,
}

impl Image {
    /// Copy the red channel to green and blue: a one-channel texture (depth, AO, a mask)
    /// then reads as grey rather than red.
    /// Numbers as a one-row, one-channel image (a buffer's words, for comparisons).
    pub fn row(values: Vec<f32>) -> Image {
        Image {
            width: values.len() as u32,
            height: 1,
            rgba: values.iter().flat_map(|&v| [v, 0.0, 0.0, 1.0]).collect(),
            srgb: false,
        }
    }

    pub fn grey_from_red(&mut self) {
        for px in self.rgba.chunks_exact_mut(4) {
            px[1] = px[0];
            px[2] = px[0];
        }
    }

    pub fn pixel(&self, x: u32, y: u32) -> [f32; 4] {
        let i = ((y * self.width + x) * 4) as usize;
        [self.rgba[i], self.rgba[i + 1], self.rgba[i + 2], self.rgba[i + 3]]
    }

    /// Values in linear light (sRGB decoded where needed).
    pub fn linear(&self) -> Vec<f32> {
        if !self.srgb {
            return self.rgba.clone();
        }
        self.rgba
            .iter()
            .enumerate()
            .map(|(i, &v)| if i % 4 == 3 { v } else { srgb_to_linear(v) })
            .collect()
    }

    /// HDR colour for display: each colour channel of the linear values mapped by L/(1+L)
    /// (negative as 0, non-finite as 1, a visible white); alpha as it is.
    pub fn tone_mapped(&self) -> Image {
        let rgba = self
            .linear()
            .into_iter()
            .enumerate()
            .map(|(i, v)| match (i % 4 == 3, v.is_finite()) {
                (true, _) => v,
                (false, true) => v.max(0.0) / (1.0 + v.max(0.0)),
                (false, false) => 1.0,
            })
            .collect();
        Image {
            rgba,
            srgb: false,
            ..*self
        }
    }

    /// Texels that are NaN or infinite.
    pub fn non_finite(&self) -> usize {
        self.rgba.iter().filter(|v| !v.is_finite()).count()
    }

    /// Mean of the first three channels over a rectangle (inclusive-exclusive), linear.
    pub fn mean_rgb(&self, x0: u32, y0: u32, x1: u32, y1: u32) -> f32 {
        let lin = self.linear();
        let mut sum = 0.0f64;
        let mut n = 0usize;
        for y in y0..y1.min(self.height) {
            for x in x0..x1.min(self.width) {
                let i = ((y * self.width + x) * 4) as usize;
                sum += (lin[i] + lin[i + 1] + lin[i + 2]) as f64 / 3.0;
                n += 1;
            }
        }
        if n == 0 {
            0.0
        } else {
            (sum / n as f64) as f32
        }
    }

    /// Save by extension: `.png` (8-bit, sRGB) or `.exr` (linear float).
    pub fn save(&self, path: &Path) -> Result<()> {
        let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase());
        let mut bytes = std::io::Cursor::new(Vec::new());
        match ext.as_deref() {
            Some("png") => {
                let data: Vec<u8> = self
                    .rgba
                    .iter()
                    .enumerate()
                    .map(|(i, &v)| {
                        // Linear data is encoded to sRGB for PNG; alpha stays linear.
                        let v = if self.srgb || i % 4 == 3 { v } else { linear_to_srgb(v) };
                        (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
                    })
                    .collect();
                let img =
                    image::RgbaImage::from_raw(self.width, self.height, data).ok_or_else(|| Error::io(path, "image size mismatch"))?;
                img.write_to(&mut bytes, image::ImageFormat::Png).map_err(|e| Error::io(path, e))?;
            }
            Some("exr") => {
                let img = image::Rgba32FImage::from_raw(self.width, self.height, self.linear())
                    .ok_or_else(|| Error::io(path, "image size mismatch"))?;
                image::DynamicImage::ImageRgba32F(img)
                    .write_to(&mut bytes, image::ImageFormat::OpenExr)
                    .map_err(|e| Error::io(path, e))?;
            }
            _ => return Err(Error::io(path, "unknown image type; use .png or .exr")),
        }
        write_atomic(path, &bytes.into_inner())
    }

    /// Load a PNG as linear-or-sRGB floats (sRGB: values as stored).
    pub fn load_png(path: &Path) -> Result<Image> {
        let img = image::open(path).map_err(|e| Error::io(path, e))?.to_rgba8();
        Ok(Image {
            width: img.width(),
            height: img.height(),
            rgba: img.as_raw().iter().map(|&b| b as f32 / 255.0).collect(),
            srgb: true,
        })
    }
}

/// A file-name-safe stem for one slice of a resource: its name (other characters as `_`),
/// then `.light{i}` for per-light resources, `.layer{l}` for layered ones and `.mip{k}` for
/// mip levels past 0 (dumps, diffs).
pub fn slice_stem(name: &str, r: &lightbench_compiler::plan::PlanResource, (inst, layer): (u32, u32), mip: u32) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if !r.per_light.is_empty() {
        s += &format!(".light{inst}");
    }
    if r.layers() > 1 {
        s += &format!(".layer{layer}");
    }
    if mip > 0 {
        s += &format!(".mip{mip}");
    }
    s
}

pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

pub fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.0031308 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// Root-mean-square error over RGB of two same-sized images, in the stored encoding.
pub fn rmse(a: &Image, b: &Image) -> Option<f64> {
    if a.width != b.width || a.height != b.height {
        return None;
    }
    let mut sum = 0.0f64;
    let mut n = 0usize;
    for (i, (x, y)) in a.rgba.iter().zip(&b.rgba).enumerate() {
        if i % 4 == 3 {
            continue;
        }
        sum += ((x - y) as f64).powi(2);
        n += 1;
    }
    Some((sum / n.max(1) as f64).sqrt())
}

/// 64-bit FNV-1a: identifies file contents in manifests (not a security hash).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h = Fnv1a::default();
    h.write(bytes);
    h.0
}

/// FNV-1a fed in pieces (`fnv1a` in one go).
pub struct Fnv1a(pub u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv1a {
    pub fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// `write`, then the length: moving bytes from one field to the next changes the hash.
    pub fn field(&mut self, bytes: &[u8]) {
        self.write(bytes);
        self.write(&(bytes.len() as u64).to_le_bytes());
    }
}
