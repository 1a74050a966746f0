//! The scene on the GPU: vertex and index buffers, per-mesh and per-material blocks and
//! textures, ready to be bound in `draw: Scene` passes.

use crate::error::{Error, Result};
use lightbench_compiler::abi::{AreaLightBlock, HitMaterial, MaterialBlock, MeshBlock, NO_MAP};
use lightbench_scene::io::{linear_to_srgb, srgb_to_linear};
use lightbench_scene::{AlphaMode, Material, SamplerDesc, Scene, Wrap};
use wgpu::util::DeviceExt;

pub struct MeshGpu {
    /// Its index in the scene's meshes.
    pub source: usize,
    /// Its vertices' and indices' content (`content_key`): an upload of a new scene keeps
    /// the buffers of a mesh with the same key.
    pub key: u128,
    pub name: String,
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
    pub vertex_count: u32,
    /// Model to world (the acceleration structure places the mesh's BLAS with it).
    pub transform: glam::Mat4,
    pub block: wgpu::Buffer,
    pub material: usize,
    /// Its material blends (alphaMode BLEND): drawn by `draw: Transparent` passes only.
    pub blend: bool,
    /// World-space centre of its bounds, for sorting blended meshes.
    pub centre: glam::Vec3,
}

/// The meshes each kind of scene draw draws, in order, for one frame's camera.
pub struct DrawOrder {
    /// `draw: Scene`: opaque and masked meshes, in scene order.
    pub opaque: Vec<usize>,
    /// `draw: Transparent`: blended meshes from far to near ("over" blending needs it).
    pub back_to_front: Vec<usize>,
}

pub struct MaterialGpu {
    pub block: wgpu::Buffer,
    /// base colour, normal, metallic-roughness, emissive, occlusion
    pub textures: [wgpu::TextureView; 5],
    /// Index into `SceneGpu::samplers`.
    pub sampler: usize,
}

pub struct SceneGpu {
    pub meshes: Vec<MeshGpu>,
    pub materials: Vec<MaterialGpu>,
    /// One per distinct material sampler.
    pub samplers: Vec<wgpu::Sampler>,
    /// The opaque and masked triangles drawn: what `draw: Triangles(n)` instances and the
    /// standard `triangles` binding holds (built apart, by `triangles`, only for a Plan that
    /// binds it).
    pub triangle_count: u32,
    /// The standard `area_lights` binding: the emissive triangles (one zero-radiance entry when
    /// there are none: a binding cannot be empty), at most `MAX_AREA_LIGHTS`.
    pub area_lights: wgpu::Buffer,
    /// Emissive triangles left out over the limit (the dimmest), for a note to the user.
    pub area_lights_dropped: usize,
    /// The standard `light_volumes` binding and the range each light's volume takes in it.
    pub light_volumes: wgpu::Buffer,
    pub volumes: super::light_volumes::LightVolumes,
    /// Each material as ray hits shade it (`hit_materials` of the acceleration structure).
    pub hit_materials: Vec<HitMaterial>,
    /// The scene's textures, in the scene's order (what `hit_maps` copies level 0 of), each
    /// with its content key and its mean (linear).
    pub textures: Vec<wgpu::Texture>,
    texture_keys: Vec<u128>,
    means: Vec<[f32; 4]>,
    /// What this upload took over from the scene uploaded before it (`SceneGpu::reusing`).
    pub kept: Kept,
}

/// What an upload took over, unchanged, from the scene on the GPU before it: the meshes whose
/// vertex and index buffers stayed resident, the textures (with their mips), and — where the
/// acceleration structure was built — its bottom levels, each as (kept, of how many); and,
/// where a reloader loaded the scene again, its models taken as the last load left them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Kept {
    pub meshes: (usize, usize),
    pub textures: (usize, usize),
    pub blas: Option<(usize, usize)>,
    pub models: Option<(usize, usize)>,
}

/// A content key: XXH3-128 over the parts, each with its length.
pub fn content_key(parts: &[&[u8]]) -> u128 {
    let mut h = xxhash_rust::xxh3::Xxh3::new();
    for p in parts {
        h.update(&(p.len() as u64).to_le_bytes());
        h.update(p);
    }
    h.digest128()
}

/// A texture with its full mip chain, made on the CPU by 2×2 box filtering (in linear light
/// for sRGB data, so that mips do not darken), and its mean in linear values (its 1×1 level:
/// what ray hits read for the map). Takes the texels: a decoded level 0 is extended in place (a
/// mapped cache entry's is copied once).
fn texture_2d(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    w: u32,
    h: u32,
    rgba: Vec<u8>,
    srgb: bool,
) -> (wgpu::TextureView, [f32; 4]) {
    let (levels, data) = mip_chain(w, h, rgba, srgb);
    let last = &data[data.len().saturating_sub(4)..];
    let mean: [f32; 4] = std::array::from_fn(|c| {
        let v = last.get(c).copied().unwrap_or(255) as f32 / 255.0;
        if srgb && c < 3 {
            srgb_to_linear(v)
        } else {
            v
        }
    });
    let tex = device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: if srgb {
                wgpu::TextureFormat::Rgba8UnormSrgb
            } else {
                wgpu::TextureFormat::Rgba8Unorm
            },
            // Copied from where ray hits look maps up (`accel::maps`).
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &data,
    );
    (tex.create_view(&wgpu::TextureViewDescriptor::default()), mean)
}

/// Every mip level down to 1×1, concatenated (level 0 first, as the upload wants them):
/// the level count and the texels. Level 0 is the input, extended in place.
pub fn mip_chain(w: u32, h: u32, mut data: Vec<u8>, srgb: bool) -> (u32, Vec<u8>) {
    let decode = |v: u8, c: usize| {
        if srgb && c < 3 {
            srgb_to_linear(v as f32 / 255.0)
        } else {
            v as f32 / 255.0
        }
    };
    let encode = |v: f32, c: usize| ((if srgb && c < 3 { linear_to_srgb(v) } else { v }).clamp(0.0, 1.0) * 255.0).round() as u8;
    let (mut pw, mut ph, mut start, mut levels) = (w as usize, h as usize, 0usize, 1u32);
    // The whole chain is at most 4/3 of level 0: reserve it once instead of growing.
    data.reserve(data.len() / 3 + 64);
    while pw > 1 || ph > 1 {
        let (nw, nh) = ((pw / 2).max(1), (ph / 2).max(1));
        let next_start = data.len();
        for y in 0..nh {
            for x in 0..nw {
                for c in 0..4 {
                    let at = |xx: usize, yy: usize| decode(data[start + (yy.min(ph - 1) * pw + xx.min(pw - 1)) * 4 + c], c);
                    let sum = at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) + at(2 * x + 1, 2 * y + 1);
                    let v = encode(sum / 4.0, c);
                    data.push(v);
                }
            }
        }
        (pw, ph, start, levels) = (nw, nh, next_start, levels + 1);
    }
    (levels, data)
}

fn sampler(device: &wgpu::Device, d: &SamplerDesc) -> wgpu::Sampler {
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => wgpu::AddressMode::Repeat,
        Wrap::Clamp => wgpu::AddressMode::ClampToEdge,
        Wrap::Mirror => wgpu::AddressMode::MirrorRepeat,
    };
    let filter = |linear: bool| {
        if linear {
            wgpu::FilterMode::Linear
        } else {
            wgpu::FilterMode::Nearest
        }
    };
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("material_sampler"),
        address_mode_u: wrap(d.wrap[0]),
        address_mode_v: wrap(d.wrap[1]),
        address_mode_w: wgpu::AddressMode::Repeat,
        mag_filter: filter(d.mag_linear),
        min_filter: filter(d.min_linear),
        mipmap_filter: if d.mip_linear {
            wgpu::MipmapFilterMode::Linear
        } else {
            wgpu::MipmapFilterMode::Nearest
        },
        ..Default::default()
    })
}

/// Every texture with its mip chain, each dropped on the CPU once uploaded (or taken over
/// from `previous` where it holds the same texels), each one's content key and mean, and how
/// many were taken over.
struct Uploaded {
    views: Vec<wgpu::TextureView>,
    keys: Vec<u128>,
    means: Vec<[f32; 4]>,
    kept: usize,
}

fn upload_textures(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    images: Vec<lightbench_scene::ImageData>,
    previous: Option<&SceneGpu>,
) -> Result<Uploaded> {
    let mut up = Uploaded {
        views: vec![],
        keys: vec![],
        means: vec![],
        kept: 0,
    };
    for (i, t) in images.into_iter().enumerate() {
        if t.rgba.len() != (t.width * t.height * 4) as usize || t.width == 0 || t.height == 0 {
            return Err(Error::scene(format!(
                "texture {i} has {} bytes for {}×{}",
                t.rgba.len(),
                t.width,
                t.height
            )));
        }
        let header = [t.width.to_le_bytes(), t.height.to_le_bytes(), (t.srgb as u32).to_le_bytes()].concat();
        let key = content_key(&[&header, &t.rgba]);
        up.keys.push(key);
        if let Some((tex, mean)) = previous.and_then(|p| p.texture_with(key)) {
            up.views.push(tex.create_view(&wgpu::TextureViewDescriptor::default()));
            up.means.push(mean);
            up.kept += 1;
            continue;
        }
        let (view, mean) = texture_2d(
            device,
            queue,
            &format!("scene_texture_{i}"),
            t.width,
            t.height,
            t.rgba.into_vec(),
            t.srgb,
        );
        up.views.push(view);
        up.means.push(mean);
        // Flush the upload's staging copy before the next texture, so that staging for every
        // texture is never held at once.
        queue.submit(std::iter::empty());
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::gpu("uploading scene textures", e))?;
    }
    Ok(up)
}

/// Material blocks and texture views (defaults for absent maps), and the distinct samplers
/// the materials index.
fn materials(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    list: &[Material],
    textures: &[wgpu::TextureView],
) -> (Vec<MaterialGpu>, Vec<SamplerDesc>) {
    let white = texture_2d(device, queue, "white", 1, 1, vec![255, 255, 255, 255], true).0;
    let white_linear = texture_2d(device, queue, "white_linear", 1, 1, vec![255, 255, 255, 255], false).0;
    let flat_normal = texture_2d(device, queue, "flat_normal", 1, 1, vec![128, 128, 255, 255], false).0;
    let pick = |i: Option<usize>, default: &wgpu::TextureView| i.and_then(|i| textures.get(i)).unwrap_or(default).clone();
    let mut descs: Vec<SamplerDesc> = vec![];
    let out = list
        .iter()
        .map(|m| {
            let sampler = descs.iter().position(|d| *d == m.sampler).unwrap_or_else(|| {
                descs.push(m.sampler);
                descs.len() - 1
            });
            MaterialGpu {
                sampler,
                block: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&m.name),
                    contents: bytemuck::bytes_of(&material_block(m)),
                    usage: wgpu::BufferUsages::UNIFORM,
                }),
                textures: [
                    pick(m.base_color_texture, &white),
                    pick(m.normal_texture, &flat_normal),
                    pick(m.metallic_roughness_texture, &white_linear),
                    pick(m.emissive_texture, &white),
                    pick(m.occlusion_texture, &white_linear),
                ],
            }
        })
        .collect();
    (out, descs)
}

/// Vertex, index and mesh-block buffers of every non-empty mesh (inputs of the acceleration
/// structure's build too, where the device traces rays); a mesh `previous` holds with the same
/// vertices and indices keeps its buffers there. Also how many were kept so.
fn meshes(device: &wgpu::Device, scene: &Scene, previous: Option<&SceneGpu>) -> Result<(Vec<MeshGpu>, usize)> {
    let traced = match device.features().contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY) {
        true => wgpu::BufferUsages::BLAS_INPUT,
        false => wgpu::BufferUsages::empty(),
    };
    let buffer = |label: &str, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    };
    let (mut out, mut kept) = (vec![], 0);
    for (index, m) in scene.meshes.iter().enumerate() {
        let Some(material) = scene.materials.get(m.material) else {
            return Err(Error::scene(format!(
                "mesh `{}` uses material {} of {}",
                m.name,
                m.material,
                scene.materials.len()
            )));
        };
        if m.vertices.is_empty() || m.indices.is_empty() {
            continue;
        }
        let of = |what: &str| format!("mesh `{}` of scene `{}`: its {what}", m.name, scene.name);
        check_buffer(device, || of("vertex buffer"), std::mem::size_of_val(&m.vertices[..]) as u64, false)?;
        check_buffer(device, || of("index buffer"), std::mem::size_of_val(&m.indices[..]) as u64, false)?;
        let block = MeshBlock {
            model: m.transform.to_cols_array_2d(),
            normal_matrix: m.transform.inverse().transpose().to_cols_array_2d(),
        };
        let key = content_key(&[bytemuck::cast_slice(&m.vertices), bytemuck::cast_slice(&m.indices)]);
        let resident = previous.and_then(|p| p.meshes.iter().find(|g| g.key == key));
        kept += resident.is_some() as usize;
        let (vertices, indices) = match resident {
            Some(g) => (g.vertices.clone(), g.indices.clone()),
            None => (
                buffer(&m.name, bytemuck::cast_slice(&m.vertices), wgpu::BufferUsages::VERTEX | traced),
                buffer(&m.name, bytemuck::cast_slice(&m.indices), wgpu::BufferUsages::INDEX | traced),
            ),
        };
        out.push(MeshGpu {
            source: index,
            key,
            name: m.name.clone(),
            vertices,
            indices,
            index_count: m.drawn_indices(),
            vertex_count: m.vertices.len() as u32,
            transform: m.transform,
            block: buffer(&m.name, bytemuck::bytes_of(&block), wgpu::BufferUsages::UNIFORM),
            material: m.material,
            blend: material.alpha == AlphaMode::Blend,
            centre: mesh_centre(m),
        });
    }
    Ok((out, kept))
}

/// The drawn triangles of the meshes `draw: Scene` draws (opaque and masked ones).
fn drawn_triangles(scene: &Scene) -> impl Iterator<Item = (&lightbench_scene::Mesh, &[u32])> {
    scene
        .meshes
        .iter()
        .filter(|m| scene.materials.get(m.material).is_some_and(|mat| mat.alpha != AlphaMode::Blend))
        .map(|m| (m, &m.indices[..(m.drawn_indices() as usize).min(m.indices.len()) / 3 * 3]))
}

/// How many triangles the standard `triangles` binding holds.
pub fn triangle_count(scene: &Scene) -> u64 {
    drawn_triangles(scene).map(|(_, drawn)| drawn.len() as u64 / 3).sum()
}

/// Refuse a buffer of `bytes` over the device's `max_buffer_size` (and, bound as storage,
/// its `max_storage_buffer_binding_size`), naming what it would hold and the limit: wgpu
/// would make an invalid buffer whose first use fails far from here.
pub fn check_buffer(device: &wgpu::Device, what: impl FnOnce() -> String, bytes: u64, storage: bool) -> Result<()> {
    let l = device.limits();
    let (max, limit) = match storage && l.max_storage_buffer_binding_size < l.max_buffer_size {
        true => (l.max_storage_buffer_binding_size, "max_storage_buffer_binding_size"),
        false => (l.max_buffer_size, "max_buffer_size"),
    };
    if bytes <= max {
        return Ok(());
    }
    let mib = |b: u64| b as f64 / (1024.0 * 1024.0);
    Err(Error::scene(format!(
        "{} needs {:.1} MiB ({bytes} bytes), over this device's {limit} of {:.1} MiB",
        what(),
        mib(bytes),
        mib(max)
    )))
}

/// The standard `triangles` binding: world-space corners of the triangles `draw: Scene` draws,
/// 3 `vec4` (w: 1) each, as a table of texels (`shaders/lib/table.wgsl`); one zeroed triangle
/// when there are none. Within the device's texture limits, or an error naming them.
pub fn triangles(gpu: (&wgpu::Device, &wgpu::Queue), scene: &Scene) -> Result<wgpu::TextureView> {
    let count = triangle_count(scene);
    let mut corners: Vec<[f32; 4]> = Vec::with_capacity(count as usize * 3);
    for (m, drawn) in drawn_triangles(scene) {
        for t in drawn.chunks_exact(3) {
            let c: Option<Vec<_>> = t.iter().map(|&i| m.vertices.get(i as usize)).collect();
            match c {
                Some(c) => corners.extend(
                    c.iter()
                        .map(|v| m.transform.transform_point3(glam::Vec3::from(v.position)).extend(1.0).to_array()),
                ),
                // A corner past the vertices: a zero-area triangle keeps the count.
                None => corners.extend([[0.0; 4]; 3]),
            }
        }
    }
    if corners.is_empty() {
        corners = vec![[0.0; 4]; 3];
    }
    let what = || format!("scene `{}`: the `triangles` binding of its {count} drawn triangles", scene.name);
    super::texel_table::texel_table(gpu, "scene triangles", what, &corners)
}

/// Area lights past this many emissive triangles are left out (the least powerful): each
/// costs every pixel of an area-light pass its closed-form integral.
pub const MAX_AREA_LIGHTS: usize = 1024;

/// The scene's emissive triangles as area lights (emissive factor × strength × the emissive
/// map's mean over the triangle: an area light's radiance is uniform), most powerful first, at
/// most `MAX_AREA_LIGHTS`; and how many were left out.
pub fn area_lights(scene: &Scene) -> (Vec<AreaLightBlock>, usize) {
    let mut out: Vec<(f32, AreaLightBlock)> = vec![];
    for m in &scene.meshes {
        if !lightbench_scene::emitter_lights::emits(scene, m) {
            continue;
        }
        let mat = &scene.materials[m.material];
        let drawn = &m.indices[..(m.drawn_indices() as usize).min(m.indices.len())];
        for t in drawn.chunks_exact(3) {
            let corner = |i: u32| {
                m.vertices
                    .get(i as usize)
                    .map(|v| m.transform.transform_point3(glam::Vec3::from(v.position)))
            };
            let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) else {
                continue;
            };
            let area = 0.5 * (b - a).cross(c - a).length();
            let map = emissive_mean(scene, m, mat, t);
            let e: [f32; 3] = std::array::from_fn(|k| mat.emissive[k] * map[k]);
            let power = area * (e[0] + e[1] + e[2]);
            let block = AreaLightBlock {
                corners: [a.extend(1.0).to_array(), b.extend(1.0).to_array(), c.extend(1.0).to_array()],
                radiance: [e[0], e[1], e[2], mat.double_sided as u32 as f32],
            };
            if power > 0.0 && power.is_finite() {
                out.push((power, block));
            }
        }
    }
    out.sort_by(|a, b| b.0.total_cmp(&a.0));
    let dropped = out.len().saturating_sub(MAX_AREA_LIGHTS);
    out.truncate(MAX_AREA_LIGHTS);
    (out.into_iter().map(|(_, b)| b).collect(), dropped)
}

/// The emissive map's mean over triangle `t` in linear RGB (1 without a map): the texels
/// nearest ten points spread evenly over it (UV set, transform and repeat as the material
/// says; sRGB decoded).
fn emissive_mean(scene: &Scene, m: &lightbench_scene::Mesh, mat: &Material, t: &[u32]) -> [f32; 3] {
    let Some(img) = mat.emissive_texture.and_then(|i| scene.textures.get(i)) else {
        return [1.0; 3];
    };
    let second = (mat.uv_sets >> 3) & 1 == 1;
    let uv = |i: u32| {
        m.vertices
            .get(i as usize)
            .map(|v| glam::Vec2::from(if second { v.uv1 } else { v.uv }))
    };
    let (Some(u0), Some(u1), Some(u2)) = (uv(t[0]), uv(t[1]), uv(t[2])) else {
        return [1.0; 3];
    };
    let [r0, r1] = mat.uv_transform;
    let (w, h) = (img.width.max(1) as f32, img.height.max(1) as f32);
    let mut sum = [0.0f32; 3];
    let mut n = 0.0;
    for i in 0..4 {
        for j in 0..4 - i {
            let (a, b) = ((i as f32 + 1.0 / 3.0) / 4.0, (j as f32 + 1.0 / 3.0) / 4.0);
            let p = u0 * (1.0 - a - b) + u1 * a + u2 * b;
            let q = glam::Vec2::new(r0[0] * p.x + r0[1] * p.y + r0[2], r1[0] * p.x + r1[1] * p.y + r1[2]);
            let (x, y) = ((q.x.rem_euclid(1.0) * w) as usize, (q.y.rem_euclid(1.0) * h) as usize);
            let at = (y.min(h as usize - 1) * w as usize + x.min(w as usize - 1)) * 4;
            for (k, s) in sum.iter_mut().enumerate() {
                let v = img.rgba.get(at + k).copied().unwrap_or(255) as f32 / 255.0;
                *s += if img.srgb { srgb_to_linear(v) } else { v };
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

/// World-space centre of a mesh's bounding box.
fn mesh_centre(m: &lightbench_scene::Mesh) -> glam::Vec3 {
    let (lo, hi) = m
        .vertices
        .iter()
        .fold((glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN)), |(lo, hi), v| {
            let p = glam::Vec3::from(v.position);
            (lo.min(p), hi.max(p))
        });
    m.transform.transform_point3((lo + hi) * 0.5)
}

impl SceneGpu {
    pub fn draw_order(&self, eye: glam::Vec3) -> DrawOrder {
        let opaque = (0..self.meshes.len()).filter(|&i| !self.meshes[i].blend).collect();
        let mut back_to_front: Vec<usize> = (0..self.meshes.len()).filter(|&i| self.meshes[i].blend).collect();
        let dist = |i: usize| (self.meshes[i].centre - eye).length_squared();
        back_to_front.sort_by(|&a, &b| dist(b).total_cmp(&dist(a)));
        DrawOrder { opaque, back_to_front }
    }
}

/// What ray hits shade with: each map stands in by its mean (`means`, linear, by texture).
fn hit_material(m: &Material, means: &[[f32; 4]]) -> HitMaterial {
    let mean = |t: Option<usize>| t.and_then(|i| means.get(i)).copied().unwrap_or([1.0; 4]);
    let (base, emissive, mr) = (
        mean(m.base_color_texture),
        mean(m.emissive_texture),
        mean(m.metallic_roughness_texture),
    );
    HitMaterial {
        albedo: std::array::from_fn(|c| m.base_color[c] * base[c]),
        emissive: [
            m.emissive[0] * emissive[0],
            m.emissive[1] * emissive[1],
            m.emissive[2] * emissive[2],
            0.0,
        ],
        // glTF: roughness in the map's green channel, metalness in its blue; clamped as
        // lib/material.wgsl clamps them.
        metallic: (m.metallic * mr[2]).clamp(0.0, 1.0),
        roughness: (m.roughness * mr[1]).clamp(0.03, 1.0),
        cutoff: match m.alpha {
            lightbench_scene::AlphaMode::Mask(c) => c,
            lightbench_scene::AlphaMode::Blend => -1.0,
            lightbench_scene::AlphaMode::Opaque => 0.0,
        },
        uv_sets: m.uv_sets,
        base_factor: m.base_color,
        emissive_factor: m.emissive,
        wrap: m.sampler.wrap.iter().enumerate().map(|(k, w)| wrap_code(*w) << (2 * k)).sum(),
        metallic_factor: m.metallic,
        roughness_factor: m.roughness,
        normal_scale: m.normal_scale,
        _pad: 0.0,
        maps: [
            m.base_color_texture,
            m.metallic_roughness_texture,
            m.normal_texture,
            m.emissive_texture,
        ]
        .map(|t| t.map_or(NO_MAP, |i| i as u32)),
        uv_row0: [m.uv_transform[0][0], m.uv_transform[0][1], m.uv_transform[0][2], 0.0],
        uv_row1: [m.uv_transform[1][0], m.uv_transform[1][1], m.uv_transform[1][2], 0.0],
    }
}

/// A wrap mode as `HitMaterial::wrap` codes it.
fn wrap_code(w: lightbench_scene::Wrap) -> u32 {
    match w {
        lightbench_scene::Wrap::Repeat => 0,
        lightbench_scene::Wrap::Clamp => 1,
        lightbench_scene::Wrap::Mirror => 2,
    }
}

fn material_block(m: &Material) -> MaterialBlock {
    let [r0, r1] = m.uv_transform;
    MaterialBlock {
        base_color: m.base_color,
        emissive: [m.emissive[0], m.emissive[1], m.emissive[2], 0.0],
        uv_row0: [r0[0], r0[1], r0[2], 0.0],
        uv_row1: [r1[0], r1[1], r1[2], 0.0],
        metallic: m.metallic,
        roughness: m.roughness,
        normal_scale: m.normal_scale,
        has_normal_map: m.normal_texture.is_some() as u32,
        alpha_cutoff: match m.alpha {
            AlphaMode::Mask(c) => c,
            _ => 0.0,
        },
        occlusion_strength: if m.occlusion_texture.is_some() { m.occlusion_strength } else { 0.0 },
        uv_sets: m.uv_sets,
        double_sided: m.double_sided as u32,
    }
}

impl SceneGpu {
    /// Upload the scene. Its textures are moved out and dropped one by one as they reach the
    /// GPU, so the upload never holds a second CPU copy of them.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, scene: &mut Scene) -> Result<SceneGpu> {
        Self::reusing(device, queue, scene, None)
    }

    /// Upload the scene, keeping resident what `previous` (the scene on the GPU before it)
    /// already holds unchanged: meshes with the same vertices and indices keep their buffers,
    /// textures with the same texels their texture and mips. What was kept is in `kept`.
    pub fn reusing(device: &wgpu::Device, queue: &wgpu::Queue, scene: &mut Scene, previous: Option<&SceneGpu>) -> Result<SceneGpu> {
        // Before the textures are handed to the GPU: emissive maps set the area lights' radiance.
        let (mut areas, area_lights_dropped) = area_lights(scene);
        let up = upload_textures(device, queue, std::mem::take(&mut scene.textures), previous)?;
        let hit_materials = scene.materials.iter().map(|m| hit_material(m, &up.means)).collect();
        let (materials, sampler_descs) = materials(device, queue, &scene.materials, &up.views);
        let (meshes, meshes_kept) = meshes(device, scene, previous)?;
        let kept = Kept {
            meshes: (meshes_kept, meshes.len()),
            textures: (up.kept, up.views.len()),
            blas: None,
            models: None,
        };
        let triangle_count = u32::try_from(triangle_count(scene))
            .map_err(|_| Error::scene(format!("scene `{}` draws more than 2³² triangles", scene.name)))?;
        let mut samplers: Vec<wgpu::Sampler> = sampler_descs.iter().map(|d| sampler(device, d)).collect();
        if samplers.is_empty() {
            samplers.push(sampler(device, &SamplerDesc::default()));
        }
        if areas.is_empty() {
            areas.push(AreaLightBlock::default());
        }
        let area_lights = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("area lights"),
            contents: bytemuck::cast_slice(&areas),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let volumes = super::light_volumes::LightVolumes::new();
        let light_volumes = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light volumes"),
            contents: bytemuck::cast_slice(&volumes.corners),
            usage: wgpu::BufferUsages::STORAGE,
        });
        Ok(SceneGpu {
            meshes,
            materials,
            samplers,
            triangle_count,
            area_lights,
            area_lights_dropped,
            light_volumes,
            volumes,
            hit_materials,
            textures: up.views.iter().map(|v| v.texture().clone()).collect(),
            texture_keys: up.keys,
            means: up.means,
            kept,
        })
    }

    /// The texture holding the texels with content key `key`, and its mean.
    fn texture_with(&self, key: u128) -> Option<(&wgpu::Texture, [f32; 4])> {
        let i = self.texture_keys.iter().position(|k| *k == key)?;
        Some((&self.textures[i], self.means[i]))
    }
}

#[cfg(test)]
mod tests {
    use super::mip_chain;

    /// An emissive map scales an area light's radiance by its mean over the triangle, sRGB
    /// decoded: a uniform 188/255 sRGB map halves it; a map black on the half of the UV square
    /// one triangle covers leaves that one dark.
    #[test]
    fn emissive_maps_set_the_radiance_by_their_mean() {
        use lightbench_scene::{geometry::quad, ImageData, Material, Mesh, Scene};
        let lamp = |texels: Vec<u8>, width: u32| {
            let (mut v, mut i) = (vec![], vec![]);
            quad(glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Z, &mut v, &mut i);
            let mut m = Material::color("lamp", [0.0; 3], 1.0);
            (m.emissive, m.emissive_texture) = ([4.0, 4.0, 4.0], Some(0));
            let mut s = Scene::from_meshes(
                "lamp",
                (8, 8),
                vec![Mesh::new("lamp", v, i, 0, glam::Mat4::IDENTITY)],
                vec![m],
                vec![],
            )
            .unwrap();
            s.textures = vec![ImageData {
                width,
                height: 1,
                rgba: texels.into(),
                srgb: true,
            }];
            super::area_lights(&s).0
        };
        let grey = lamp([188, 188, 188, 255].repeat(4), 4);
        assert!(grey.iter().all(|l| (l.radiance[0] - 2.0).abs() < 0.02), "{grey:?}");
        // Left half white, right half black: the quad's two triangles cover the halves unevenly.
        let split = lamp(
            [[255u8, 255, 255, 255], [255, 255, 255, 255], [0, 0, 0, 255], [0, 0, 0, 255]].concat(),
            4,
        );
        let r: Vec<f32> = split.iter().map(|l| l.radiance[0]).collect();
        assert!(r.iter().all(|v| (0.0..4.0).contains(v)) && (r[0] - r[1]).abs() > 0.5, "{r:?}");
    }

    /// Emissive triangles become area lights in world space, most powerful first, capped.
    #[test]
    fn emissive_triangles_become_area_lights_up_to_the_limit() {
        use lightbench_scene::{geometry::quad, Material, Mesh, Scene};
        let mut meshes = vec![];
        let mut materials = vec![Material::color("grey", [0.5; 3], 1.0)];
        // 520 emissive quads (1,040 triangles), the later ones brighter, and a plain floor.
        for k in 0..520 {
            let (mut v, mut i) = (vec![], vec![]);
            quad(
                glam::Vec3::new(k as f32, 1.0, 0.0),
                glam::Vec3::X * 0.4,
                glam::Vec3::Z * 0.3,
                &mut v,
                &mut i,
            );
            let mut m = Material::color("lamp", [0.0; 3], 1.0);
            m.emissive = [1.0 + k as f32, 1.0, 1.0];
            materials.push(m);
            meshes.push(Mesh::new("lamp", v, i, k + 1, glam::Mat4::from_translation(glam::Vec3::Y)));
        }
        let (mut v, mut i) = (vec![], vec![]);
        quad(glam::Vec3::ZERO, glam::Vec3::X * 9.0, glam::Vec3::Z * 9.0, &mut v, &mut i);
        meshes.push(Mesh::new("floor", v, i, 0, glam::Mat4::IDENTITY));
        let scene = Scene::from_meshes("lamps", (8, 8), meshes, materials, vec![]).unwrap();
        let (lights, dropped) = super::area_lights(&scene);
        assert_eq!((lights.len(), dropped), (super::MAX_AREA_LIGHTS, 1040 - super::MAX_AREA_LIGHTS));
        assert_eq!(lights[0].radiance, [520.0, 1.0, 1.0, 0.0], "the brightest first, single-sided");
        assert!(
            lights.iter().all(|l| l.corners.iter().all(|c| (c[1] - 2.0).abs() < 1e-6)),
            "placed by the mesh's transform"
        );
    }

    #[test]
    fn mips_average_in_linear_light_down_to_one_texel() {
        // Black and white sRGB texels average to 50% linear grey, which is sRGB 188, not 128.
        let (levels, data) = mip_chain(2, 1, vec![0, 0, 0, 255, 255, 255, 255, 255], true);
        assert_eq!(levels, 2);
        assert_eq!(data[8..], [188, 188, 188, 255]);
        let (_, linear) = mip_chain(2, 1, vec![0, 0, 0, 255, 255, 255, 255, 255], false);
        assert_eq!(linear[8..], [128, 128, 128, 255]);
        // 5×3, 2×1, 1×1: 15 + 2 + 1 texels.
        let (levels, data) = mip_chain(5, 3, vec![9; 60], false);
        assert_eq!((levels, data.len()), (3, 18 * 4));
        assert!(data.iter().all(|v| *v == 9), "a flat image stays flat");
    }
}
