//! The scene's acceleration structure: one bottom level (BLAS) per mesh, built from the
//! mesh's own vertex and index buffers, and a top level (TLAS) over them placed by each mesh's
//! transform; and, apart, the data ray hits are shaded with (`HitData`), which only passes
//! that shade hits need. Each is built once, the first time a Plan binds it, and kept for the
//! scene's life (the scene's geometry does not change between frames; a new scene builds its
//! own).

use super::scene_gpu::{check_buffer, MeshGpu};
use super::texel_table::{staged_size, texel_table, texel_table_from_gpu};
use crate::error::{Error, Result};
use bytemuck::Zeroable;
use lightbench_compiler::abi::{HitCorners, HitEmitter, HitMaterial, HitTriangle, Vertex, NO_EMITTER};
use lightbench_scene::{Mesh, Scene};
use wgpu::util::DeviceExt;

/// Instance masks (`shaders/lib/ray.wgsl`).
const OPAQUE_MESHES: u32 = 1;
const BLENDED_MESHES: u32 = 2;

/// A ray hit finds its triangle's data at the instance's custom index (where its mesh's
/// triangles begin) plus its primitive index; custom indices have 24 bits.
const MAX_FIRST_TRIANGLE: u64 = 1 << 24;

/// What rays are traced against: every mesh, the opaque and alpha-masked ones under instance
/// mask `OPAQUE_MESHES` (what the raster's shadow and G-buffer passes draw), the blended ones
/// under `BLENDED_MESHES` (a pass may skip them by its cull mask, as `draw: Scene` skips them;
/// the bundled passes meet them as the reference does, as stochastic transparency).
pub struct Accel {
    pub tlas: wgpu::Tlas,
    /// The bottom levels, one per traced mesh (the TLAS's instances keep them alive too),
    /// each with what it was built from (a new scene's build keeps those it has unchanged).
    pub blas: Vec<(BlasKey, wgpu::Blas)>,
    pub triangles: u64,
    /// How many bottom levels were taken over from the previous scene's, unbuilt.
    pub kept: usize,
}

/// What a BLAS was built from: its mesh's vertices and indices (`MeshGpu::key`, whose
/// buffers a new scene keeps with them), the triangles drawn and whether they are opaque.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlasKey {
    mesh: u128,
    index_count: u32,
    opaque: bool,
}

/// The standard bindings hits are shaded with, in the order the TLAS's custom indices address.
pub struct HitData {
    /// `hit_triangles`: every traced triangle, mesh after mesh (a table of texels).
    pub triangles: wgpu::TextureView,
    /// `hit_materials`: every material of the scene.
    pub materials: wgpu::Buffer,
    /// `hit_emitters`: the traced triangles that emit, with their choice probabilities (a
    /// table of texels: the count, then the emitters).
    pub emitters: wgpu::TextureView,
}

/// What maps are looked up at hits with, built apart (only passes that look maps up bind it:
/// the scene's textures at full resolution need not be copied for the others).
pub struct HitMaps {
    /// `hit_corners`: every traced triangle's corners' texture coordinates and tangents (a
    /// table of texels).
    pub corners: wgpu::TextureView,
    /// `hit_maps`: the scene's maps at full resolution (a table of texels).
    pub maps: wgpu::TextureView,
}

/// A traced triangle's world corners, in its own order (its front is its hit data's `ng`).
type Corners = [[f32; 3]; 3];

/// Mesh `m`'s triangles as one BLAS geometry: positions are the first 12 bytes of each
/// interleaved vertex. An opaque material's triangles end shadow queries by themselves; a
/// masked or blended one's are offered to the shader (`shaders/lib/ray.wgsl`), each once, so
/// that a blended surface's transmittance is counted once per ray.
fn size_of(m: &MeshGpu, scene: &Scene) -> wgpu::BlasTriangleGeometrySizeDescriptor {
    let opaque = blas_key(m, scene).opaque;
    wgpu::BlasTriangleGeometrySizeDescriptor {
        vertex_format: wgpu::VertexFormat::Float32x3,
        vertex_count: m.vertex_count,
        index_format: Some(wgpu::IndexFormat::Uint32),
        index_count: Some(m.index_count),
        flags: match opaque {
            true => wgpu::AccelerationStructureGeometryFlags::OPAQUE,
            false => wgpu::AccelerationStructureGeometryFlags::NO_DUPLICATE_ANY_HIT_INVOCATION,
        },
    }
}

fn blas_key(m: &MeshGpu, scene: &Scene) -> BlasKey {
    let opaque = scene
        .materials
        .get(m.material)
        .is_none_or(|mat| mat.alpha == lightbench_scene::AlphaMode::Opaque);
    BlasKey {
        mesh: m.key,
        index_count: m.index_count,
        opaque,
    }
}

/// A column-major affine transform as the TLAS wants it: 3 rows × 4 columns, row-major.
fn rows(t: &glam::Mat4) -> [f32; 12] {
    let r = t.transpose().to_cols_array();
    std::array::from_fn(|i| r[i])
}

/// The meshes traced: those with at least one whole triangle drawn.
fn traced(meshes: &[MeshGpu]) -> Vec<usize> {
    (0..meshes.len()).filter(|&i| meshes[i].index_count >= 3).collect()
}

/// Where each traced mesh's triangles begin among all traced triangles (the hit data's order).
fn first_triangles(meshes: &[MeshGpu], list: &[usize]) -> Vec<u64> {
    list.iter()
        .scan(0u64, |next, &i| {
            let first = *next;
            *next += meshes[i].index_count as u64 / 3;
            Some(first)
        })
        .collect()
}

/// Refuse what the device cannot build, naming the scene or mesh and the limit: `meshes` the
/// traced meshes' names and triangle counts.
fn check_limits(limits: &wgpu::Limits, scene: &str, meshes: &[(&str, u64)]) -> Result<()> {
    if meshes.is_empty() {
        return Err(Error::scene(format!(
            "scene `{scene}` has no triangles to trace rays against (the pipeline reads an acceleration structure; choose its raster option)"
        )));
    }
    let mut first = 0u64;
    for (name, tris) in meshes {
        if first >= MAX_FIRST_TRIANGLE {
            return Err(Error::scene(format!(
                "mesh `{name}` of scene `{scene}` begins at traced triangle {first}, beyond the {MAX_FIRST_TRIANGLE} a ray hit can name (24-bit instance index)"
            )));
        }
        first += tris;
    }
    if meshes.len() as u64 > limits.max_tlas_instance_count as u64 {
        return Err(Error::scene(format!(
            "scene `{scene}` has {} meshes to trace, over this device's limit of {} acceleration-structure instances (max_tlas_instance_count)",
            meshes.len(),
            limits.max_tlas_instance_count
        )));
    }
    if let Some((name, tris)) = meshes.iter().find(|m| m.1 > limits.max_blas_primitive_count as u64) {
        return Err(Error::scene(format!(
            "mesh `{name}` of scene `{scene}` has {tris} triangles, over this device's limit of {} per acceleration structure (max_blas_primitive_count)",
            limits.max_blas_primitive_count
        )));
    }
    Ok(())
}

/// Mesh `m`'s drawn triangles as hits read them: world-space shading normals (the geometric
/// normal where a vertex has none), the front's normal, the material; and their corners.
fn hit_triangles(m: &Mesh, double_sided: bool, out: &mut Vec<HitTriangle>, corners: &mut Vec<Corners>) {
    let normal_matrix = glam::Mat3::from_mat4(m.transform).inverse().transpose();
    let mirrored = m.transform.determinant() < 0.0;
    let drawn = &m.indices[..(m.drawn_indices() as usize).min(m.indices.len())];
    for t in drawn.chunks_exact(3) {
        let v = |k: usize| m.vertices.get(t[k] as usize).copied().unwrap_or(Vertex::zeroed());
        let p = |k: usize| m.transform.transform_point3(glam::Vec3::from(v(k).position));
        let cross = (p(1) - p(0)).cross(p(2) - p(0));
        let ng = if mirrored { -cross } else { cross }.normalize_or_zero();
        let n = |k: usize| {
            let n = (normal_matrix * glam::Vec3::from(v(k).normal)).normalize_or_zero();
            if n == glam::Vec3::ZERO {
                ng.to_array()
            } else {
                n.to_array()
            }
        };
        out.push(HitTriangle {
            n0: n(0),
            material: m.material as u32,
            n1: n(1),
            double_sided: double_sided as u32,
            n2: n(2),
            emitter: NO_EMITTER,
            ng: ng.to_array(),
            ..Default::default()
        });
        corners.push([p(0).to_array(), p(1).to_array(), p(2).to_array()]);
    }
}

/// Mesh `m`'s drawn triangles' corners as map lookups read them: both UV sets, and tangents
/// placed as the reference places them (by the transform itself, the sign kept).
fn hit_corners(m: &Mesh, out: &mut Vec<HitCorners>) {
    let drawn = &m.indices[..(m.drawn_indices() as usize).min(m.indices.len())];
    for t in drawn.chunks_exact(3) {
        let v = |k: usize| m.vertices.get(t[k] as usize).copied().unwrap_or(Vertex::zeroed());
        out.push(HitCorners {
            uv: std::array::from_fn(|k| {
                let v = v(k);
                [v.uv[0], v.uv[1], v.uv1[0], v.uv1[1]]
            }),
            tangent: std::array::from_fn(|k| {
                let t = v(k).tangent;
                m.transform
                    .transform_vector3(glam::Vec3::from_slice(&t[..3]))
                    .extend(t[3])
                    .to_array()
            }),
        });
    }
}

/// Every traced mesh's hit data, mesh after mesh, and each traced triangle's corners.
fn hit_data(meshes: &[MeshGpu], list: &[usize], scene: &Scene) -> (Vec<HitTriangle>, Vec<Corners>) {
    let (mut all, mut corners) = (vec![], vec![]);
    for &i in list {
        let m = &scene.meshes[meshes[i].source];
        let double_sided = scene.materials.get(m.material).is_some_and(|mat| mat.double_sided);
        hit_triangles(m, double_sided, &mut all, &mut corners);
    }
    (all, corners)
}

/// Where each map's texels begin in `hit_maps` (bytes, 256-aligned as copies want them), its
/// row pitch in bytes, and the whole table's size: the count and an entry per map (a texel
/// each), then the maps.
fn map_layout(textures: &[wgpu::Texture]) -> (Vec<(u64, u64)>, u64) {
    let header = 16 * (1 + textures.len() as u64);
    let mut at = header.next_multiple_of(256);
    let mut places = vec![];
    for t in textures {
        let pitch = (4 * t.width() as u64).next_multiple_of(256);
        places.push((at, pitch));
        at += pitch * t.height() as u64;
    }
    (places, at)
}

/// The scene's maps for lookups at ray hits (`hit_maps`), a table of texels: the count, then
/// per map (first texel's word, width, height, row pitch in words | 1 << 31 for sRGB), then
/// each map's level 0 as RGBA8 texels, copied on the GPU from the uploaded textures (the scene
/// keeps no CPU copy).
fn maps(gpu: (&wgpu::Device, &wgpu::Queue), textures: &[wgpu::Texture]) -> Result<wgpu::TextureView> {
    let (places, size) = map_layout(textures);
    let what = || format!("the scene's {} maps at full resolution, looked up at ray hits,", textures.len());
    let staged = || format!("{} staged for their table", what());
    check_buffer(gpu.0, staged, staged_size(gpu.0, size), false)?;
    let mut table = vec![[textures.len() as u32, 0, 0, 0]];
    for (t, (at, pitch)) in textures.iter().zip(&places) {
        let srgb = (t.format() == wgpu::TextureFormat::Rgba8UnormSrgb) as u32;
        table.push([(at / 4) as u32, t.width(), t.height(), (pitch / 4) as u32 | srgb << 31]);
    }
    texel_table_from_gpu(gpu, "hit maps", what, size, |enc, staging| {
        gpu.1.write_buffer(staging, 0, bytemuck::cast_slice(&table));
        for (t, (at, pitch)) in textures.iter().zip(&places) {
            enc.copy_texture_to_buffer(
                t.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: staging,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: *at,
                        bytes_per_row: Some(*pitch as u32),
                        rows_per_image: Some(t.height()),
                    },
                },
                wgpu::Extent3d {
                    width: t.width(),
                    height: t.height(),
                    depth_or_array_layers: 1,
                },
            );
        }
    })
}

/// The traced triangles that emit as lights, chosen in proportion to their power (area ×
/// brightest channel, as the reference weighs them), and each emitting triangle's index
/// among them written to its hit data.
fn emitters(hits: &mut [HitTriangle], corners: &[Corners], materials: &[HitMaterial]) -> Vec<HitEmitter> {
    let mut out = vec![];
    let mut power = vec![];
    for (i, (h, c)) in hits.iter_mut().zip(corners).enumerate() {
        let Some(m) = materials.get(h.material as usize) else {
            continue;
        };
        let [a, b, cc] = c.map(glam::Vec3::from);
        let area = 0.5 * (b - a).cross(cc - a).length();
        let p = area as f64 * m.emissive[..3].iter().fold(0.0f32, |x, &y| x.max(y)) as f64;
        if p > 0.0 && p.is_finite() {
            h.emitter = out.len() as u32;
            out.push(HitEmitter {
                p0: c[0],
                p1: c[1],
                p2: c[2],
                triangle: i as u32,
                radiance: [m.emissive[0], m.emissive[1], m.emissive[2]],
                area,
                ..Default::default()
            });
            power.push(p);
        }
    }
    let total: f64 = power.iter().sum();
    let mut below = 0.0;
    for (e, p) in out.iter_mut().zip(&power) {
        e.prob = (p / total) as f32;
        below += p / total;
        e.cdf = below as f32;
    }
    if let Some(last) = out.last_mut() {
        last.cdf = 1.0;
    }
    out
}

/// The emitters as `shaders/lib/hit_emitters.wgsl` reads them: a texel holding their count,
/// then each one's 4 texels; with none, one of probability 0 (the search needs an entry).
fn emitter_table(emitters: &[HitEmitter]) -> Vec<[u32; 4]> {
    let none = [HitEmitter::default()];
    let emitters = if emitters.is_empty() { &none[..] } else { emitters };
    let mut texels = vec![[emitters.len() as u32, 0, 0, 0]];
    texels.extend_from_slice(bytemuck::cast_slice(emitters));
    texels
}

/// A storage buffer of `items`; a binding cannot be empty, so one zeroed item stands in for none.
fn storage<T: bytemuck::Pod>(device: &wgpu::Device, label: &str, items: &[T]) -> wgpu::Buffer {
    let zero = [T::zeroed()];
    let items = if items.is_empty() { &zero[..] } else { items };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(items),
        usage: wgpu::BufferUsages::STORAGE,
    })
}

impl HitData {
    /// The traced meshes' triangles and the scene's materials as hits read them: the
    /// triangles and the emitters as tables within the device's texture limits.
    pub fn build(gpu: (&wgpu::Device, &wgpu::Queue), scene_gpu: &super::scene_gpu::SceneGpu, scene: &Scene) -> Result<HitData> {
        let device = gpu.0;
        let (meshes, materials) = (&scene_gpu.meshes[..], &scene_gpu.hit_materials[..]);
        let (mut hits, corners) = hit_data(meshes, &traced(meshes), scene);
        let emitters = emitters(&mut hits, &corners, materials);
        drop(corners);
        let what = || format!("scene `{}`: its {} emissive traced triangles", scene.name, emitters.len());
        let emitters = texel_table(gpu, "hit emitters", what, &emitter_table(&emitters))?;
        let what = || format!("scene `{}`: the ray-hit data of its {} traced triangles", scene.name, hits.len());
        Ok(HitData {
            triangles: texel_table(gpu, "hit triangles", what, &hits)?,
            materials: storage(device, "hit materials", materials),
            emitters,
        })
    }
}

impl HitMaps {
    /// The traced triangles' corners (in the hit data's order) and the scene's maps, as
    /// tables within the device's texture limits.
    pub fn build(gpu: (&wgpu::Device, &wgpu::Queue), scene_gpu: &super::scene_gpu::SceneGpu, scene: &Scene) -> Result<HitMaps> {
        let mut corners = vec![];
        for i in traced(&scene_gpu.meshes) {
            hit_corners(&scene.meshes[scene_gpu.meshes[i].source], &mut corners);
        }
        let what = || {
            format!(
                "scene `{}`: the texture coordinates of its {} traced triangles",
                scene.name,
                corners.len()
            )
        };
        Ok(HitMaps {
            corners: texel_table(gpu, "hit corners", what, &corners)?,
            maps: maps(gpu, &scene_gpu.textures)?,
        })
    }
}

impl Accel {
    /// Build the BLAS of every traced mesh and the TLAS over them, and wait for the build. A
    /// mesh whose BLAS `previous` (the scene's before it) holds unchanged keeps it, unbuilt.
    pub fn build(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        meshes: &[MeshGpu],
        scene: &Scene,
        previous: &[(BlasKey, wgpu::Blas)],
    ) -> Result<Accel> {
        if !device.features().contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY) {
            return Err(Error::Adapter(
                "this device has no ray queries (EXPERIMENTAL_RAY_QUERY): the pipeline's acceleration structure cannot be built".into(),
            ));
        }
        let list = traced(meshes);
        let sizes_of: Vec<(&str, u64)> = list
            .iter()
            .map(|&i| (meshes[i].name.as_str(), meshes[i].index_count as u64 / 3))
            .collect();
        check_limits(&device.limits(), &scene.name, &sizes_of)?;
        let first = first_triangles(meshes, &list);
        // Each traced mesh's BLAS: the previous scene's where it has one built from the same
        // buffers, else a new one to build (with its geometry's size).
        let mut blas = vec![];
        let mut to_build = vec![];
        for &i in &list {
            let key = blas_key(&meshes[i], scene);
            match previous.iter().find(|(k, _)| *k == key) {
                Some((_, b)) => blas.push((key, b.clone())),
                None => {
                    let size = size_of(&meshes[i], scene);
                    blas.push((key, new_blas(device, &meshes[i].name, &size)));
                    to_build.push((i, blas.len() - 1, size));
                }
            }
        }
        let mut tlas = device.create_tlas(&wgpu::CreateTlasDescriptor {
            label: Some("scene TLAS"),
            max_instances: list.len() as u32,
            flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
            update_mode: wgpu::AccelerationStructureUpdateMode::Build,
        });
        for (k, (&i, (_, b))) in list.iter().zip(&blas).enumerate() {
            // The custom index is where the mesh's hit data begins (checked to fit 24 bits).
            let mask = if meshes[i].blend { BLENDED_MESHES } else { OPAQUE_MESHES };
            tlas[k] = Some(wgpu::TlasInstance::new(b, rows(&meshes[i].transform), first[k] as u32, mask as u8));
        }
        let entries: Vec<wgpu::BlasBuildEntry> = to_build
            .iter()
            .map(|(i, at, size)| wgpu::BlasBuildEntry {
                blas: &blas[*at].1,
                geometry: wgpu::BlasGeometries::TriangleGeometries(vec![wgpu::BlasTriangleGeometry {
                    size,
                    vertex_buffer: &meshes[*i].vertices,
                    first_vertex: 0,
                    vertex_stride: std::mem::size_of::<Vertex>() as u64,
                    index_buffer: Some(&meshes[*i].indices),
                    first_index: Some(0),
                    transform_buffer: None,
                    transform_buffer_offset: None,
                }]),
            })
            .collect();
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("acceleration structure build"),
        });
        enc.build_acceleration_structures(entries.iter(), std::iter::once(&tlas));
        queue.submit([enc.finish()]);
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::gpu("building the acceleration structure", e))?;
        let triangles = sizes_of.iter().map(|m| m.1).sum();
        let kept = list.len() - to_build.len();
        Ok(Accel {
            tlas,
            blas,
            triangles,
            kept,
        })
    }
}

/// A BLAS for one triangle geometry of `size`, not yet built.
fn new_blas(device: &wgpu::Device, label: &str, size: &wgpu::BlasTriangleGeometrySizeDescriptor) -> wgpu::Blas {
    device.create_blas(
        &wgpu::CreateBlasDescriptor {
            label: Some(label),
            flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
            update_mode: wgpu::AccelerationStructureUpdateMode::Build,
        },
        wgpu::BlasGeometrySizeDescriptors::Triangles {
            descriptors: vec![size.clone()],
        },
    )
}

#[cfg(test)]
mod tests {
    use super::check_limits;

    /// What a device cannot build is refused before anything is built, naming the scene, the
    /// mesh and the limit.
    #[test]
    fn limits_are_refused_by_name() {
        let limits = wgpu::Limits {
            max_tlas_instance_count: 2,
            max_blas_primitive_count: 100,
            ..wgpu::Limits::default()
        };
        let err = |meshes: &[(&str, u64)]| check_limits(&limits, "yard", meshes).unwrap_err().to_string();
        assert!(err(&[]).starts_with("scene `yard` has no triangles to trace"), "{}", err(&[]));
        let e = err(&[("fence", 10), ("tree", 101)]);
        assert!(
            e.contains("mesh `tree` of scene `yard` has 101 triangles") && e.contains("max_blas_primitive_count"),
            "{e}"
        );
        let e = err(&[("a", 1), ("b", 1), ("c", 1)]);
        assert!(
            e.contains("3 meshes to trace") && e.contains("limit of 2") && e.contains("max_tlas_instance_count"),
            "{e}"
        );
        // Custom indices name where each mesh begins: the last may run past 2²⁴ triangles, but
        // none may begin there.
        let big = wgpu::Limits {
            max_blas_primitive_count: 1 << 30,
            ..limits.clone()
        };
        assert!(check_limits(&big, "yard", &[("a", (1 << 24) - 1), ("b", 1 << 20)]).is_ok());
        let e = check_limits(&big, "yard", &[("a", 1 << 24), ("b", 1)]).unwrap_err().to_string();
        assert!(e.contains("mesh `b` of scene `yard` begins at traced triangle 16777216"), "{e}");
        assert!(check_limits(&limits, "yard", &[("a", 100), ("b", 1)]).is_ok());
    }
}
