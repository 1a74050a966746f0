//! Read-back: any resource's parts (light instance, layer, mip, history copy) as the last
//! frame left them, for dumps, `verify` and tests.

use super::{Executor, Part};
use crate::error::{Error, Result};
use crate::readback::{self, NonFinite, Raw};
use crate::{pool, Gpu};
use lightbench_scene::io::Image;

impl Executor {
    pub(super) fn entry(&self, name: &str) -> Result<&pool::Entry> {
        self.state.pool.by_name(name).ok_or_else(|| {
            let names: Vec<&str> = self.state.plan.resources.iter().map(|r| r.name.as_str()).collect();
            Error::Resource(format!("`{name}` is not a resource of this plan (resources: {})", names.join(", ")))
        })
    }

    /// Every (instance, layer) of a resource, for dumps: per light and per face.
    pub fn slices(&self, name: &str) -> Result<Vec<(u32, u32)>> {
        let e = self.entry(name)?;
        let layers = e.key.layers();
        Ok((0..e.key.instances).flat_map(|i| (0..layers).map(move |l| (i, l))).collect())
    }

    /// The parity of the frame that was just rendered.
    pub(super) fn last_parity(&self) -> u32 {
        (self.frame_index.wrapping_sub(1) & 1) as u32
    }

    /// The current (last rendered) value of a texture slice.
    pub fn read_texture(&self, gpu: &Gpu, name: &str, instance: u32, layer: u32) -> Result<Image> {
        let tex = self
            .entry(name)?
            .texture(instance, false, self.last_parity())
            .ok_or_else(|| Error::Resource(format!("`{name}` is a buffer; use read_buffer")))?;
        readback::read_texture(gpu, tex, layer)
    }

    /// One mip level of a texture slice, not decoded (see `readback::Raw`).
    pub fn read_texture_raw(&self, gpu: &Gpu, name: &str, (instance, layer): (u32, u32), mip: u32) -> Result<Raw> {
        let tex = self
            .entry(name)?
            .texture(instance, false, self.last_parity())
            .ok_or_else(|| Error::Resource(format!("`{name}` is a buffer; use read_buffer")))?;
        readback::read_texture_raw(gpu, tex, layer, mip)
    }

    /// How many mip levels a resource has (1 for buffers and single-level textures).
    pub fn mips(&self, name: &str) -> Result<u32> {
        Ok(match self.entry(name)?.key.shape {
            lightbench_compiler::plan::ResourceShape::Texture { mips, .. } => mips.max(1),
            _ => 1,
        })
    }

    /// Every part of a resource that holds values: each light instance, layer, mip level
    /// and, for history resources, both copies (`previous`: the one the last frame read).
    pub fn parts(&self, name: &str) -> Result<Vec<Part>> {
        let e = self.entry(name)?;
        let mips = match e.key.shape {
            lightbench_compiler::plan::ResourceShape::Texture { mips, .. } => mips.max(1),
            _ => 1,
        };
        let mut out = vec![];
        for instance in 0..e.key.instances {
            for previous in (0..e.key.copies).map(|c| c == 1) {
                for layer in 0..e.key.layers() {
                    out.extend((0..mips).map(|mip| Part {
                        instance,
                        layer,
                        mip,
                        previous,
                    }));
                }
            }
        }
        Ok(out)
    }

    /// One part of a texture as it is now (see `parts`).
    pub fn read_part(&self, gpu: &Gpu, name: &str, p: Part) -> Result<Image> {
        let tex = self.part_texture(name, p, "; use read_buffer_part")?;
        readback::read_texture_mip(gpu, tex, p.layer, p.mip)
    }

    /// Non-finite values of one part of a texture (see `readback::scan_texture`).
    pub fn scan_part(&self, gpu: &Gpu, name: &str, p: Part) -> Result<Option<NonFinite>> {
        let tex = self.part_texture(name, p, "")?;
        readback::scan_texture(gpu, tex, p.layer, p.mip)
    }

    /// The texture holding part `p` of resource `name`; a buffer is refused (`hint` ends the
    /// message).
    fn part_texture(&self, name: &str, p: Part, hint: &str) -> Result<&wgpu::Texture> {
        self.entry(name)?
            .texture(p.instance, p.previous, self.last_parity())
            .ok_or_else(|| Error::Resource(format!("`{name}` is a buffer{hint}")))
    }

    /// One instance (and copy) of a buffer as it is now, as f32 words.
    pub fn read_buffer_part(&self, gpu: &Gpu, name: &str, p: Part) -> Result<Vec<f32>> {
        let buf = self
            .entry(name)?
            .buffer(p.instance, p.previous, self.last_parity())
            .ok_or_else(|| Error::Resource(format!("`{name}` is a texture")))?;
        readback::read_buffer(gpu, buf)
    }

    /// The current value of a buffer resource as f32 words.
    pub fn read_buffer(&self, gpu: &Gpu, name: &str, instance: u32) -> Result<Vec<f32>> {
        let buf = self
            .entry(name)?
            .buffer(instance, false, self.last_parity())
            .ok_or_else(|| Error::Resource(format!("`{name}` is a texture")))?;
        readback::read_buffer(gpu, buf)
    }
}
