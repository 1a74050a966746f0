//! The scene's acceleration structure: one bottom level (BLAS) per mesh, built from the
//! mesh's own vertex and index buffers, and a top level (TLAS) over them placed by each mesh's
//! transform. Built once, the first time a Plan binds it, and kept for the scene's life (the
//! scene's geometry does not change between frames; a new scene builds its own).

use super::scene_gpu::MeshGpu;
use lightbench_compiler::abi::Vertex;
use lightbench_scene::error::{Error, Result};

/// What rays are traced against: the opaque and alpha-masked meshes, as the raster's shadow
/// and G-buffer passes draw them (blended meshes are left out, as `draw: Scene` leaves them).
pub struct Accel {
    pub tlas: wgpu::Tlas,
    /// The bottom levels, one per traced mesh (the TLAS's instances keep them alive too).
    pub blas: Vec<wgpu::Blas>,
    pub triangles: u64,
}

/// Mesh `m`'s triangles as one BLAS geometry: positions are the first 12 bytes of each
/// interleaved vertex.
fn size_of(m: &MeshGpu) -> wgpu::BlasTriangleGeometrySizeDescriptor {
    wgpu::BlasTriangleGeometrySizeDescriptor {
        vertex_format: wgpu::VertexFormat::Float32x3,
        vertex_count: m.vertex_count,
        index_format: Some(wgpu::IndexFormat::Uint32),
        index_count: Some(m.index_count),
        flags: wgpu::AccelerationStructureGeometryFlags::OPAQUE,
    }
}

/// A column-major affine transform as the TLAS wants it: 3 rows × 4 columns, row-major.
fn rows(t: &glam::Mat4) -> [f32; 12] {
    let r = t.transpose().to_cols_array();
    std::array::from_fn(|i| r[i])
}

/// The meshes traced: opaque and masked ones with at least one whole triangle drawn.
fn traced(meshes: &[MeshGpu]) -> Vec<usize> {
    (0..meshes.len())
        .filter(|&i| !meshes[i].blend && meshes[i].index_count >= 3)
        .collect()
}

/// Refuse what the device cannot build, naming the mesh and the limit.
fn check_limits(device: &wgpu::Device, meshes: &[MeshGpu], list: &[usize]) -> Result<()> {
    let limits = device.limits();
    if list.is_empty() {
        return Err(Error::Scene(
            "the scene has no opaque triangles to trace rays against (the pipeline reads an acceleration structure)".into(),
        ));
    }
    if list.len() as u64 > limits.max_tlas_instance_count as u64 {
        return Err(Error::Scene(format!(
            "the scene has {} meshes to trace, over this device's limit of {} acceleration-structure instances (max_tlas_instance_count)",
            list.len(),
            limits.max_tlas_instance_count
        )));
    }
    for &i in list {
        let tris = meshes[i].index_count as u64 / 3;
        if tris > limits.max_blas_primitive_count as u64 {
            return Err(Error::Scene(format!(
                "mesh `{}` has {tris} triangles, over this device's limit of {} per acceleration structure (max_blas_primitive_count)",
                meshes[i].name, limits.max_blas_primitive_count
            )));
        }
    }
    Ok(())
}

impl Accel {
    /// Build the BLAS of every traced mesh and the TLAS over them, and wait for the build.
    pub fn build(device: &wgpu::Device, queue: &wgpu::Queue, meshes: &[MeshGpu]) -> Result<Accel> {
        if !device.features().contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY) {
            return Err(Error::Adapter(
                "this device has no ray queries (EXPERIMENTAL_RAY_QUERY): the pipeline's acceleration structure cannot be built".into(),
            ));
        }
        let list = traced(meshes);
        check_limits(device, meshes, &list)?;
        let sizes: Vec<_> = list.iter().map(|&i| size_of(&meshes[i])).collect();
        let blas: Vec<wgpu::Blas> = list
            .iter()
            .zip(&sizes)
            .map(|(&i, size)| {
                device.create_blas(
                    &wgpu::CreateBlasDescriptor {
                        label: Some(&meshes[i].name),
                        flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
                        update_mode: wgpu::AccelerationStructureUpdateMode::Build,
                    },
                    wgpu::BlasGeometrySizeDescriptors::Triangles {
                        descriptors: vec![size.clone()],
                    },
                )
            })
            .collect();
        let mut tlas = device.create_tlas(&wgpu::CreateTlasDescriptor {
            label: Some("scene TLAS"),
            max_instances: list.len() as u32,
            flags: wgpu::AccelerationStructureFlags::PREFER_FAST_TRACE,
            update_mode: wgpu::AccelerationStructureUpdateMode::Build,
        });
        for (k, (&i, b)) in list.iter().zip(&blas).enumerate() {
            // The custom index is the mesh's index in the scene upload (24 bits).
            tlas[k] = Some(wgpu::TlasInstance::new(b, rows(&meshes[i].transform), i as u32 & 0xff_ffff, 0xff));
        }
        let entries: Vec<wgpu::BlasBuildEntry> = list
            .iter()
            .zip(&blas)
            .zip(&sizes)
            .map(|((&i, b), size)| wgpu::BlasBuildEntry {
                blas: b,
                geometry: wgpu::BlasGeometries::TriangleGeometries(vec![wgpu::BlasTriangleGeometry {
                    size,
                    vertex_buffer: &meshes[i].vertices,
                    first_vertex: 0,
                    vertex_stride: std::mem::size_of::<Vertex>() as u64,
                    index_buffer: Some(&meshes[i].indices),
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
        let triangles = list.iter().map(|&i| meshes[i].index_count as u64 / 3).sum();
        Ok(Accel { tlas, blas, triangles })
    }
}
