//! The scene on the GPU: vertex and index buffers, per-mesh and per-material blocks and
//! textures, ready to be bound in `draw: Scene` passes.

use crate::blocks::{MaterialBlock, MeshBlock};
use crate::error::{Error, Result};
use crate::scene::Scene;
use wgpu::util::DeviceExt;

pub struct MeshGpu {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
    pub block: wgpu::Buffer,
    pub material: usize,
}

pub struct MaterialGpu {
    pub block: wgpu::Buffer,
    /// base colour, normal, metallic-roughness, emissive
    pub textures: [wgpu::TextureView; 4],
}

pub struct SceneGpu {
    pub meshes: Vec<MeshGpu>,
    pub materials: Vec<MaterialGpu>,
    pub sampler: wgpu::Sampler,
}

fn texture_2d(device: &wgpu::Device, queue: &wgpu::Queue, label: &str, w: u32, h: u32, rgba: &[u8], srgb: bool) -> wgpu::TextureView {
    let tex = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: if srgb {
                wgpu::TextureFormat::Rgba8UnormSrgb
            } else {
                wgpu::TextureFormat::Rgba8Unorm
            },
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        rgba,
    );
    tex.create_view(&wgpu::TextureViewDescriptor::default())
}

impl SceneGpu {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Result<SceneGpu> {
        let white = texture_2d(device, queue, "white", 1, 1, &[255, 255, 255, 255], true);
        let white_linear = texture_2d(device, queue, "white_linear", 1, 1, &[255, 255, 255, 255], false);
        let flat_normal = texture_2d(device, queue, "flat_normal", 1, 1, &[128, 128, 255, 255], false);
        let mut textures = vec![];
        for (i, t) in scene.textures.iter().enumerate() {
            if t.rgba.len() != (t.width * t.height * 4) as usize || t.width == 0 || t.height == 0 {
                return Err(Error::Scene(format!(
                    "texture {i} has {} bytes for {}×{}",
                    t.rgba.len(),
                    t.width,
                    t.height
                )));
            }
            textures.push(texture_2d(
                device,
                queue,
                &format!("scene_texture_{i}"),
                t.width,
                t.height,
                &t.rgba,
                t.srgb,
            ));
        }
        let pick = |i: Option<usize>, default: &wgpu::TextureView| i.and_then(|i| textures.get(i)).unwrap_or(default).clone();
        let materials = scene
            .materials
            .iter()
            .map(|m| {
                let block = MaterialBlock {
                    base_color: m.base_color,
                    emissive: [m.emissive[0], m.emissive[1], m.emissive[2], 0.0],
                    metallic: m.metallic,
                    roughness: m.roughness,
                    normal_scale: m.normal_scale,
                    has_normal_map: m.normal_texture.is_some() as u32,
                };
                MaterialGpu {
                    block: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(&m.name),
                        contents: bytemuck::bytes_of(&block),
                        usage: wgpu::BufferUsages::UNIFORM,
                    }),
                    textures: [
                        pick(m.base_color_texture, &white),
                        pick(m.normal_texture, &flat_normal),
                        pick(m.metallic_roughness_texture, &white_linear),
                        pick(m.emissive_texture, &white),
                    ],
                }
            })
            .collect::<Vec<_>>();
        let mut meshes = vec![];
        for m in &scene.meshes {
            if m.material >= materials.len() {
                return Err(Error::Scene(format!(
                    "mesh `{}` uses material {} of {}",
                    m.name,
                    m.material,
                    materials.len()
                )));
            }
            if m.vertices.is_empty() || m.indices.is_empty() {
                continue;
            }
            let normal = m.transform.inverse().transpose();
            let block = MeshBlock {
                model: m.transform.to_cols_array_2d(),
                normal_matrix: normal.to_cols_array_2d(),
            };
            meshes.push(MeshGpu {
                vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&m.name),
                    contents: bytemuck::cast_slice(&m.vertices),
                    usage: wgpu::BufferUsages::VERTEX,
                }),
                indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&m.name),
                    contents: bytemuck::cast_slice(&m.indices),
                    usage: wgpu::BufferUsages::INDEX,
                }),
                index_count: m.drawn_indices(),
                block: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&m.name),
                    contents: bytemuck::bytes_of(&block),
                    usage: wgpu::BufferUsages::UNIFORM,
                }),
                material: m.material,
            });
        }
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("material_sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            address_mode_w: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Ok(SceneGpu {
            meshes,
            materials,
            sampler,
        })
    }
}
