//! `cargo bench -p lightbench --bench overhead`: what running `pipelines/deferred.ron` through
//! the Plan executor costs against a small wgpu renderer written by hand for the same passes
//! (here, in the bench: not part of the product). Needs a GPU adapter (lavapipe is enough);
//! `cargo test` runs it at its smallest (2 rounds of a frame), image check included.
//!
//! The Cornell box at 128×128 runs seven passes: G-buffer, six cube-shadow faces, ambient,
//! the point light, the luminance reduction (tiles, then the tiles) and the tone map. The
//! hand-written renderer shares nothing with the executor: it reads the shader files and
//! expands their `#include`s itself, draws the full-screen triangle with its own vertex shader,
//! uploads the scene's meshes and writes their mesh and material blocks itself, and builds its
//! own textures, layouts, pipelines, parameter blocks and bind groups; what it takes from
//! lightbench is the scene (the input: meshes, materials, camera, and each light's block as the
//! scene crate computes it, `Light::block`) and the block structs that mirror the shaders'
//! declarations (`abi`, checked against the WGSL by naga). It renders the same image, bit for
//! bit (checked). Reported: the wall time of a
//! frame on each side, each waiting for its frame, in interleaved rounds: the median and
//! quartiles of the per-round ratio (goal ≤ 1.05×), and the executor's CPU encode time per
//! pass (goal ≤ 20 µs).

use lightbench::blocks::{FrameBlock, InstanceBlock, LightBlock, Vertex};
use lightbench::gpu::{DeviceOptions, Executor, Gpu};
use lightbench::scene::{builtin, Scene};
use std::path::{Path, PathBuf};
use wgpu::util::DeviceExt;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{interleaved, ms, Size};

/// The passes of `deferred.ron` at its defaults, which the hand-written renderer mirrors.
const PASSES: [&str; 7] = [
    "gbuffer",
    "shadow_cube_classic",
    "ambient",
    "light_point",
    "luminance_tiles",
    "luminance",
    "tonemap",
];
const SIZE: (u32, u32) = (128, 128);
const CUBE: u32 = 512;

fn texture(
    gpu: &Gpu,
    label: &str,
    (w, h, layers): (u32, u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn view(t: &wgpu::Texture) -> wgpu::TextureView {
    t.create_view(&Default::default())
}

fn shader_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders")
}

/// A shader file's text with each `#include "path"` line (a path below the shader root)
/// replaced by that file's, each file once — read and expanded here, not by the compiler.
fn expanded(path: &str, seen: &mut Vec<String>) -> String {
    let text = std::fs::read_to_string(shader_root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut out = String::new();
    for line in text.lines() {
        let Some(rest) = line.trim_start().strip_prefix("#include") else {
            out.push_str(line);
            out.push('\n');
            continue;
        };
        let included = rest.trim().trim_matches('"').to_string();
        if !seen.contains(&included) {
            seen.push(included.clone());
            out.push_str(&expanded(&included, seen));
        }
    }
    out
}

fn module(gpu: &Gpu, path: &str) -> wgpu::ShaderModule {
    gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(path),
        source: wgpu::ShaderSource::Wgsl(expanded(path, &mut vec![path.to_string()]).into()),
    })
}

/// The full-screen passes' vertex stage: one triangle over the target.
const FULLSCREEN_VS: &str = "@vertex\nfn fullscreen_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {\n    \
let x = f32((i << 1u) & 2u);\n    let y = f32(i & 2u);\n    return vec4<f32>(x * 2.0 - 1.0, 1.0 - y * 2.0, 0.0, 1.0);\n}\n";

/// A full-screen pass's modules: the vertex stage's, then the fragment shader's.
fn screen_modules(gpu: &Gpu, path: &str) -> [wgpu::ShaderModule; 2] {
    let vs = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("fullscreen_vs"),
        source: wgpu::ShaderSource::Wgsl(FULLSCREEN_VS.into()),
    });
    [vs, module(gpu, path)]
}

/// Layout entries: (binding, type).
fn layout(gpu: &Gpu, entries: &[(u32, wgpu::BindingType)]) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = entries
        .iter()
        .map(|(binding, ty)| wgpu::BindGroupLayoutEntry {
            binding: *binding,
            // Writable storage in a vertex stage needs a feature: compute and fragment only.
            visibility: match ty {
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: false },
                    ..
                }
                | wgpu::BindingType::StorageTexture { .. } => wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                _ => wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
            },
            ty: *ty,
            count: None,
        })
        .collect();
    gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: None,
        entries: &entries,
    })
}

fn group(gpu: &Gpu, layout: &wgpu::BindGroupLayout, entries: &[(u32, wgpu::BindingResource)]) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = entries
        .iter()
        .map(|(binding, r)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: r.clone(),
        })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout,
        entries: &entries,
    })
}

const UNIFORM: wgpu::BindingType = wgpu::BindingType::Buffer {
    ty: wgpu::BufferBindingType::Uniform,
    has_dynamic_offset: false,
    min_binding_size: None,
};

const fn storage(read_only: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

const fn tex(sample_type: wgpu::TextureSampleType, dim: wgpu::TextureViewDimension) -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type,
        view_dimension: dim,
        multisampled: false,
    }
}

const FLOAT: wgpu::BindingType = tex(wgpu::TextureSampleType::Float { filterable: true }, wgpu::TextureViewDimension::D2);
const UNFILTERED: wgpu::BindingType = tex(wgpu::TextureSampleType::Float { filterable: false }, wgpu::TextureViewDimension::D2);

fn uniform(gpu: &Gpu, bytes: &[u8]) -> wgpu::Buffer {
    gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytes,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    })
}

fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// The scene's vertex layout (`shaders/lib/mesh.wgsl`'s `VertexIn`).
fn vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    const ATTRS: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![
        0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4, 4 => Float32x2
    ];
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &ATTRS,
    }
}

struct RenderPipe<'a> {
    modules: &'a [wgpu::ShaderModule],
    entries: (&'a str, Option<&'a str>),
    layouts: &'a [&'a wgpu::BindGroupLayout],
    scene_vertices: bool,
    color: &'a [wgpu::TextureFormat],
    depth: Option<(wgpu::CompareFunction, bool)>,
    cull: Option<wgpu::Face>,
    blend: Option<wgpu::BlendState>,
}

fn render_pipeline(gpu: &Gpu, p: RenderPipe) -> wgpu::RenderPipeline {
    let layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: None,
        bind_group_layouts: &p.layouts.iter().map(|l| Some(*l)).collect::<Vec<_>>(),
        immediate_size: 0,
    });
    let buffers = if p.scene_vertices { vec![Some(vertex_layout())] } else { vec![] };
    let targets: Vec<Option<wgpu::ColorTargetState>> = p
        .color
        .iter()
        .map(|f| {
            Some(wgpu::ColorTargetState {
                format: *f,
                blend: p.blend,
                write_mask: wgpu::ColorWrites::ALL,
            })
        })
        .collect();
    let fs_module = p.modules.last().expect("a module");
    gpu.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: None,
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: &p.modules[0],
            entry_point: Some(p.entries.0),
            compilation_options: Default::default(),
            buffers: &buffers,
        },
        fragment: p.entries.1.map(|e| wgpu::FragmentState {
            module: fs_module,
            entry_point: Some(e),
            compilation_options: Default::default(),
            targets: &targets,
        }),
        primitive: wgpu::PrimitiveState {
            cull_mode: p.cull,
            ..Default::default()
        },
        depth_stencil: p.depth.map(|(compare, write)| wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    })
}

/// The hand-written renderer: everything made up front, one encoder per frame.
struct Hand {
    frame: wgpu::Buffer,
    lights: wgpu::Buffer,
    meshes: Vec<HandMesh>,
    pipes: [wgpu::RenderPipeline; 5],
    /// The luminance reduction: tiles, then the tiles in one workgroup.
    luminance: [wgpu::ComputePipeline; 2],
    tiles: (u32, u32),
    /// Per mesh: the G-buffer's material group and the shadow pass's mesh group.
    mesh_groups: Vec<(wgpu::BindGroup, wgpu::BindGroup)>,
    frame_group: wgpu::BindGroup,
    /// The shadow pass's group 0, one per cube face; the light pass's.
    face_groups: Vec<wgpu::BindGroup>,
    light_group0: wgpu::BindGroup,
    /// Group 2 of ambient, the point light, the two luminance passes and the tone map.
    groups2: [wgpu::BindGroup; 5],
    empty: wgpu::BindGroup,
    views: Views,
}

struct Views {
    gbuf: [wgpu::TextureView; 3],
    depth: wgpu::TextureView,
    faces: Vec<wgpu::TextureView>,
    hdr: wgpu::TextureView,
    ldr: wgpu::TextureView,
    ldr_texture: wgpu::Texture,
}

/// A mesh as the hand-written renderer uploads it.
struct HandMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    /// Its mesh block (`shaders/lib/mesh.wgsl`) and material block (`lib/material.wgsl`).
    block: wgpu::Buffer,
    material: wgpu::Buffer,
}

/// The scene's meshes uploaded, with their mesh and material blocks packed here. The bench
/// scene has no textures: every map is a 1×1 default (checked).
fn upload(gpu: &Gpu, scene: &Scene) -> Vec<HandMesh> {
    let buffer = |contents: &[u8], usage| {
        gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents,
            usage,
        })
    };
    let drawn = scene.meshes.iter().filter(|m| !m.vertices.is_empty() && !m.indices.is_empty());
    drawn
        .map(|m| {
            let mat = &scene.materials[m.material];
            let maps = [
                mat.base_color_texture,
                mat.normal_texture,
                mat.metallic_roughness_texture,
                mat.emissive_texture,
                mat.occlusion_texture,
            ];
            assert!(maps.iter().all(Option::is_none), "the bench scene has no textures");
            // model, then the normal matrix (the inverse transpose), column by column.
            let mut block = f32s(&m.transform.to_cols_array());
            block.extend(f32s(&m.transform.inverse().transpose().to_cols_array()));
            // base colour, emissive, the UV transform's rows, then the scalars.
            let [r0, r1] = mat.uv_transform;
            let mut material = f32s(&mat.base_color);
            for v in [[mat.emissive[0], mat.emissive[1], mat.emissive[2]], r0, r1] {
                material.extend(f32s(&[v[0], v[1], v[2], 0.0]));
            }
            material.extend(f32s(&[mat.metallic, mat.roughness, mat.normal_scale]));
            material.extend(0u32.to_le_bytes()); // no normal map
            let cutoff = match mat.alpha {
                lightbench::scene::AlphaMode::Mask(c) => c,
                _ => 0.0,
            };
            material.extend(f32s(&[cutoff, 0.0])); // no occlusion map: strength 0
            material.extend(mat.uv_sets.to_le_bytes());
            material.extend((mat.double_sided as u32).to_le_bytes());
            HandMesh {
                vertices: buffer(bytemuck::cast_slice(&m.vertices), wgpu::BufferUsages::VERTEX),
                indices: buffer(bytemuck::cast_slice(&m.indices), wgpu::BufferUsages::INDEX),
                index_count: m.drawn_indices(),
                block: buffer(&block, wgpu::BufferUsages::UNIFORM),
                material: buffer(&material, wgpu::BufferUsages::UNIFORM),
            }
        })
        .collect()
}

/// A 1×1 texture of one texel (the default of a map a material does not have).
fn texel(gpu: &Gpu, rgba: [u8; 4], format: wgpu::TextureFormat) -> wgpu::TextureView {
    let usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
    let t = texture(gpu, "default map", (1, 1, 1), format, usage);
    gpu.queue.write_texture(
        t.as_image_copy(),
        &rgba,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4),
            rows_per_image: None,
        },
        wgpu::Extent3d {
            width: 1,
            height: 1,
            depth_or_array_layers: 1,
        },
    );
    view(&t)
}

impl Hand {
    fn new(gpu: &Gpu, scene: &Scene) -> Hand {
        use wgpu::TextureFormat as F;
        use wgpu::TextureUsages as U;
        let (w, h) = SIZE;
        let rt = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING;
        let gbuf = [
            texture(gpu, "gbuf.normal", (w, h, 1), F::Rgba16Uint, rt),
            texture(gpu, "gbuf.albedo", (w, h, 1), F::Rgba8Unorm, rt),
            texture(gpu, "gbuf.emissive", (w, h, 1), F::Rgba16Float, rt),
        ];
        let depth = texture(gpu, "gbuf.depth", (w, h, 1), F::Depth32Float, rt);
        let cube = texture(gpu, "shadow.cube", (CUBE, CUBE, 6), F::Depth32Float, rt);
        let hdr = texture(gpu, "hdr", (w, h, 1), F::Rgba16Float, rt);
        let ldr_texture = texture(gpu, "ldr", (w, h, 1), F::Rgba8UnormSrgb, rt | U::COPY_SRC);
        // `texture lum.tiles: Rgba32Float viewport*0.0625`, `buffer lum: 28 bytes`.
        let tiles = (w.div_ceil(16), h.div_ceil(16));
        let lum_tiles = texture(
            gpu,
            "lum.tiles",
            (tiles.0, tiles.1, 1),
            F::Rgba32Float,
            U::STORAGE_BINDING | U::TEXTURE_BINDING,
        );
        let lum = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lum"),
            size: 28,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let frame = uniform(gpu, &[0; std::mem::size_of::<FrameBlock>()]);
        let lights = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lights"),
            size: (std::mem::size_of::<LightBlock>() * scene.lights.len().max(1)) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let instances: Vec<wgpu::Buffer> = (0..6)
            .map(|face| {
                let block = InstanceBlock {
                    light: 0,
                    face,
                    view_count: 1,
                    mip: 0,
                    target_size: [CUBE as f32, CUBE as f32, 1.0 / CUBE as f32, 1.0 / CUBE as f32],
                    ..Default::default()
                };
                uniform(gpu, bytemuck::bytes_of(&block))
            })
            .collect();
        let screen_instance = uniform(
            gpu,
            bytemuck::bytes_of(&InstanceBlock {
                light: 0,
                face: 0,
                view_count: 1,
                mip: 0,
                target_size: [w as f32, h as f32, 1.0 / w as f32, 1.0 / h as f32],
                ..Default::default()
            }),
        );
        // Parameter blocks at the pipeline's defaults.
        let ambient = uniform(gpu, &f32s(&[0.03, 0.03, 0.035, 0.0]));
        // light_point: cube.bias_texels, cube.pcf (off), cube.normal_offset_texels.
        let mut cube_params = f32s(&[1.0]);
        cube_params.extend(0u32.to_le_bytes());
        cube_params.extend(f32s(&[2.0, 0.0]));
        let point = uniform(gpu, &cube_params);
        // luminance_tiles: by_luminance; luminance_reduce: key, automatic, ev, by_luminance,
        // tau_brighter, tau_darker (padded to 16 bytes).
        let by_luminance = uniform(gpu, &[0; 16]);
        let mut metering = f32s(&[0.18]);
        metering.extend(1u32.to_le_bytes());
        metering.extend(f32s(&[0.0]));
        metering.extend(0u32.to_le_bytes());
        metering.extend(f32s(&[0.5, 2.0, 0.0, 0.0]));
        let exposure = uniform(gpu, &metering);
        let cmp = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });

        let depth_tex = tex(wgpu::TextureSampleType::Depth, wgpu::TextureViewDimension::Cube);
        let l0_frame = layout(gpu, &[(0, UNIFORM)]);
        let l0_light = layout(gpu, &[(0, UNIFORM), (1, UNIFORM), (2, storage(true))]);
        let l0_empty = layout(gpu, &[]);
        let l1_material = layout(
            gpu,
            &[
                (0, UNIFORM),
                (1, UNIFORM),
                (2, FLOAT),
                (3, FLOAT),
                (4, FLOAT),
                (5, FLOAT),
                (6, wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering)),
                (7, FLOAT),
            ],
        );
        let l1_mesh = layout(gpu, &[(0, UNIFORM)]);
        let l2_ambient = layout(gpu, &[(0, FLOAT), (1, FLOAT), (2, UNIFORM)]);
        let l2_point = layout(
            gpu,
            &[
                (0, UNFILTERED),
                (1, tex(wgpu::TextureSampleType::Uint, wgpu::TextureViewDimension::D2)),
                (2, FLOAT),
                (3, depth_tex),
                (4, wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison)),
                (5, UNIFORM),
            ],
        );
        let tiles_out = wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format: F::Rgba32Float,
            view_dimension: wgpu::TextureViewDimension::D2,
        };
        let l2_tiles = layout(gpu, &[(0, FLOAT), (1, UNFILTERED), (2, tiles_out), (3, UNIFORM)]);
        let l2_reduce = layout(gpu, &[(0, UNFILTERED), (1, storage(false)), (2, UNIFORM)]);
        let l2_tonemap = layout(gpu, &[(0, FLOAT), (1, storage(true))]);

        let gm = [module(gpu, "gbuffer.wgsl")];
        let sm = [module(gpu, "shadow_cube_classic.wgsl")];
        let (am, pm, tm) = (
            screen_modules(gpu, "ambient.wgsl"),
            screen_modules(gpu, "light_point.wgsl"),
            screen_modules(gpu, "tonemap.wgsl"),
        );
        let add = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
        };
        let screen = |modules: &[wgpu::ShaderModule], layouts: &[&wgpu::BindGroupLayout], color: F, blend| {
            render_pipeline(
                gpu,
                RenderPipe {
                    modules,
                    entries: ("fullscreen_vs", Some("fs_main")),
                    layouts,
                    scene_vertices: false,
                    color: &[color],
                    depth: None,
                    cull: None,
                    blend,
                },
            )
        };
        let pipes = [
            render_pipeline(
                gpu,
                RenderPipe {
                    modules: &gm,
                    entries: ("vs_main", Some("fs_main")),
                    layouts: &[&l0_frame, &l1_material],
                    scene_vertices: true,
                    color: &[F::Rgba16Uint, F::Rgba8Unorm, F::Rgba16Float],
                    depth: Some((wgpu::CompareFunction::Less, true)),
                    // Both faces: the material says which are seen.
                    cull: None,
                    blend: None,
                },
            ),
            render_pipeline(
                gpu,
                RenderPipe {
                    modules: &sm,
                    entries: ("vs_main", None),
                    layouts: &[&l0_light, &l1_mesh],
                    scene_vertices: true,
                    color: &[],
                    depth: Some((wgpu::CompareFunction::Less, true)),
                    cull: None,
                    blend: None,
                },
            ),
            screen(&am, &[&l0_empty, &l0_empty, &l2_ambient], F::Rgba16Float, None),
            screen(&pm, &[&l0_light, &l0_empty, &l2_point], F::Rgba16Float, Some(add)),
            screen(&tm, &[&l0_empty, &l0_empty, &l2_tonemap], F::Rgba8UnormSrgb, None),
        ];
        let compute = |file: &str, l2: &wgpu::BindGroupLayout| {
            let layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: None,
                bind_group_layouts: &[Some(&l0_empty), Some(&l0_empty), Some(l2)],
                immediate_size: 0,
            });
            gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: None,
                layout: Some(&layout),
                module: &module(gpu, file),
                entry_point: Some("cs_main"),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let luminance = [
            compute("luminance_tiles.wgsl", &l2_tiles),
            compute("luminance_reduce.wgsl", &l2_reduce),
        ];

        // Every map at its default: base colour and emissive white (sRGB), the normal flat,
        // metallic-roughness and occlusion white.
        let (srgb, linear) = (F::Rgba8UnormSrgb, F::Rgba8Unorm);
        let white = texel(gpu, [255; 4], srgb);
        let flat = texel(gpu, [128, 128, 255, 255], linear);
        let white_linear = texel(gpu, [255; 4], linear);
        let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor::default());
        let meshes = upload(gpu, scene);
        let mesh_groups = meshes
            .iter()
            .map(|mesh| {
                let material = group(
                    gpu,
                    &l1_material,
                    &[
                        (0, mesh.block.as_entire_binding()),
                        (1, mesh.material.as_entire_binding()),
                        (2, wgpu::BindingResource::TextureView(&white)),
                        (3, wgpu::BindingResource::TextureView(&flat)),
                        (4, wgpu::BindingResource::TextureView(&white_linear)),
                        (5, wgpu::BindingResource::TextureView(&white)),
                        (6, wgpu::BindingResource::Sampler(&sampler)),
                        (7, wgpu::BindingResource::TextureView(&white_linear)),
                    ],
                );
                (material, group(gpu, &l1_mesh, &[(0, mesh.block.as_entire_binding())]))
            })
            .collect();
        let frame_group = group(gpu, &l0_frame, &[(0, frame.as_entire_binding())]);
        let light_group = |instance: &wgpu::Buffer| {
            group(
                gpu,
                &l0_light,
                &[
                    (0, frame.as_entire_binding()),
                    (1, instance.as_entire_binding()),
                    (2, lights.as_entire_binding()),
                ],
            )
        };
        let face_groups = instances.iter().map(light_group).collect();
        let light_group0 = light_group(&screen_instance);
        let gv: Vec<wgpu::TextureView> = gbuf.iter().map(view).collect();
        let depth_view = view(&depth);
        let cube_view = cube.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::Cube),
            ..Default::default()
        });
        let hdr_view = view(&hdr);
        let tv = wgpu::BindingResource::TextureView;
        let groups2 = [
            group(
                gpu,
                &l2_ambient,
                &[(0, tv(&gv[1])), (1, tv(&gv[2])), (2, ambient.as_entire_binding())],
            ),
            group(
                gpu,
                &l2_point,
                &[
                    (0, tv(&depth_view)),
                    (1, tv(&gv[0])),
                    (2, tv(&gv[1])),
                    (3, tv(&cube_view)),
                    (4, wgpu::BindingResource::Sampler(&cmp)),
                    (5, point.as_entire_binding()),
                ],
            ),
            group(
                gpu,
                &l2_tiles,
                &[
                    (0, tv(&hdr_view)),
                    (1, tv(&depth_view)),
                    (2, tv(&view(&lum_tiles))),
                    (3, by_luminance.as_entire_binding()),
                ],
            ),
            group(
                gpu,
                &l2_reduce,
                &[
                    (0, tv(&view(&lum_tiles))),
                    (1, lum.as_entire_binding()),
                    (2, exposure.as_entire_binding()),
                ],
            ),
            group(gpu, &l2_tonemap, &[(0, tv(&hdr_view)), (1, lum.as_entire_binding())]),
        ];
        let empty = group(gpu, &l0_empty, &[]);
        let faces = (0..6)
            .map(|f| {
                cube.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: f,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let [n, a, e] = [&gbuf[0], &gbuf[1], &gbuf[2]].map(view);
        Hand {
            frame,
            lights,
            meshes,
            pipes,
            luminance,
            tiles,
            mesh_groups,
            frame_group,
            face_groups,
            light_group0,
            groups2,
            empty,
            views: Views {
                gbuf: [n, a, e],
                depth: depth_view,
                faces,
                hdr: hdr_view,
                ldr: view(&ldr_texture),
                ldr_texture,
            },
        }
    }
}

fn color<'a>(v: &'a wgpu::TextureView, load: wgpu::LoadOp<wgpu::Color>) -> Option<wgpu::RenderPassColorAttachment<'a>> {
    Some(wgpu::RenderPassColorAttachment {
        view: v,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        },
    })
}

fn depth(v: &wgpu::TextureView, load: wgpu::LoadOp<f32>) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
    Some(wgpu::RenderPassDepthStencilAttachment {
        view: v,
        depth_ops: Some(wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    })
}

fn pass<'a>(
    enc: &'a mut wgpu::CommandEncoder,
    colors: &[Option<wgpu::RenderPassColorAttachment>],
    d: Option<wgpu::RenderPassDepthStencilAttachment>,
) -> wgpu::RenderPass<'a> {
    enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: None,
        color_attachments: colors,
        depth_stencil_attachment: d,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

impl Hand {
    /// The uniforms the executor writes each frame: camera and lights.
    fn write_blocks(&self, gpu: &Gpu, scene: &Scene, time: f32) {
        let (w, h) = SIZE;
        let cam = &scene.camera;
        let view = cam.view();
        let proj = cam.proj(w as f32 / h as f32);
        let vp = proj * view;
        let bounds = scene.bounds();
        let block = FrameBlock {
            view: view.to_cols_array_2d(),
            proj: proj.to_cols_array_2d(),
            view_proj: vp.to_cols_array_2d(),
            inv_view_proj: vp.inverse().to_cols_array_2d(),
            prev_view_proj: vp.to_cols_array_2d(),
            prev_inv_view_proj: vp.inverse().to_cols_array_2d(),
            camera_pos: cam.position.extend(1.0).to_array(),
            resolution: [w as f32, h as f32, 1.0 / w as f32, 1.0 / h as f32],
            jitter: [0.0; 4],
            time,
            frame_index: 0,
            light_count: scene.lights.len() as u32,
            scene_radius: (bounds.1 - bounds.0).length() * 0.5,
        };
        gpu.queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&block));
        let lights: Vec<LightBlock> = scene.lights.iter().map(|l| l.at(time).block(bounds)).collect();
        gpu.queue.write_buffer(&self.lights, 0, bytemuck::cast_slice(&lights));
    }

    fn frame(&self, gpu: &Gpu, scene: &Scene, time: f32) {
        self.write_blocks(gpu, scene, time);
        let v = &self.views;
        let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        let meshes = |rp: &mut wgpu::RenderPass, material: bool| {
            for (mesh, (mg, meshg)) in self.meshes.iter().zip(&self.mesh_groups) {
                rp.set_bind_group(1, if material { mg } else { meshg }, &[]);
                rp.set_vertex_buffer(0, mesh.vertices.slice(..));
                rp.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                rp.draw_indexed(0..mesh.index_count, 0, 0..1);
            }
        };
        {
            let colors: Vec<_> = v.gbuf.iter().map(|g| color(g, clear)).collect();
            let mut rp = pass(&mut enc, &colors, depth(&v.depth, wgpu::LoadOp::Clear(1.0)));
            rp.set_pipeline(&self.pipes[0]);
            rp.set_bind_group(0, &self.frame_group, &[]);
            meshes(&mut rp, true);
        }
        for (face, g) in v.faces.iter().zip(&self.face_groups) {
            let mut rp = pass(&mut enc, &[], depth(face, wgpu::LoadOp::Clear(1.0)));
            rp.set_pipeline(&self.pipes[1]);
            rp.set_bind_group(0, g, &[]);
            meshes(&mut rp, false);
        }
        let screen =
            |enc: &mut wgpu::CommandEncoder, target: &wgpu::TextureView, load, pipe: usize, g0: &wgpu::BindGroup, g2: &wgpu::BindGroup| {
                let mut rp = pass(enc, &[color(target, load)], None);
                rp.set_pipeline(&self.pipes[pipe]);
                rp.set_bind_group(0, g0, &[]);
                rp.set_bind_group(1, &self.empty, &[]);
                rp.set_bind_group(2, g2, &[]);
                rp.draw(0..3, 0..1);
            };
        screen(
            &mut enc,
            &v.hdr,
            wgpu::LoadOp::Clear(wgpu::Color::BLACK),
            2,
            &self.empty,
            &self.groups2[0],
        );
        screen(&mut enc, &v.hdr, wgpu::LoadOp::Load, 3, &self.light_group0, &self.groups2[1]);
        // Tiles of 8×8 invocations over the tile texture, then one workgroup over the tiles.
        for (pipe, (g2, groups)) in self.luminance.iter().zip([
            (&self.groups2[2], (self.tiles.0.div_ceil(8), self.tiles.1.div_ceil(8))),
            (&self.groups2[3], (1, 1)),
        ]) {
            let mut cp = enc.begin_compute_pass(&Default::default());
            cp.set_pipeline(pipe);
            cp.set_bind_group(0, &self.empty, &[]);
            cp.set_bind_group(1, &self.empty, &[]);
            cp.set_bind_group(2, g2, &[]);
            cp.dispatch_workgroups(groups.0, groups.1, 1);
        }
        screen(&mut enc, &v.ldr, clear, 4, &self.empty, &self.groups2[4]);
        gpu.queue.submit([enc.finish()]);
        gpu.device.poll(wgpu::PollType::wait_indefinitely()).expect("wait");
    }
}

fn main() {
    let size = Size::from_args();
    let (rounds, frames) = (size.pick(20, 2), size.pick(10, 1));
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let mut scene = builtin::cornell();
    scene.size = SIZE;
    let pipeline = Path::new(env!("CARGO_MANIFEST_DIR")).join("../pipelines/deferred.ron");
    let (exe, _) = lightbench::render::compile(&gpu, &pipeline, None, &scene, &[]).expect("compile");
    let passes: Vec<&str> = exe.plan.passes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(passes, PASSES, "the hand-written renderer mirrors these passes");

    let mut ex = Executor::new(&gpu, &exe, &scene).expect("executor");
    ex.set_reuse(false);
    // Serial: each frame waited for as it is submitted, as the hand-written side does.
    ex.set_frames_in_flight(0);
    let hand = Hand::new(&gpu, &scene);

    // Both render the same image, bit for bit.
    ex.render_frame(&gpu, &ex.inputs(0.0)).expect("frame");
    hand.frame(&gpu, &scene, 0.0);
    let ours = ex.read_texture(&gpu, "ldr", 0, 0).expect("read");
    let theirs = lightbench::gpu::readback::read_texture(&gpu, &hand.views.ldr_texture, 0).expect("read");
    let e = lightbench::io::rmse(&ours, &theirs).expect("same size");
    println!("same image: RMSE {e} between the executor's and the hand-written renderer's output");
    assert_eq!(e, 0.0, "the renderers disagree");

    println!(
        "Executor overhead: deferred.ron on the Cornell box, {}×{}, {} passes; each side waits for each frame; ms per frame, {frames} frames a round",
        SIZE.0,
        SIZE.1,
        PASSES.len()
    );
    for timing in [false, true] {
        ex.set_timing(timing);
        let (mut encode_us, mut encoded) = (0.0, 0usize);
        let mut executor = |time: f32| {
            let inputs = ex.inputs(time);
            ex.render_frame(&gpu, &inputs).expect("frame");
            encode_us += ex.last_timings.iter().map(|t| t.cpu_encode_us).sum::<f64>();
            encoded += ex.last_timings.len();
        };
        let per_frame = |f: &mut dyn FnMut(f32)| ms(|| (0..frames).for_each(|i| f(i as f32 / 60.0))) / frames as f64;
        let p = interleaved(
            rounds,
            || per_frame(&mut |t| hand.frame(&gpu, &scene, t)),
            || per_frame(&mut executor),
        );
        if timing {
            println!("  with GPU timestamps per pass on the executor's side (the hand-written side has none):");
        } else {
            println!("  without timestamps (Executor::set_timing(false)), the like-for-like comparison (goal ≤ 1.05×):");
        }
        println!("{}", p.report(("hand-written wgpu", "Plan executor"), "ms"));
        if timing {
            println!(
                "  CPU encode per pass                {:>10.1} µs (goal ≤ 20 µs)",
                encode_us / encoded.max(1) as f64
            );
        }
    }
}
