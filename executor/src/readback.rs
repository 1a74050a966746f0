//! Reading textures and buffers back to the CPU as f32 values.

use super::Gpu;
use crate::error::{Error, Result};
use lightbench_scene::io::Image;

fn texel_bytes(f: wgpu::TextureFormat) -> Result<u32> {
    use wgpu::TextureFormat as F;
    Ok(match f {
        F::R8Unorm => 1,
        F::Rg8Unorm | F::R16Float | F::Depth16Unorm => 2,
        F::Rgba8Unorm
        | F::Rgba8UnormSrgb
        | F::Bgra8Unorm
        | F::Bgra8UnormSrgb
        | F::Rgb10a2Unorm
        | F::Rg11b10Ufloat
        | F::Rg16Float
        | F::R32Float
        | F::R32Uint
        | F::R32Sint
        | F::Depth32Float => 4,
        F::Rgba16Float | F::Rg32Float | F::Rg32Uint | F::Rgba16Uint => 8,
        F::Rgba32Float | F::Rgba32Uint => 16,
        other => return Err(Error::Resource(format!("reading back {other:?} is not supported"))),
    })
}

/// Unsigned float with `m` mantissa bits and a 5-bit exponent (Rg11b10Ufloat channels).
fn small_float(bits: u32, m: u32) -> f32 {
    let mant = bits & ((1 << m) - 1);
    let exp = (bits >> m) & 0x1f;
    match exp {
        0 => mant as f32 / (1 << m) as f32 * 2f32.powi(-14),
        31 => {
            if mant == 0 {
                f32::INFINITY
            } else {
                f32::NAN
            }
        }
        e => (1.0 + mant as f32 / (1 << m) as f32) * 2f32.powi(e as i32 - 15),
    }
}

/// Rows of `w` texels of `N` bytes each, `row` bytes apart, each decoded by `texel`: one loop
/// per format (monomorphised), so that nothing is decided per texel but its values.
fn texels<const N: usize>(data: &[u8], row: usize, (w, h): (usize, usize), texel: impl Fn(&[u8; N]) -> [f32; 4]) -> Vec<f32> {
    let mut rgba = Vec::with_capacity(w * h * 4);
    for y in 0..h {
        for t in data[y * row..y * row + w * N].chunks_exact(N) {
            rgba.extend_from_slice(&texel(t.try_into().expect("chunks of N bytes")));
        }
    }
    rgba
}

/// A level's texels (rows `row` bytes apart) as RGBA f32: normalized formats scaled to 0..1,
/// integers as their values, missing channels 0 and alpha 1.
fn decode(f: wgpu::TextureFormat, data: &[u8], row: u32, (w, h): (u32, u32)) -> Result<Vec<f32>> {
    use wgpu::TextureFormat as F;
    let u8n = |v: u8| v as f32 / 255.0;
    let h16 = |t: &[u8], i: usize| half::f16::from_le_bytes([t[2 * i], t[2 * i + 1]]).to_f32();
    let u16_at = |t: &[u8], i: usize| u16::from_le_bytes([t[2 * i], t[2 * i + 1]]) as f32;
    let f32_at = |t: &[u8], i: usize| f32::from_le_bytes([t[4 * i], t[4 * i + 1], t[4 * i + 2], t[4 * i + 3]]);
    let u32_at = |t: &[u8], i: usize| u32::from_le_bytes([t[4 * i], t[4 * i + 1], t[4 * i + 2], t[4 * i + 3]]);
    let (d, r, s) = (data, row as usize, (w as usize, h as usize));
    Ok(match f {
        F::R8Unorm => texels::<1>(d, r, s, |t| [u8n(t[0]), 0.0, 0.0, 1.0]),
        F::Rg8Unorm => texels::<2>(d, r, s, |t| [u8n(t[0]), u8n(t[1]), 0.0, 1.0]),
        F::Rgba8Unorm | F::Rgba8UnormSrgb => texels::<4>(d, r, s, |t| t.map(u8n)),
        F::Bgra8Unorm | F::Bgra8UnormSrgb => texels::<4>(d, r, s, |t| [u8n(t[2]), u8n(t[1]), u8n(t[0]), u8n(t[3])]),
        F::Rgb10a2Unorm => texels::<4>(d, r, s, |t| {
            let v = u32_at(t, 0);
            [
                (v & 1023) as f32 / 1023.0,
                ((v >> 10) & 1023) as f32 / 1023.0,
                ((v >> 20) & 1023) as f32 / 1023.0,
                (v >> 30) as f32 / 3.0,
            ]
        }),
        F::Rg11b10Ufloat => texels::<4>(d, r, s, |t| {
            let v = u32_at(t, 0);
            [
                small_float(v & 0x7ff, 6),
                small_float((v >> 11) & 0x7ff, 6),
                small_float(v >> 22, 5),
                1.0,
            ]
        }),
        F::R16Float => texels::<2>(d, r, s, |t| [h16(t, 0), 0.0, 0.0, 1.0]),
        F::Rg16Float => texels::<4>(d, r, s, |t| [h16(t, 0), h16(t, 1), 0.0, 1.0]),
        F::Rgba16Float => texels::<8>(d, r, s, |t| [h16(t, 0), h16(t, 1), h16(t, 2), h16(t, 3)]),
        F::R32Float | F::Depth32Float => texels::<4>(d, r, s, |t| [f32_at(t, 0), 0.0, 0.0, 1.0]),
        F::Depth16Unorm => texels::<2>(d, r, s, |t| [u16_at(t, 0) / 65535.0, 0.0, 0.0, 1.0]),
        F::Rg32Float => texels::<8>(d, r, s, |t| [f32_at(t, 0), f32_at(t, 1), 0.0, 1.0]),
        F::Rgba32Float => texels::<16>(d, r, s, |t| [f32_at(t, 0), f32_at(t, 1), f32_at(t, 2), f32_at(t, 3)]),
        F::R32Uint => texels::<4>(d, r, s, |t| [u32_at(t, 0) as f32, 0.0, 0.0, 1.0]),
        F::R32Sint => texels::<4>(d, r, s, |t| [u32_at(t, 0) as i32 as f32, 0.0, 0.0, 1.0]),
        F::Rg32Uint => texels::<8>(d, r, s, |t| [u32_at(t, 0) as f32, u32_at(t, 1) as f32, 0.0, 1.0]),
        F::Rgba32Uint => texels::<16>(d, r, s, |t| [0, 1, 2, 3].map(|i| u32_at(t, i) as f32)),
        F::Rgba16Uint => texels::<8>(d, r, s, |t| [0, 1, 2, 3].map(|i| u16_at(t, i))),
        other => return Err(Error::Resource(format!("reading back {other:?} is not supported"))),
    })
}

/// Mip 0 of one array layer.
pub fn read_texture(gpu: &Gpu, tex: &wgpu::Texture, layer: u32) -> Result<Image> {
    read_texture_mip(gpu, tex, layer, 0)
}

/// A layer's texels as copied from the GPU, not yet decoded (decoding can then run on
/// another thread: `lightbench diff` decodes while it reads the next resource). Equal when
/// their bytes are: `diff` decodes and measures two equal slices once.
#[derive(PartialEq)]
pub struct Raw {
    format: wgpu::TextureFormat,
    bytes: Vec<u8>,
    row: u32,
    size: (u32, u32),
}

impl Raw {
    pub fn decode(&self) -> Result<Image> {
        let (w, h) = self.size;
        Ok(Image {
            width: w,
            height: h,
            rgba: decode(self.format, &self.bytes, self.row, self.size)?,
            srgb: self.format.is_srgb(),
        })
    }
}

/// One layer of one mip level, copied to the CPU undecoded.
pub fn read_texture_raw(gpu: &Gpu, tex: &wgpu::Texture, layer: u32, mip: u32) -> Result<Raw> {
    let (w, h, (bytes, row)) = with_texels(gpu, tex, (layer, mip), |data, row, _| (data.to_vec(), row))?;
    Ok(Raw {
        format: tex.format(),
        bytes,
        row,
        size: (w, h),
    })
}

/// One layer of one mip level.
pub fn read_texture_mip(gpu: &Gpu, tex: &wgpu::Texture, layer: u32, mip: u32) -> Result<Image> {
    let f = tex.format();
    let (w, h, rgba) = with_texels(gpu, tex, (layer, mip), |data, row, size| decode(f, data, row, size))?;
    Ok(Image {
        width: w,
        height: h,
        rgba: rgba?,
        srgb: f.is_srgb(),
    })
}

/// The first non-finite value of a texture level: (x, y, channel), the value, and how many
/// non-finite values it holds.
pub type NonFinite = ((u32, u32, u32), f32, usize);

/// Non-finite values of one layer and mip level, checked on the raw bits (fast: no
/// decoding): the first as (x, y, channel, value) and how many. `None` without reading for
/// formats that cannot hold one (normalized and integer formats).
pub fn scan_texture(gpu: &Gpu, tex: &wgpu::Texture, layer: u32, mip: u32) -> Result<Option<NonFinite>> {
    use wgpu::TextureFormat as F;
    let f = tex.format();
    let half = matches!(f, F::R16Float | F::Rg16Float | F::Rgba16Float);
    let single = matches!(f, F::R32Float | F::Rg32Float | F::Rgba32Float | F::Depth32Float);
    if f == F::Rg11b10Ufloat {
        let img = read_texture_mip(gpu, tex, layer, mip)?;
        let count = img.rgba.iter().filter(|v| !v.is_finite()).count();
        return Ok(img.rgba.iter().position(|v| !v.is_finite()).map(|i| {
            let t = (i / 4) as u32;
            ((t % img.width, t / img.width, (i % 4) as u32), img.rgba[i], count)
        }));
    }
    if !half && !single {
        return Ok(None);
    }
    let (size, comps) = (if half { 2 } else { 4 }, texel_bytes(f)? / if half { 2 } else { 4 });
    let (_, _, found) = with_texels(gpu, tex, (layer, mip), |data, row, (w, h)| {
        let mut first = None;
        let mut count = 0;
        for y in 0..h {
            let line = &data[(y * row) as usize..][..(w * comps * size) as usize];
            for (i, c) in line.chunks_exact(size as usize).enumerate() {
                let (bad, value) = if half {
                    let bits = u16::from_le_bytes([c[0], c[1]]);
                    (bits & 0x7c00 == 0x7c00, half::f16::from_bits(bits).to_f32())
                } else {
                    let bits = u32::from_le_bytes([c[0], c[1], c[2], c[3]]);
                    (bits & 0x7f80_0000 == 0x7f80_0000, f32::from_bits(bits))
                };
                if bad {
                    count += 1;
                    let i = i as u32;
                    first.get_or_insert(((i / comps, y, i % comps), value));
                }
            }
        }
        first.map(|(at, v)| (at, v, count))
    })?;
    Ok(found)
}

/// Copy one layer and mip level to a mapped buffer and hand its rows (`row` bytes apart) to
/// `f` with the level's size.
fn with_texels<T>(
    gpu: &Gpu,
    tex: &wgpu::Texture,
    (layer, mip): (u32, u32),
    f: impl FnOnce(&[u8], u32, (u32, u32)) -> T,
) -> Result<(u32, u32, T)> {
    let format = tex.format();
    let bpp = texel_bytes(format)?;
    let (w, h) = ((tex.width() >> mip).max(1), (tex.height() >> mip).max(1));
    let row = (w * bpp).div_ceil(256) * 256;
    let buf = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: (row * h) as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture: tex,
            mip_level: mip,
            origin: wgpu::Origin3d { x: 0, y: 0, z: layer },
            aspect: if format.is_depth_stencil_format() {
                wgpu::TextureAspect::DepthOnly
            } else {
                wgpu::TextureAspect::All
            },
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buf,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    gpu.queue.submit([enc.finish()]);
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(Error::gpu(format!("reading back a {format:?} texture"), e));
    }
    let slice = buf.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Error::gpu("waiting for the read-back", e))?;
    let data = slice.get_mapped_range().map_err(|e| Error::gpu("mapping the read-back", e))?;
    let out = f(&data, row, (w, h));
    drop(data);
    buf.unmap();
    Ok((w, h, out))
}

pub fn read_buffer(gpu: &Gpu, src: &wgpu::Buffer) -> Result<Vec<f32>> {
    let size = src.size();
    let buf = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    enc.copy_buffer_to_buffer(src, 0, &buf, 0, size);
    gpu.queue.submit([enc.finish()]);
    let slice = buf.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Error::gpu("waiting for the read-back", e))?;
    let out = bytemuck::cast_slice::<u8, f32>(&slice.get_mapped_range().map_err(|e| Error::gpu("mapping the read-back", e))?).to_vec();
    buf.unmap();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::{decode, small_float};

    /// Rows padded beyond their texels (as copies to buffers are) decode to the texels alone,
    /// channel by channel as each format stores them.
    #[test]
    fn padded_rows_decode_by_format() {
        use wgpu::TextureFormat as F;
        // 2×2 texels, 4 bytes each, rows 12 bytes apart (4 of padding).
        let rows = [
            [0u8, 51, 255, 102, 255, 0, 0, 255, 9, 9, 9, 9],
            [1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 9],
        ];
        let data: Vec<u8> = rows.concat();
        let rgba = decode(F::Rgba8Unorm, &data, 12, (2, 2)).unwrap();
        assert_eq!(rgba.len(), 16);
        assert_eq!(&rgba[..8], &[0.0, 0.2, 1.0, 0.4, 1.0, 0.0, 0.0, 1.0]);
        assert_eq!(rgba[8], 1.0 / 255.0);
        let bgra = decode(F::Bgra8Unorm, &data, 12, (2, 2)).unwrap();
        assert_eq!(&bgra[..4], &[1.0, 0.2, 0.0, 0.4]);
        let depth: Vec<u8> = [0.25f32, -1.5].iter().flat_map(|v| v.to_le_bytes()).collect();
        assert_eq!(
            decode(F::Depth32Float, &depth, 8, (2, 1)).unwrap(),
            [0.25, 0.0, 0.0, 1.0, -1.5, 0.0, 0.0, 1.0]
        );
        let half: Vec<u8> = [1.0f32, -2.0, 0.5, 65504.0]
            .iter()
            .flat_map(|v| half::f16::from_f32(*v).to_le_bytes())
            .collect();
        assert_eq!(decode(F::Rgba16Float, &half, 8, (1, 1)).unwrap(), [1.0, -2.0, 0.5, 65504.0]);
        assert!(decode(
            F::Astc {
                block: wgpu::AstcBlock::B4x4,
                channel: wgpu::AstcChannel::Unorm
            },
            &data,
            12,
            (1, 1)
        )
        .is_err());
    }

    #[test]
    fn eleven_bit_floats_decode() {
        // 1.0 = exponent 15, mantissa 0
        assert_eq!(small_float(15 << 6, 6), 1.0);
        assert_eq!(small_float((16 << 6) | 32, 6), 3.0);
        assert_eq!(small_float(0, 6), 0.0);
        assert!(small_float(31 << 6, 6).is_infinite());
    }
}
