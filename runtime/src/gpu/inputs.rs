//! External resources (`external: true`): the caller supplies their contents before a frame
//! — a texture from a PNG or EXR, a buffer from raw little-endian bytes or a JSON array of
//! numbers (as f32). Values are taken as stored (no colour conversion: inputs are data). A
//! size that does not match the declaration is an error naming both.

use super::Executor;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use lightbench_compiler::format::{ScalarKind, TextureFormat};
use lightbench_compiler::plan::ResourceShape;
use std::path::Path;

impl Executor {
    /// Fill external resource `name` from `file`.
    pub fn load_input(&mut self, gpu: &Gpu, name: &str, file: &Path) -> Result<()> {
        let res = self
            .plan()
            .resource(name)
            .ok_or_else(|| Error::Usage(format!("--input `{name}`: no such resource")))?;
        if !res.external {
            return Err(Error::Usage(format!("--input `{name}`: the resource is not `external: true`")));
        }
        if !res.per_light.is_empty() {
            return Err(Error::Usage(format!(
                "--input `{name}`: per-light external resources cannot be supplied yet"
            )));
        }
        let shape = res.shape.clone();
        let entry = self
            .pool()
            .by_name(name)
            .ok_or_else(|| Error::Resource(format!("`{name}` has no storage")))?;
        match shape {
            ResourceShape::Buffer { size } => {
                let bytes = buffer_bytes(file)?;
                if bytes.len() as u64 != size {
                    let msg = format!(
                        "--input `{name}`: {} has {} bytes, the buffer is declared with {size}",
                        file.display(),
                        bytes.len()
                    );
                    return Err(Error::Usage(msg));
                }
                for parity in 0..2 {
                    if let Some(b) = entry.buffer(0, false, parity) {
                        gpu.queue.write_buffer(b, 0, &bytes);
                    }
                }
            }
            ResourceShape::Texture {
                format,
                extent,
                layers,
                mips,
                ..
            } => {
                if layers != 1 || mips != 1 {
                    return Err(Error::Usage(format!(
                        "--input `{name}`: only single-layer textures without mips can be supplied yet"
                    )));
                }
                let bytes = texture_bytes(file, format, extent)?;
                for parity in 0..2 {
                    if let Some(t) = entry.texture(0, false, parity) {
                        write_texture(gpu, t, &bytes, format.bytes(), extent);
                    }
                }
            }
        }
        self.supplied.insert(name.to_string());
        Ok(())
    }
}

fn write_texture(gpu: &Gpu, t: &wgpu::Texture, bytes: &[u8], texel: u32, (w, h): (u32, u32)) {
    gpu.queue.write_texture(
        t.as_image_copy(),
        bytes,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * texel),
            rows_per_image: Some(h),
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
}

/// A buffer's bytes: a JSON array of numbers (each an f32) or the file's raw bytes.
fn buffer_bytes(file: &Path) -> Result<Vec<u8>> {
    let raw = std::fs::read(file).map_err(|e| Error::io(file, e))?;
    if file.extension().is_some_and(|e| e.eq_ignore_ascii_case("json")) {
        let values: Vec<f64> =
            serde_json::from_slice(&raw).map_err(|e| Error::io(file, format!("expected a JSON array of numbers: {e}")))?;
        return Ok(values.iter().flat_map(|v| (*v as f32).to_le_bytes()).collect());
    }
    Ok(raw)
}

/// A texture's texels in `format` from a PNG or EXR of exactly `extent`.
fn texture_bytes(file: &Path, format: TextureFormat, (w, h): (u32, u32)) -> Result<Vec<u8>> {
    let img = image::open(file).map_err(|e| Error::io(file, e))?;
    if (img.width(), img.height()) != (w, h) {
        return Err(Error::Usage(format!(
            "--input: {} is {}×{}, the texture is {w}×{h} at this resolution",
            file.display(),
            img.width(),
            img.height()
        )));
    }
    let n = format.components() as usize;
    let per = format.bytes() as usize / n.max(1);
    let plain = per * n == format.bytes() as usize && !format.is_depth() && !format.name().starts_with("Bgra");
    let out: Vec<u8> = match (plain, format.kind(), per) {
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
            return Err(Error::Usage(format!(
                "--input: textures of format {} cannot be supplied from an image yet",
                format.name()
            )))
        }
    };
    Ok(out)
}
