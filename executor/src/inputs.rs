//! External resources (`external: true`): the caller supplies their contents before a frame
//! — a texture from a PNG or EXR, a buffer from raw little-endian bytes or a JSON array of
//! numbers (as f32) (`load_input`); a host's bytes in memory (`supply_input`); or what the
//! host wrote into the resource's own storage itself, with its queue or its encoder
//! (`mark_supplied`) — and resources with `data`, uploaded once. Decoding is the compiler's
//! (`lightbench_compiler::data`), so `check` accepts exactly what is uploaded here.

use super::Executor;
use crate::error::{Error, Result};
use crate::Gpu;
use lightbench_compiler::data::{self, TextureShape};
use lightbench_compiler::plan::{PlanResource, ResourceShape};
use std::path::Path;

impl Executor {
    /// Fill external resource `name` from `file`.
    pub fn load_input(&mut self, gpu: &Gpu, name: &str, file: &Path) -> Result<()> {
        let supply = |error| supply_error("load_input", name, error);
        let res = self.external(name).map_err(supply)?;
        // The file's content (wrong size, format, a number beyond f32): bad input.
        let bad = |e: String| supply(Error::Input(format!("{} {e}", file.display())));
        let raw = lightbench_compiler::vfs::read_bytes(file, lightbench_compiler::vfs::MAX_FILE_BYTES).map_err(|e| Error::io(file, e))?;
        let bytes = match res.shape {
            ResourceShape::Buffer { size, .. } => {
                let b = data::buffer_from_file(file, raw).map_err(bad)?;
                data::check_buffer(b, size).map_err(bad)?
            }
            ResourceShape::Texture {
                format, extent, layers, ..
            } => data::texture_from_file(file, raw, TextureShape { format, extent, layers }).map_err(bad)?,
            ResourceShape::AccelerationStructure => return Err(supply(built_from_the_scene())),
        };
        self.fill(gpu, &res, &bytes)?;
        self.supplied_now(name);
        Ok(())
    }

    /// Fill external resource `name` with the host's `bytes`: a buffer's, or a texture's
    /// texels row by row, layer after layer, tightly packed in its format — exactly the size
    /// the Plan declares (an error names both sizes, as `load_input` does).
    pub fn supply_input(&mut self, gpu: &Gpu, name: &str, bytes: &[u8]) -> Result<()> {
        let supply = |error| supply_error("supply_input", name, error);
        let res = self.external(name).map_err(supply)?;
        // The compiler's rules for a resource's bytes, as for `load_input` and `data`.
        let fits = match res.shape {
            ResourceShape::Buffer { size, .. } => data::check_buffer_size(bytes.len(), size),
            ResourceShape::Texture {
                format, extent, layers, ..
            } => data::check_texels_size(bytes.len(), TextureShape { format, extent, layers }),
            ResourceShape::AccelerationStructure => return Err(supply(built_from_the_scene())),
        };
        fits.map_err(|e| supply(Error::Input(format!("the input {e}"))))?;
        self.fill(gpu, &res, bytes)?;
        self.supplied_now(name);
        Ok(())
    }

    /// External resource `name` holds what the host wrote into its storage itself
    /// (`texture(name)` or `buffer(name)`, with its queue or in its encoder before `encode`):
    /// frames may read it. Its format, size and usages are the Plan's, which wgpu holds the
    /// host's writes to. Storage recreated by a reload must be written and marked again.
    pub fn mark_supplied(&mut self, name: &str) -> Result<()> {
        self.external(name).map_err(|e| supply_error("mark_supplied", name, e))?;
        self.supplied_now(name);
        Ok(())
    }

    /// The Plan's external resource `name`, which a caller may supply: one copy (not per
    /// light), a texture or a buffer.
    fn external(&self, name: &str) -> Result<PlanResource> {
        let res = self
            .plan()
            .resource(name)
            .ok_or_else(|| Error::Request("no such resource".into()))?;
        if !res.external {
            return Err(Error::Request("the resource is not `external: true`".into()));
        }
        if !res.per_light.is_empty() {
            return Err(Error::Request("per-light external resources cannot be supplied yet".into()));
        }
        if matches!(res.shape, ResourceShape::AccelerationStructure) {
            return Err(built_from_the_scene());
        }
        Ok(res.clone())
    }

    fn supplied_now(&mut self, name: &str) {
        self.supplied.insert(name.to_string());
        // New contents: whatever read the old ones runs again.
        self.reuse.reset();
    }

    /// Upload every data resource's `contents` (decoded and checked by the compiler, carried
    /// by the Plan): on creation and after a reload, so an edited data file takes effect.
    pub(super) fn upload_data(&self, gpu: &Gpu) -> Result<()> {
        for r in self.plan().resources.iter().filter(|r| r.data) {
            let bytes = r.contents.as_ref().ok_or_else(|| {
                Error::Plan(format!(
                    "resource `{}` is filled from data, but the Plan carries no `contents`",
                    r.name
                ))
            })?;
            self.fill(gpu, r, bytes)?;
        }
        Ok(())
    }

    /// Write `bytes` (mip 0 of every layer) to every instance and history copy of `res`.
    fn fill(&self, gpu: &Gpu, res: &PlanResource, bytes: &[u8]) -> Result<()> {
        let name = &res.name;
        let entry = self
            .pool()
            .by_name(name)
            .ok_or_else(|| Error::Resource(format!("`{name}` has no storage")))?;
        for instance in 0..res.instances {
            for parity in 0..2 {
                match res.shape {
                    ResourceShape::Buffer { .. } => {
                        if let Some(b) = entry.buffer(instance, false, parity) {
                            gpu.queue.write_buffer(b, 0, bytes);
                        }
                    }
                    ResourceShape::Texture {
                        format, extent, layers, ..
                    } => {
                        if let Some(t) = entry.texture(instance, false, parity) {
                            write_texture(gpu, t, bytes, format.bytes(), extent, layers);
                        }
                    }
                    ResourceShape::AccelerationStructure => {}
                }
            }
        }
        Ok(())
    }
}

fn built_from_the_scene() -> Error {
    Error::Request("an acceleration structure is built from the scene".into())
}

/// `error` from supplying external resource `name` through `call`.
fn supply_error(call: &'static str, name: &str, error: Error) -> Error {
    Error::Supply {
        call,
        name: name.to_string(),
        error: Box::new(error),
    }
}

fn write_texture(gpu: &Gpu, t: &wgpu::Texture, bytes: &[u8], texel: u32, (w, h): (u32, u32), layers: u32) {
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
            depth_or_array_layers: layers,
        },
    );
}
