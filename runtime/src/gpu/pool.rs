//! GPU resources of a Plan: one texture (or buffer) per instance (per light for per-light
//! resources), two for history resources (this frame and the previous one). When a new Plan
//! replaces the running one, resources whose descriptors did not change are shared with the
//! old pool (wgpu objects are reference-counted), so the old pool stays whole if the
//! replacement fails.

use super::convert;
use lightbench_compiler::plan::{Plan, PlanResource, ResourceId, ResourceShape, Usage};
use std::collections::BTreeSet;

/// Everything that decides whether a texture or buffer can be reused.
#[derive(Clone, Debug, PartialEq)]
pub struct Key {
    pub shape: ResourceShape,
    pub usage: BTreeSet<Usage>,
    pub instances: u32,
    pub copies: u32,
}

impl Key {
    pub fn of(r: &PlanResource) -> Key {
        Key {
            shape: r.shape.clone(),
            usage: r.usage.clone(),
            instances: r.instances.max(1),
            copies: if r.history { 2 } else { 1 },
        }
    }
    pub fn layers(&self) -> u32 {
        match self.shape {
            ResourceShape::Texture { layers, .. } => layers,
            ResourceShape::Buffer { .. } => 1,
        }
    }
}

#[derive(Clone)]
pub enum Storage {
    Textures(Vec<wgpu::Texture>),
    Buffers(Vec<wgpu::Buffer>),
}

#[derive(Clone)]
pub struct Entry {
    pub name: String,
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
            Storage::Textures(list) => list.get(self.index(instance, prev, parity)),
            Storage::Buffers(_) => None,
        }
    }
    pub fn buffer(&self, instance: u32, prev: bool, parity: u32) -> Option<&wgpu::Buffer> {
        match &self.storage {
            Storage::Buffers(list) => list.get(self.index(instance, prev, parity)),
            Storage::Textures(_) => None,
        }
    }
}

/// The resources of one Plan, indexed like `Plan::resources`.
#[derive(Clone, Default)]
pub struct Pool {
    pub entries: Vec<Entry>,
    /// Resources taken from the previous Plan by the last `build` (for reports and tests).
    pub reused: Vec<String>,
    /// Resources created by the last `build`.
    pub created: Vec<String>,
}

impl Pool {
    /// The resources of `plan`, sharing unchanged ones with `old`.
    pub fn build(device: &wgpu::Device, plan: &Plan, old: &Pool) -> Pool {
        let mut pool = Pool::default();
        for r in &plan.resources {
            let key = Key::of(r);
            if let Some(e) = old.entries.iter().find(|e| e.name == r.name && e.key == key) {
                pool.reused.push(r.name.clone());
                pool.entries.push(e.clone());
                continue;
            }
            pool.created.push(r.name.clone());
            pool.entries.push(Entry {
                name: r.name.clone(),
                storage: create(device, r, &key),
                key,
            });
        }
        pool
    }

    pub fn get(&self, id: ResourceId) -> Option<&Entry> {
        self.entries.get(id.0 as usize)
    }

    pub fn by_name(&self, name: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// History resources swap every frame; without them both parities bind the same.
    pub fn has_history(&self) -> bool {
        self.entries.iter().any(|e| e.key.copies == 2)
    }
}

fn create(device: &wgpu::Device, r: &PlanResource, key: &Key) -> Storage {
    let count = key.instances * key.copies;
    match &r.shape {
        ResourceShape::Buffer { size, .. } => Storage::Buffers(
            (0..count)
                .map(|i| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&format!("{}#{i}", r.name)),
                        size: (*size).max(4).div_ceil(4) * 4,
                        usage: wgpu::BufferUsages::STORAGE
                            | wgpu::BufferUsages::UNIFORM
                            | wgpu::BufferUsages::COPY_SRC
                            | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    })
                })
                .collect(),
        ),
        ResourceShape::Texture {
            format,
            extent,
            layers,
            mips,
            ..
        } => {
            // Everything can be read back (--dump); external resources are filled by copy.
            let usage = convert::usage(&r.usage) | wgpu::TextureUsages::COPY_SRC;
            Storage::Textures(
                (0..count)
                    .map(|i| {
                        device.create_texture(&wgpu::TextureDescriptor {
                            label: Some(&format!("{}#{i}", r.name)),
                            size: wgpu::Extent3d {
                                width: extent.0,
                                height: extent.1,
                                depth_or_array_layers: *layers,
                            },
                            mip_level_count: *mips,
                            sample_count: 1,
                            dimension: wgpu::TextureDimension::D2,
                            format: convert::format(*format),
                            usage,
                            view_formats: &[],
                        })
                    })
                    .collect(),
            )
        }
    }
}
