//! Scene upload, tables: per-triangle records as the texels of a `texture_2d_array<u32>`
//! (16 bytes each), row after row, layer after layer, as `shaders/lib/table.wgsl`'s
//! `table_texel` reads them: its width and rows per layer are powers of two, so that a texel's
//! place is found by shifts and masks (integer division is slow where a driver runs shaders
//! in SIMD lanes on a CPU). A texture is not bounded by the storage-binding size (128 MiB
//! on many devices, 2 M triangles of ray-hit data) but by its dimensions and layer count,
//! which hold tens of millions of triangles.

use crate::error::{Error, Result};

/// Texels per row and rows per layer at most: a layer is then 64 MiB, so a table's last,
/// partly filled layer (or rows up to a power of two) waste little.
const SIDE: u32 = 2048;
const TEXEL: u64 = 16;

/// A table's width, rows per layer (both powers of two) and layers (at least `min_layers`)
/// for `texels` texels within the device's `max_texture_dimension_2d` (`max_side`); the
/// layers may exceed the device's count (the caller refuses that, naming the limit).
fn shape(texels: u64, max_side: u32, min_layers: u64) -> (u32, u32, u64) {
    let side = 1u64 << SIDE.min(max_side).max(16).ilog2();
    let texels = texels.max(1);
    // At least 16 texels (256 bytes, as buffer-to-texture copies want rows).
    let width = side.min(texels.next_power_of_two().max(16));
    let rows = texels.div_ceil(width);
    let height = side.min(rows.next_power_of_two());
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
    debug_assert_eq!(std::mem::size_of::<T>() as u64 % TEXEL, 0);
    let bytes: &[u8] = bytemuck::cast_slice(records);
    let (texture, shape) = new_table(gpu.0, label, &what, bytes.len() as u64)?;
    upload(gpu.1, &texture, bytes, shape);
    Ok(array_view(&texture))
}

/// The bytes of the buffer `texel_table_from_gpu` stages a table of `bytes` in: its whole rows
/// (which the caller checks against the device's `max_buffer_size`).
pub fn staged_size(device: &wgpu::Device, bytes: u64) -> u64 {
    let (width, _, _) = shape(bytes / TEXEL, device.limits().max_texture_dimension_2d, 1);
    (bytes / TEXEL).max(1).div_ceil(width as u64) * width as u64 * TEXEL
}

/// A table of `bytes` filled on the GPU: `fill` records its copies into a buffer of the
/// table's whole rows (`staged_size`; `COPY_DST`, its bytes past `bytes` unused), which is
/// then copied in.
pub fn texel_table_from_gpu(
    gpu: (&wgpu::Device, &wgpu::Queue),
    label: &str,
    what: impl Fn() -> String,
    bytes: u64,
    fill: impl FnOnce(&mut wgpu::CommandEncoder, &wgpu::Buffer),
) -> Result<wgpu::TextureView> {
    let (device, queue) = gpu;
    let (texture, (width, height)) = new_table(device, label, &what, bytes)?;
    let row = width as u64 * TEXEL;
    let rows = (bytes / TEXEL).max(1).div_ceil(width as u64);
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: rows * row,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
    fill(&mut enc, &staging);
    for (z, first) in (0..rows).step_by(height as usize).enumerate() {
        let layer_rows = (rows - first).min(height as u64) as u32;
        enc.copy_buffer_to_texture(
            wgpu::TexelCopyBufferInfo {
                buffer: &staging,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: first * row,
                    bytes_per_row: Some(row as u32),
                    rows_per_image: Some(layer_rows),
                },
            },
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d { x: 0, y: 0, z: z as u32 },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::Extent3d {
                width,
                height: layer_rows,
                depth_or_array_layers: 1,
            },
        );
    }
    queue.submit([enc.finish()]);
    Ok(array_view(&texture))
}

/// An empty table for `bytes` and its width and rows per layer, within the device's limits.
fn new_table(device: &wgpu::Device, label: &str, what: &dyn Fn() -> String, bytes: u64) -> Result<(wgpu::Texture, (u32, u32))> {
    let limits = device.limits();
    // wgpu's GL backend makes a texture of one layer a `TEXTURE_2D`, which no array view can
    // read: there a second (empty) layer makes it an array.
    let min_layers = if device.adapter_info().backend == wgpu::Backend::Gl { 2 } else { 1 };
    let (width, height, layers) = shape(bytes / TEXEL, limits.max_texture_dimension_2d, min_layers);
    let mib = bytes as f64 / (1024.0 * 1024.0);
    if layers > limits.max_texture_array_layers as u64 {
        return Err(Error::scene(format!(
            "{} needs {layers} layers of {width}×{height} texels ({mib:.1} MiB), over this device's max_texture_array_layers of {}",
            what(),
            limits.max_texture_array_layers
        )));
    }
    // A texture is one allocation, bounded by the device's largest (Vulkan's
    // `maxMemoryAllocationSize`, which wgpu's `max_buffer_size` does not exceed; 2 GiB on
    // Mesa's drivers). wgpu has no limit of its own on a texture's bytes, and what a driver
    // does past its largest allocation is not for a user's scene to find out.
    let texture_bytes = width as u64 * height as u64 * layers * TEXEL;
    if texture_bytes > limits.max_buffer_size {
        return Err(Error::scene(format!(
            "{} needs a texture of {:.1} MiB ({width}×{height}×{layers} texels), over this device's largest allocation (max_buffer_size) of {:.1} MiB",
            what(),
            texture_bytes as f64 / (1024.0 * 1024.0),
            limits.max_buffer_size as f64 / (1024.0 * 1024.0)
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
            "{} needs a texture of {mib:.1} MiB, which this device could not allocate: {e}",
            what()
        )));
    }
    Ok((texture, (width, height)))
}

fn array_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
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

    /// Small tables are one row (of a power of two, at least 16 texels); larger ones rows of
    /// 2048 texels (or the device's side, down to a power of two), as many as a power of two
    /// holds in one layer, then layers of 2048 rows.
    #[test]
    fn tables_are_shaped_in_rows_then_layers() {
        assert_eq!(shape(0, 8192, 1), (16, 1, 1));
        assert_eq!(shape(12, 8192, 1), (16, 1, 1));
        assert_eq!(shape(17, 8192, 1), (32, 1, 1));
        assert_eq!(shape(2049, 8192, 1), (2048, 2, 1));
        assert_eq!(shape(2048 * 5, 8192, 1), (2048, 8, 1));
        assert_eq!(shape(2048 * 2048, 8192, 1), (2048, 2048, 1));
        assert_eq!(shape(2048 * 2048 + 1, 8192, 1), (2048, 2048, 2));
        // 16 M triangles of 4 texels: 16 layers of 64 MiB.
        assert_eq!(shape(4 << 24, 16384, 1), (2048, 2048, 16));
        // A device of 64-texel sides: layers of 64 × 64; of 1000: 512 × 512.
        assert_eq!(shape(64 * 64 * 3 + 5, 64, 1), (64, 64, 4));
        assert_eq!(shape(512 * 512 + 1, 1000, 1), (512, 512, 2));
        // GL's at least two layers.
        assert_eq!(shape(12, 8192, 2), (16, 1, 2));
        assert_eq!(shape(64 * 64 * 3 + 5, 64, 2), (64, 64, 4));
    }
}
