//! Scene upload, tables: per-triangle records as the texels of a `texture_2d_array<u32>`
//! (16 bytes each), row after row, layer after layer, as `shaders/lib/hit.wgsl`'s
//! `table_texel` reads them. A texture is not bounded by the storage-binding size (128 MiB
//! on many devices, 2 M triangles of ray-hit data) but by its dimensions and layer count,
//! which hold tens of millions of triangles.

use crate::error::{Error, Result};

/// Texels per row and rows per layer at most: a layer is then 64 MiB, so a table's last,
/// partly filled layer wastes little.
const SIDE: u32 = 2048;
const TEXEL: u64 = 16;

/// A table's width, rows per layer and layers (at least `min_layers`) for `texels` texels
/// within the device's `max_texture_dimension_2d` (`max_side`); the layers may exceed the
/// device's count (the caller refuses that, naming the limit).
fn shape(texels: u64, max_side: u32, min_layers: u64) -> (u32, u32, u64) {
    let side = SIDE.min(max_side).max(1) as u64;
    let texels = texels.max(1);
    let width = side.min(texels);
    let rows = texels.div_ceil(width);
    let height = rows.min(side);
    (width as u32, height as u32, rows.div_ceil(height).max(min_layers))
}

/// `records` (each a whole number of texels) as a table texture, labelled `label`; `what`
/// names them in the error that refuses a table over the device's layer count or memory.
pub fn texel_table<T: bytemuck::Pod>(
    gpu: (&wgpu::Device, &wgpu::Queue),
    label: &str,
    what: impl Fn() -> String,
    records: &[T],
) -> Result<wgpu::TextureView> {
    let (device, queue) = gpu;
    debug_assert_eq!(std::mem::size_of::<T>() as u64 % TEXEL, 0);
    let bytes: &[u8] = bytemuck::cast_slice(records);
    let limits = device.limits();
    let texels = bytes.len() as u64 / TEXEL;
    // wgpu's GL backend makes a texture of one layer a `TEXTURE_2D`, which no array view can
    // read: there a second (empty) layer makes it an array.
    let min_layers = if device.adapter_info().backend == wgpu::Backend::Gl { 2 } else { 1 };
    let (width, height, layers) = shape(texels, limits.max_texture_dimension_2d, min_layers);
    if layers > limits.max_texture_array_layers as u64 {
        return Err(Error::scene(format!(
            "{} needs {layers} layers of {width}×{height} texels ({:.1} MiB), over this device's max_texture_array_layers of {}",
            what(),
            bytes.len() as f64 / (1024.0 * 1024.0),
            limits.max_texture_array_layers
        )));
    }
    let scope = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: layers as u32,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba32Uint,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(Error::scene(format!(
            "{} needs a texture of {:.1} MiB, which this device could not allocate: {e}",
            what(),
            bytes.len() as f64 / (1024.0 * 1024.0)
        )));
    }
    upload(queue, &texture, bytes, (width, height));
    Ok(texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    }))
}

/// Write `bytes` into the table: each layer's whole rows, then the last row's texels. Each
/// layer is submitted as it is written, so that no more than one layer waits in staging.
fn upload(queue: &wgpu::Queue, texture: &wgpu::Texture, bytes: &[u8], (width, height): (u32, u32)) {
    let row = width as usize * TEXEL as usize;
    let layer = row * height as usize;
    let whole_rows = bytes.len() / row;
    let write = |at: usize, (x, y, z): (u32, u32, u32), (w, h): (u32, u32)| {
        let len = w as usize * h as usize * TEXEL as usize;
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d { x, y, z },
                aspect: wgpu::TextureAspect::All,
            },
            &bytes[at..at + len],
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w * TEXEL as u32),
                rows_per_image: Some(h),
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        queue.submit([]);
    };
    for (z, first) in (0..whole_rows).step_by(height as usize).enumerate() {
        let rows = (whole_rows - first).min(height as usize) as u32;
        write(z * layer, (0, 0, z as u32), (width, rows));
    }
    let tail = bytes.len() - whole_rows * row;
    if tail > 0 {
        let (z, y) = (whole_rows / height as usize, whole_rows % height as usize);
        write(whole_rows * row, (0, y as u32, z as u32), ((tail / TEXEL as usize) as u32, 1));
    }
}

#[cfg(test)]
mod tests {
    use super::shape;

    /// Small tables are one row; larger ones whole rows of 2048 texels (or the device's side),
    /// then layers of as many rows.
    #[test]
    fn tables_are_shaped_in_rows_then_layers() {
        assert_eq!(shape(0, 8192, 1), (1, 1, 1));
        assert_eq!(shape(12, 8192, 1), (12, 1, 1));
        assert_eq!(shape(2049, 8192, 1), (2048, 2, 1));
        assert_eq!(shape(2048 * 2048, 8192, 1), (2048, 2048, 1));
        assert_eq!(shape(2048 * 2048 + 1, 8192, 1), (2048, 2048, 2));
        // 16 M triangles of 4 texels: 16 layers of 64 MiB.
        assert_eq!(shape(4 << 24, 16384, 1), (2048, 2048, 16));
        // A device of 64-texel sides: layers of 64 × 64.
        assert_eq!(shape(64 * 64 * 3 + 5, 64, 1), (64, 64, 4));
        // GL's at least two layers.
        assert_eq!(shape(12, 8192, 2), (12, 1, 2));
        assert_eq!(shape(64 * 64 * 3 + 5, 64, 2), (64, 64, 4));
    }
}
