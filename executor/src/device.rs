//! Adapter and device: pick an adapter, request the features the pipelines can use, and
//! derive the capability profile the compiler checks variants against.

use crate::error::{Error, Result};
use lightbench_compiler::profile::{Feature, Limits, Profile};
use std::sync::{Arc, Mutex};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum BackendChoice {
    Vulkan,
    Gl,
}

/// How [`Gpu::from_host`] treats a host renderer's device.
#[derive(Clone, Copy, Debug, Default)]
pub struct HostOptions {
    /// Run the capability probes, which render a little on the host's queue (off: trust what
    /// the driver exposes).
    pub probe: bool,
}

#[derive(Clone, Debug, Default)]
pub struct DeviceOptions {
    pub backend: Option<BackendChoice>,
    /// Substring of the adapter name to pick.
    pub adapter: Option<String>,
}

/// A device the executor renders with, and what it can do: the compiler's capability
/// profile (features probed, not just trusted) and notes on what the probes found. Made by
/// `Gpu::new` (lightbench picks the adapter), `from_host` (a host renderer's device, its
/// handlers untouched) or `from_parts` (a device opened for lightbench, e.g. the viewer's).
pub struct Gpu {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub profile: Profile,
    /// Errors wgpu raised outside an error scope, kept instead of panicking.
    pub uncaptured: Arc<Mutex<Vec<String>>>,
    /// What the capability probes found (features exposed but not working).
    pub notes: Vec<String>,
}

/// wgpu features lightbench asks for when the adapter has them. Ray queries are experimental
/// in wgpu 30: `device_descriptor` acknowledges that (`ExperimentalFeatures::enabled`) only
/// when the adapter has them.
const WANTED: &[(wgpu::Features, Feature)] = &[
    (wgpu::Features::MULTIVIEW, Feature::Multiview),
    (wgpu::Features::CLIP_DISTANCES, Feature::ClipDistances),
    (wgpu::Features::TIMESTAMP_QUERY, Feature::TimestampQuery),
    (wgpu::Features::SHADER_F16, Feature::ShaderF16),
    (wgpu::Features::FLOAT32_FILTERABLE, Feature::Float32Filterable),
    (wgpu::Features::DEPTH_CLIP_CONTROL, Feature::DepthClipControl),
    (wgpu::Features::DUAL_SOURCE_BLENDING, Feature::DualSourceBlending),
    (wgpu::Features::RG11B10UFLOAT_RENDERABLE, Feature::Rg11b10UfloatRenderable),
    (wgpu::Features::SHADER_F64, Feature::ShaderF64),
    (wgpu::Features::SHADER_I16, Feature::ShaderI16),
    (wgpu::Features::SHADER_INT64, Feature::ShaderInt64),
    (wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX, Feature::ShaderInt64AtomicMinMax),
    (wgpu::Features::SHADER_INT64_ATOMIC_ALL_OPS, Feature::ShaderInt64AtomicAllOps),
    (wgpu::Features::SHADER_FLOAT32_ATOMIC, Feature::ShaderFloat32Atomic),
    (wgpu::Features::TEXTURE_ATOMIC, Feature::TextureAtomic),
    (wgpu::Features::IMMEDIATES, Feature::Immediates),
    (wgpu::Features::TEXTURE_BINDING_ARRAY, Feature::TextureBindingArray),
    (wgpu::Features::BUFFER_BINDING_ARRAY, Feature::BufferBindingArray),
    (wgpu::Features::STORAGE_RESOURCE_BINDING_ARRAY, Feature::StorageResourceBindingArray),
    (
        wgpu::Features::SAMPLED_TEXTURE_AND_STORAGE_BUFFER_ARRAY_NON_UNIFORM_INDEXING,
        Feature::SampledTextureAndStorageBufferArrayNonUniformIndexing,
    ),
    (
        wgpu::Features::STORAGE_TEXTURE_ARRAY_NON_UNIFORM_INDEXING,
        Feature::StorageTextureArrayNonUniformIndexing,
    ),
    (wgpu::Features::UNIFORM_BUFFER_BINDING_ARRAYS, Feature::UniformBufferBindingArrays),
    (wgpu::Features::SUBGROUP, Feature::Subgroup),
    (wgpu::Features::SUBGROUP_VERTEX, Feature::SubgroupVertex),
    (wgpu::Features::SUBGROUP_BARRIER, Feature::SubgroupBarrier),
    (wgpu::Features::PRIMITIVE_INDEX, Feature::PrimitiveIndex),
    (wgpu::Features::SHADER_EARLY_DEPTH_TEST, Feature::ShaderEarlyDepthTest),
    (wgpu::Features::SHADER_BARYCENTRICS, Feature::ShaderBarycentrics),
    (wgpu::Features::EXPERIMENTAL_RAY_QUERY, Feature::ExperimentalRayQuery),
];

impl Gpu {
    /// Pick an adapter (hardware first) and open a device with the features and limits
    /// pipelines can use.
    pub fn new(opts: &DeviceOptions) -> Result<Gpu> {
        let adapter = choose_adapter(opts)?;
        let (device, queue) = open_device(&adapter)?;
        Gpu::from_parts(adapter, device, queue)
    }

    /// Wrap a device someone else opened for lightbench's own use (the windowed viewer shares
    /// its device this way): the capability profile comes from the device's features and
    /// limits, checked by probes, and errors raised outside error scopes are collected here
    /// (`take_uncaptured`) in place of wgpu's default handler, which panics.
    pub fn from_parts(adapter: wgpu::Adapter, device: wgpu::Device, queue: wgpu::Queue) -> Result<Gpu> {
        let gpu = Gpu::from_host(adapter, device, queue, HostOptions { probe: true })?;
        let sink = gpu.uncaptured.clone();
        gpu.device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        Ok(gpu)
    }

    /// Use a host renderer's device as it is: its uncaptured-error handler is left alone (the
    /// executor reports its own errors as values, from error scopes), and the probes that
    /// render on the device run only if `opts.probe` says so; without them a feature the
    /// driver exposes is trusted. `adapter`, `device` and `queue` are clones of the host's.
    pub fn from_host(adapter: wgpu::Adapter, device: wgpu::Device, queue: wgpu::Queue, opts: HostOptions) -> Result<Gpu> {
        let info = adapter.get_info();
        let (features, limits, notes) = capabilities(&adapter, &device, &queue, opts.probe);
        let profile = Profile {
            name: format!("{} ({:?})", info.name, info.backend),
            features,
            limits: profile_limits(&limits),
        };
        Ok(Gpu {
            adapter,
            device,
            queue,
            info,
            profile,
            uncaptured: Arc::new(Mutex::new(vec![])),
            notes,
        })
    }

    /// For humans: name, backend, the features that matter here, and probe findings.
    pub fn describe(&self) -> String {
        let feats: Vec<&str> = self.profile.features.iter().map(|f| f.name()).collect();
        let mut s = format!(
            "adapter: {} ({:?}, {:?}); features: {}",
            self.info.name,
            self.info.backend,
            self.info.device_type,
            if feats.is_empty() { "none".into() } else { feats.join(", ") }
        );
        for n in &self.notes {
            s += &format!("\nnote: {n}");
        }
        s
    }

    /// Errors raised outside error scopes since the last call.
    pub fn take_uncaptured(&self) -> Vec<String> {
        self.uncaptured.lock().map(|mut v| std::mem::take(&mut *v)).unwrap_or_default()
    }
}

impl Gpu {
    /// A device that can present to `surface` (the viewer's window), with the same features,
    /// limits and probes as `Gpu::new`.
    pub fn for_surface(instance: &wgpu::Instance, surface: &wgpu::Surface) -> Result<Gpu> {
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: Some(surface),
            ..Default::default()
        }))
        .map_err(|e| Error::Adapter(format!("no GPU adapter can present to the window: {e}")))?;
        let (device, queue) = open_device(&adapter)?;
        Gpu::from_parts(adapter, device, queue)
    }
}

/// What the device can do, as the compiler's features and wgpu's limits, with the probes'
/// findings (`probe`: render on the device to test what drivers are known to expose broken).
fn capabilities(
    adapter: &wgpu::Adapter,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    probe: bool,
) -> (std::collections::BTreeSet<Feature>, wgpu::Limits, Vec<String>) {
    let enabled = device.features();
    let mut features: std::collections::BTreeSet<Feature> =
        WANTED.iter().filter(|(wf, _)| enabled.contains(*wf)).map(|(_, f)| *f).collect();
    let mut limits = device.limits();
    if limits.max_multiview_view_count < 6 {
        // Multiview with fewer than 6 views cannot render a cube in one pass.
        features.remove(&Feature::Multiview);
    }
    if adapter
        .get_downlevel_capabilities()
        .flags
        .contains(wgpu::DownlevelFlags::CUBE_ARRAY_TEXTURES)
    {
        features.insert(Feature::CubeArrayTextures);
    }
    // GL (through EGL on llvmpipe, or GLES) may not render to 32-bit float formats.
    let renders = |f: wgpu::TextureFormat| {
        adapter
            .get_texture_format_features(f)
            .allowed_usages
            .contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
    };
    if [
        wgpu::TextureFormat::R32Float,
        wgpu::TextureFormat::Rg32Float,
        wgpu::TextureFormat::Rgba32Float,
    ]
    .into_iter()
    .all(renders)
    {
        features.insert(Feature::Float32Renderable);
    }
    let mut notes = vec![];
    if probe && features.contains(&Feature::Multiview) && !multiview_works(device, queue) {
        // Seen on Mesa 22 lavapipe: the feature is exposed but every view lands in layer 0.
        features.remove(&Feature::Multiview);
        limits.max_multiview_view_count = 0;
        notes.push(
            "MULTIVIEW is exposed but renders every view into layer 0 on this driver (probe failed); treated as unavailable".to_string(),
        );
    }
    (features, limits, notes)
}

fn choose_adapter(opts: &DeviceOptions) -> Result<wgpu::Adapter> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = desc_backends(opts);
    let instance = wgpu::Instance::new(desc);
    let adapters = pollster::block_on(instance.enumerate_adapters(desc_backends(opts)));
    if adapters.is_empty() {
        return Err(Error::Adapter(format!(
            "no GPU adapter found{} (install Mesa's lavapipe: apt-get install mesa-vulkan-drivers)",
            match opts.backend {
                Some(BackendChoice::Vulkan) => " for the Vulkan backend",
                Some(BackendChoice::Gl) => " for the GL backend",
                None => "",
            }
        )));
    }
    let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
    if let Some(sub) = &opts.adapter {
        return adapters
            .into_iter()
            .find(|a| a.get_info().name.to_lowercase().contains(&sub.to_lowercase()))
            .ok_or_else(|| Error::Adapter(format!("no adapter matches `{sub}`; available: {}", names.join(", "))));
    }
    // Hardware first, then software, then anything; Vulkan before other backends.
    let rank = |a: &wgpu::Adapter| {
        let info = a.get_info();
        let kind = match info.device_type {
            wgpu::DeviceType::DiscreteGpu => 0,
            wgpu::DeviceType::IntegratedGpu => 1,
            wgpu::DeviceType::VirtualGpu => 2,
            wgpu::DeviceType::Cpu => 3,
            wgpu::DeviceType::Other => 4,
        };
        (kind, (info.backend != wgpu::Backend::Vulkan) as u8)
    };
    adapters
        .into_iter()
        .min_by_key(rank)
        .ok_or_else(|| Error::Adapter("no adapter".into()))
}

/// Open a device asking for every wanted feature the adapter has, and its limits where
/// pipelines may need more than the defaults.
fn open_device(adapter: &wgpu::Adapter) -> Result<(wgpu::Device, wgpu::Queue)> {
    pollster::block_on(adapter.request_device(&device_descriptor(adapter)))
        .map_err(|e| Error::Adapter(format!("cannot open device on {}: {e}", adapter.get_info().name)))
}

/// The device lightbench opens on `adapter`: every feature its pipelines can use that the
/// adapter has, and the limits they need. A host renderer that opens its device with this
/// (adding its own features and limits) gets the variants `lightbench render` chooses there.
pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
    let available = adapter.features();
    let mut required = wgpu::Features::empty();
    for (wf, _) in WANTED {
        if available.contains(*wf) {
            required |= *wf;
        }
    }
    let a = adapter.limits();
    let mut limits = wgpu::Limits {
        max_multiview_view_count: a.max_multiview_view_count.min(6),
        max_bind_groups: a.max_bind_groups.min(8),
        max_texture_dimension_2d: a.max_texture_dimension_2d,
        max_texture_array_layers: a.max_texture_array_layers,
        // The adapter's own sizes: wgpu's defaults (256 MiB buffers) would refuse scenes of a
        // few million triangles that the device holds.
        max_buffer_size: a.max_buffer_size,
        max_storage_buffer_binding_size: a.max_storage_buffer_binding_size,
        max_sampled_textures_per_shader_stage: a.max_sampled_textures_per_shader_stage,
        max_storage_textures_per_shader_stage: a.max_storage_textures_per_shader_stage,
        max_compute_invocations_per_workgroup: a.max_compute_invocations_per_workgroup,
        max_compute_workgroup_size_x: a.max_compute_workgroup_size_x,
        max_compute_workgroup_size_y: a.max_compute_workgroup_size_y,
        ..Default::default()
    };
    if a.max_multiview_view_count < 6 {
        required.remove(wgpu::Features::MULTIVIEW);
        limits.max_multiview_view_count = 0;
    }
    let rays = required.contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY);
    if rays {
        // The adapter's own acceleration-structure limits: wgpu's guaranteed minimums exceed
        // some drivers' (lavapipe's BLAS primitive count).
        limits = limits.using_acceleration_structure_values(a);
    }
    wgpu::DeviceDescriptor {
        label: Some("lightbench"),
        required_features: required,
        required_limits: limits,
        // SAFETY: asked for only where the adapter exposes ray queries; wgpu's experimental
        // flag acknowledges its ray-query implementation may still have bugs (what we use of
        // it: BLAS/TLAS builds and inline ray queries, tested on lavapipe in CI).
        experimental_features: match rays {
            true => unsafe { wgpu::ExperimentalFeatures::enabled() },
            false => wgpu::ExperimentalFeatures::disabled(),
        },
        memory_hints: wgpu::MemoryHints::Performance,
        trace: wgpu::Trace::Off,
    }
}

fn desc_backends(opts: &DeviceOptions) -> wgpu::Backends {
    match opts.backend {
        Some(BackendChoice::Vulkan) => wgpu::Backends::VULKAN,
        Some(BackendChoice::Gl) => wgpu::Backends::GL,
        None => wgpu::Backends::PRIMARY | wgpu::Backends::GL,
    }
}

/// The compiler's view of the device limits.
pub fn profile_limits(l: &wgpu::Limits) -> Limits {
    Limits {
        max_texture_dimension_2d: l.max_texture_dimension_2d as u64,
        max_texture_array_layers: l.max_texture_array_layers as u64,
        max_bind_groups: l.max_bind_groups as u64,
        max_bindings_per_bind_group: l.max_bindings_per_bind_group as u64,
        max_color_attachments: l.max_color_attachments as u64,
        max_color_attachment_bytes_per_sample: l.max_color_attachment_bytes_per_sample as u64,
        max_uniform_buffer_binding_size: l.max_uniform_buffer_binding_size,
        max_storage_buffer_binding_size: l.max_storage_buffer_binding_size,
        max_sampled_textures_per_shader_stage: l.max_sampled_textures_per_shader_stage as u64,
        max_samplers_per_shader_stage: l.max_samplers_per_shader_stage as u64,
        max_storage_textures_per_shader_stage: l.max_storage_textures_per_shader_stage as u64,
        max_uniform_buffers_per_shader_stage: l.max_uniform_buffers_per_shader_stage as u64,
        max_storage_buffers_per_shader_stage: l.max_storage_buffers_per_shader_stage as u64,
        max_compute_workgroup_size_x: l.max_compute_workgroup_size_x as u64,
        max_compute_workgroup_size_y: l.max_compute_workgroup_size_y as u64,
        max_compute_workgroup_size_z: l.max_compute_workgroup_size_z as u64,
        max_compute_invocations_per_workgroup: l.max_compute_invocations_per_workgroup as u64,
        max_multiview_view_count: l.max_multiview_view_count as u64,
        max_buffer_size: l.max_buffer_size,
        max_compute_workgroups_per_dimension: l.max_compute_workgroups_per_dimension as u64,
    }
}

/// Render two views into a 2-layer target and check that view 1 reached layer 1.
fn multiview_works(device: &wgpu::Device, queue: &wgpu::Queue) -> bool {
    const SRC: &str = "struct O { @builtin(position) p: vec4<f32>, @location(0) @interpolate(flat) v: u32 };
@vertex fn vs(@builtin(vertex_index) i: u32, @builtin(view_index) view: u32) -> O {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return O(vec4<f32>(uv * 2.0 - 1.0, 0.5, 1.0), view);
}
@fragment fn fs(o: O) -> @location(0) vec4<f32> { return vec4<f32>(f32(o.v + 1u) * 0.25); }";
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("multiview probe"),
        source: wgpu::ShaderSource::Wgsl(SRC.into()),
    });
    let mask = std::num::NonZeroU32::new(0b11);
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("multiview probe"),
        layout: None,
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: wgpu::TextureFormat::R8Unorm,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: mask,
        cache: None,
    });
    let tex = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("multiview probe"),
        size: wgpu::Extent3d {
            width: 4,
            height: 4,
            depth_or_array_layers: 2,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R8Unorm,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = tex.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        array_layer_count: Some(2),
        ..Default::default()
    });
    let buf = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 256 * 4 * 2,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: mask,
        });
        rp.set_pipeline(&pipeline);
        rp.draw(0..3, 0..1);
    }
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture: &tex,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buf,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(256),
                rows_per_image: Some(4),
            },
        },
        wgpu::Extent3d {
            width: 4,
            height: 4,
            depth_or_array_layers: 2,
        },
    );
    queue.submit([enc.finish()]);
    if pollster::block_on(scope.pop()).is_some() {
        return false;
    }
    let slice = buf.slice(..);
    slice.map_async(wgpu::MapMode::Read, |_| {});
    if device.poll(wgpu::PollType::wait_indefinitely()).is_err() {
        return false;
    }
    let ok = match slice.get_mapped_range() {
        Ok(data) => {
            let (l0, l1) = (data[0] as i32, data[256 * 4] as i32);
            (l0 - 64).abs() <= 2 && (l1 - 128).abs() <= 2
        }
        Err(_) => false,
    };
    buf.unmap();
    ok
}
