//! Resource data: a file's or inline numbers' bytes in the exact layout of a declared
//! texture or buffer (`data:` in a pipeline file, `render --input`). One decoder for both,
//! so what `check` accepts is what the runtime uploads. Values are taken as stored: no
//! colour conversion (inputs are data).

use crate::format::{ScalarKind, TextureFormat};
use crate::ir::DataSource;
use std::path::Path;

/// What a texture's data must fill: mip 0 of every layer.
#[derive(Clone, Copy, Debug)]
pub struct TextureShape {
    pub format: TextureFormat,
    pub extent: (u32, u32),
    pub layers: u32,
}

/// Is this file an image (decoded by its format) rather than raw bytes?
fn is_image(path: &Path) -> bool {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    matches!(ext.as_deref(), Some("png" | "exr"))
}

fn is_json(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// A buffer's bytes from a file (a JSON array of numbers, each an f32; anything else raw).
pub fn buffer_from_file(path: &Path, raw: Vec<u8>) -> Result<Vec<u8>, String> {
    if !is_json(path) {
        return Ok(raw);
    }
    let values: Vec<f64> = serde_json::from_slice(&raw).map_err(|e| format!("expected a JSON array of numbers: {e}"))?;
    // 1e39 is finite text but +inf as an f32: refused, not uploaded as infinity.
    if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| !(**v as f32).is_finite()) {
        return Err(format!("element {i} ({v:e}) is not a finite 32-bit float (largest ±3.4e38)"));
    }
    Ok(f32_bytes(&values))
}

fn f32_bytes(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|v| (*v as f32).to_le_bytes()).collect()
}

/// Inline numbers as bytes (files are read by the caller).
pub fn inline_bytes(d: &DataSource) -> Option<Vec<u8>> {
    match d {
        DataSource::File(_) => None,
        DataSource::F32(v) => Some(f32_bytes(v)),
        DataSource::U32(v) => Some(v.iter().flat_map(|x| (*x as u32).to_le_bytes()).collect()),
    }
}

/// The bytes a buffer of `size` gets, or why they do not fit.
pub fn check_buffer(bytes: Vec<u8>, size: u64) -> Result<Vec<u8>, String> {
    check_buffer_size(bytes.len(), size)?;
    Ok(bytes)
}

/// Whether `len` bytes fill a buffer of `size`, or why not.
pub fn check_buffer_size(len: usize, size: u64) -> Result<(), String> {
    if len as u64 != size {
        return Err(format!("has {len} bytes, the buffer is declared with {size}"));
    }
    Ok(())
}

/// Whether `len` bytes are exactly a texture's raw texels (mip 0 of every layer, tightly
/// packed), or why not.
pub fn check_texels_size(len: usize, shape: TextureShape) -> Result<(), String> {
    let (w, h) = shape.extent;
    let want = w as u64 * h as u64 * shape.layers as u64 * shape.format.bytes() as u64;
    if len as u64 != want {
        return Err(format!(
            "has {len} bytes; {w}×{h} × {} layer(s) of {} is {want} bytes",
            shape.layers,
            shape.format.name()
        ));
    }
    Ok(())
}

/// A texture's texels from a file: a PNG or EXR of exactly its size (one layer), or raw
/// bytes of exactly mip 0 of every layer.
pub fn texture_from_file(path: &Path, raw: Vec<u8>, shape: TextureShape) -> Result<Vec<u8>, String> {
    let (w, h) = shape.extent;
    if !is_image(path) {
        check_texels_size(raw.len(), shape)?;
        return Ok(raw);
    }
    if shape.layers != 1 {
        return Err(format!(
            "an image holds one layer; the texture has {} (give raw bytes of every layer instead)",
            shape.layers
        ));
    }
    let img = image::load_from_memory(&raw).map_err(|e| format!("cannot decode the image: {e}"))?;
    if (img.width(), img.height()) != (w, h) {
        return Err(format!("is {}×{}, the texture is {w}×{h}", img.width(), img.height()));
    }
    texels(&img, shape.format)
}

/// An image's pixels in `format`: 8-bit normalized, 16-bit float or 32-bit float channels.
fn texels(img: &image::DynamicImage, format: TextureFormat) -> Result<Vec<u8>, String> {
    let n = format.components() as usize;
    let per = format.bytes() as usize / n.max(1);
    let plain = per * n == format.bytes() as usize && !format.is_depth() && !format.name().starts_with("Bgra");
    Ok(match (plain, format.kind(), per) {
        (true, ScalarKind::Float, 1) => img.to_rgba8().pixels().flat_map(|p| p.0[..n].to_vec()).collect(),
        (true, ScalarKind::Float, 2) => img
            .to_rgba32f()
            .pixels()
            .flat_map(|p| {
                p.0[..n]
                    .iter()
                    .flat_map(|v| half::f16::from_f32(*v).to_le_bytes())
                    .collect::<Vec<_>>()
            })
            .collect(),
        (true, ScalarKind::Float, 4) => img
            .to_rgba32f()
            .pixels()
            .flat_map(|p| p.0[..n].iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<_>>())
            .collect(),
        _ => {
            return Err(format!(
                "a {} texture cannot be filled from an image (give raw little-endian bytes)",
                format.name()
            ))
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A JSON number beyond f32 (finite text, +inf as the f32 uploaded) is refused, named by
    /// its index, in data files and `--input` alike (one decoder).
    #[test]
    fn json_numbers_beyond_f32_are_refused() {
        let err = buffer_from_file(Path::new("v.json"), b"[1.0, 1e39]".to_vec()).unwrap_err();
        assert!(err.contains("element 1 (1e39) is not a finite 32-bit float"), "{err}");
        assert_eq!(buffer_from_file(Path::new("v.json"), b"[1.0, -3e38]".to_vec()).unwrap().len(), 8);
    }

    #[test]
    fn buffers_from_json_raw_and_inline() {
        let json = buffer_from_file(Path::new("w.json"), b"[0.5, 2]".to_vec()).unwrap();
        assert_eq!(json, [0.5f32.to_le_bytes(), 2f32.to_le_bytes()].concat());
        assert_eq!(buffer_from_file(Path::new("w.bin"), vec![1, 2, 3]).unwrap(), vec![1, 2, 3]);
        assert!(buffer_from_file(Path::new("w.json"), b"{}".to_vec())
            .unwrap_err()
            .contains("JSON array"));
        assert_eq!(inline_bytes(&DataSource::U32(vec![7])).unwrap(), 7u32.to_le_bytes());
        assert!(check_buffer(vec![0; 8], 16)
            .unwrap_err()
            .contains("has 8 bytes, the buffer is declared with 16"));
    }

    #[test]
    fn raw_textures_must_fill_every_layer() {
        let shape = TextureShape {
            format: TextureFormat::R32Float,
            extent: (2, 2),
            layers: 3,
        };
        assert_eq!(texture_from_file(Path::new("t.bin"), vec![0; 48], shape).unwrap().len(), 48);
        let e = texture_from_file(Path::new("t.bin"), vec![0; 47], shape).unwrap_err();
        assert!(e.contains("has 47 bytes; 2×2 × 3 layer(s) of R32Float is 48 bytes"), "{e}");
    }
}
