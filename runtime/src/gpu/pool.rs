//! GPU resources of a Plan: one texture (or buffer) per instance (per light for per-light
//! resources), two for history resources (this frame and the previous one). When a new Plan
//! replaces the running one, resources whose descriptors did not change are kept.

use super::convert;
use lightbench_compiler::plan::{Plan, PlanResource};
use std::collections::HashMap;

/// Everything that decides whether a texture or buffer can be reused.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Key {
    pub kind: String,
    pub format: Option<String>,
    pub extent: (u32, u32),
    pub layers: u32,
    pub mips: u32,
    pub usage: Vec<String>,
    pub instances: u32,
    pub copies: u32,
    pub bytes: u64,
}

impl Key {
    pub fn of(r: &PlanResource) -> Key {
        Key {
            kind: r.kind.clone(),
            format: r.format.clone(),
            extent: r.extent,
            layers: r.layers,
            mips: r.mips,
            usage: r.usage.clone(),
            instances: r.instances.max(1),
            copies: if r.history { 2 } else { 1 },
            bytes: r.bytes,
        }
    }
}

pub enum Storage {
    Textures {
        format: wgpu::TextureFormat,
        list: Vec<wgpu::Texture>,
    },
    Buffers(Vec<wgpu::Buffer>),
}

pub struct Entry {
    pub key: Key,
    pub storage: Storage,
}

impl Entry {
    /// Index of (instance, previous-frame?) in the list, given the frame parity.
    fn index(&self, instance: u32, prev: bool, parity: u32) -> usize {
        let copy = if self.key.copies == 2 { (parity ^ prev as u32) & 1 } else { 0 };
        (instance.min(self.key.instances - 1) * self.key.copies + copy) as usize
    }
    pub fn texture(&self, instance: u32, prev: bool, parity: u32) -> Option<&wgpu::Texture> {
        match &self.storage {
            Storage::Textures { list, .. } => list.get(self.index(instance, prev, parity)),
            Storage::Buffers(_) => None,
        }
    }
    pub fn buffer(&self, instance: u32, prev: bool, parity: u32) -> Option<&wgpu::Buffer> {
        match &self.storage {
            Storage::Buffers(list) => list.get(self.index(instance, prev, parity)),
            Storage::Textures { .. } => None,
        }
    }
}

#[derive(Default)]
pub struct Pool {
    pub entries: HashMap<String, Entry>,
    /// Resources kept from the previous Plan by the last `build` (for tests and logs).
    pub reused: Vec<String>,
}

impl Pool {
    /// Create the resources of `plan`, taking unchanged ones from `old`.
    pub fn build(device: &wgpu::Device, plan: &Plan, mut old: Pool) -> Result<Pool, String> {
        let mut pool = Pool::default();
        for r in &plan.resources {
            let key = Key::of(r);
            if let Some(e) = old.entries.remove(&r.name) {
                if e.key == key {
                    pool.reused.push(r.name.clone());
                    pool.entries.insert(r.name.clone(), e);
                    continue;
                }
            }
            let count = key.instances * key.copies;
            let storage = if r.kind == "buffer" {
                let list = (0..count)
                    .map(|i| {
                        device.create_buffer(&wgpu::BufferDescriptor {
                            label: Some(&format!("{}#{i}", r.name)),
                            size: (r.bytes / count as u64).max(4).div_ceil(4) * 4,
                            usage: wgpu::BufferUsages::STORAGE
                                | wgpu::BufferUsages::UNIFORM
                                | wgpu::BufferUsages::COPY_SRC
                                | wgpu::BufferUsages::COPY_DST,
                            mapped_at_creation: false,
                        })
                    })
                    .collect();
                Storage::Buffers(list)
            } else {
                let format = convert::format(r.format.as_deref().unwrap_or(""))?;
                // Everything can be read back (--dump); external resources are filled by copy.
                let usage = convert::usage(&r.usage) | wgpu::TextureUsages::COPY_SRC;
                let list = (0..count)
                    .map(|i| {
                        device.create_texture(&wgpu::TextureDescriptor {
                            label: Some(&format!("{}#{i}", r.name)),
                            size: wgpu::Extent3d {
                                width: r.extent.0,
                                height: r.extent.1,
                                depth_or_array_layers: r.layers,
                            },
                            mip_level_count: r.mips,
                            sample_count: 1,
                            dimension: wgpu::TextureDimension::D2,
                            format,
                            usage,
                            view_formats: &[],
                        })
                    })
                    .collect();
                Storage::Textures { format, list }
            };
            pool.entries.insert(r.name.clone(), Entry { key, storage });
        }
        Ok(pool)
    }

    pub fn get(&self, name: &str) -> Result<&Entry, String> {
        self.entries
            .get(name)
            .ok_or_else(|| format!("resource `{name}` is not part of the plan"))
    }
}
