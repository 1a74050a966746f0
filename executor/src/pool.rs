//! GPU resources of a Plan: one texture (or buffer) per instance (per light for per-light
//! resources), two for history resources (this frame and the previous one); with aliasing,
//! transient resources the Plan lets share memory live in one resource's objects. When a new Plan
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
            ResourceShape::Buffer { .. } | ResourceShape::AccelerationStructure => 1,
        }
    }
}

#[derive(Clone)]
pub enum Storage {
    Textures(Vec<wgpu::Texture>),
    Buffers(Vec<wgpu::Buffer>),
    /// The scene's acceleration structure: the scene upload holds it, the pool nothing.
    Scene,
}

#[derive(Clone)]
pub struct Entry {
    pub name: String,
    pub key: Key,
    pub storage: Storage,
    /// The resource whose memory this one lives in (transient aliasing), if another's.
    pub alias_of: Option<String>,
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
            Storage::Buffers(_) | Storage::Scene => None,
        }
    }
    pub fn buffer(&self, instance: u32, prev: bool, parity: u32) -> Option<&wgpu::Buffer> {
        match &self.storage {
            Storage::Buffers(list) => list.get(self.index(instance, prev, parity)),
            Storage::Textures(_) | Storage::Scene => None,
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
    /// The resources of `plan`, sharing unchanged ones with `old`. With `alias`, a transient
    /// resource the Plan lets share another's memory (`PlanResource::shares`) gets that one's
    /// textures or buffers, created with the usages of every resource living in them.
    pub fn build(device: &wgpu::Device, plan: &Plan, old: &Pool, alias: bool) -> Pool {
        let owner = |r: &PlanResource| r.shares.filter(|_| alias).map(|o| o.0 as usize);
        let mut usage: Vec<BTreeSet<Usage>> = plan.resources.iter().map(|r| r.usage.clone()).collect();
        for (i, r) in plan.resources.iter().enumerate() {
            if let Some(o) = owner(r) {
                let own = usage[i].clone();
                usage[o].extend(own);
            }
        }
        let mut pool = Pool::default();
        let mut entries: Vec<Option<Entry>> = vec![None; plan.resources.len()];
        for (i, r) in plan.resources.iter().enumerate().filter(|(_, r)| owner(r).is_none()) {
            let key = Key {
                usage: usage[i].clone(),
                ..Key::of(r)
            };
            // An old entry that lived in another's memory is never taken over.
            let found = old
                .entries
                .iter()
                .find(|e| e.name == r.name && e.key == key && e.alias_of.is_none());
            entries[i] = Some(match found {
                Some(e) => {
                    pool.reused.push(r.name.clone());
                    e.clone()
                }
                None => {
                    pool.created.push(r.name.clone());
                    Entry {
                        name: r.name.clone(),
                        storage: create(device, r, &key),
                        key,
                        alias_of: None,
                    }
                }
            });
        }
        for (i, r) in plan.resources.iter().enumerate() {
            let Some(o) = owner(r) else { continue };
            entries[i] = entries[o].clone().map(|home| Entry {
                name: r.name.clone(),
                alias_of: Some(home.name.clone()),
                ..home
            });
        }
        // Index-aligned with the Plan's resources (every owner was made above).
        pool.entries = entries
            .into_iter()
            .zip(&plan.resources)
            .map(|(e, r)| {
                e.unwrap_or_else(|| Entry {
                    name: r.name.clone(),
                    storage: create(device, r, &Key::of(r)),
                    key: Key::of(r),
                    alias_of: None,
                })
            })
            .collect();
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
        ResourceShape::AccelerationStructure => Storage::Scene,
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
            let usage = convert::usage(&key.usage) | wgpu::TextureUsages::COPY_SRC;
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
