//! Scene buffers against the device's limits: what a device cannot hold is refused by name, as
//! a value (exit 1 from the CLI), never a panic; what no pass reads is not built.

use crate::gpu_common::root;
use lightbench::gpu::{device, Executor, Gpu, HostOptions};

const LIMIT: u64 = 1 << 20;

/// A device whose buffers hold at most 2 MiB and storage bindings 1 MiB, as a host may open it.
fn small_device() -> Gpu {
    device_with(|l| {
        l.max_buffer_size = 2 * LIMIT;
        l.max_storage_buffer_binding_size = LIMIT;
    })
}

/// A device opened as lightbench opens it, its limits then changed by `limit`.
fn device_with(limit: impl Fn(&mut wgpu::Limits)) -> Gpu {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter =
        pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default())).expect("an adapter (CI installs lavapipe)");
    let mut desc = device::device_descriptor(&adapter);
    limit(&mut desc.required_limits);
    let (dev, queue) = pollster::block_on(adapter.request_device(&desc)).unwrap();
    Gpu::from_host(adapter, dev, queue, HostOptions { probe: false }).unwrap()
}

/// A flat n × n grid of vertices (2 (n − 1)² triangles) on the Cornell box's floor, its
/// shading normals leaning outwards (so each triangle shades apart).
fn grid(n: u32) -> lightbench::scene::Mesh {
    let vertex = |i: u32| lightbench::blocks::Vertex {
        position: [(i % n) as f32 / n as f32 - 0.5, 0.01, (i / n) as f32 / n as f32 - 0.5],
        normal: glam::Vec3::new((i % n) as f32 / n as f32 - 0.5, 1.0, (i / n) as f32 / n as f32 - 0.5)
            .normalize()
            .to_array(),
        uv: [(i % n) as f32 / n as f32, (i / n) as f32 / n as f32],
        tangent: [1.0, 0.0, 0.0, 1.0],
        uv1: [0.0; 2],
    };
    let cells = (0..n - 1).flat_map(|y| (0..n - 1).map(move |x| y * n + x));
    let indices = cells.flat_map(|c| [c, c + n, c + 1, c + 1, c + n, c + n + 1]).collect();
    crate::gpu_common::mesh("grid", ((0..n * n).map(vertex).collect(), indices), glam::Mat4::IDENTITY)
}

fn cornell_with(mesh: lightbench::scene::Mesh) -> lightbench::scene::Scene {
    let mut s = lightbench::scene::load("cornell").unwrap();
    s.size = (32, 32);
    s.effects.insert(lightbench_compiler::ir::Effect::AmbientOcclusion);
    s.meshes.push(mesh);
    s
}

fn executor(gpu: &Gpu, pipeline: &str, variants: &[(&str, &str)], s: &lightbench::scene::Scene) -> lightbench::gpu::Result<Executor> {
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let (exe, _) =
        lightbench::render::compile(gpu, &root().join("pipelines").join(pipeline), None, s, &v).unwrap_or_else(|e| panic!("{e}"));
    Executor::new(gpu, &exe, s)
}

/// A 120² grid in the Cornell box: its vertex buffer (0.8 MiB) fits. The default pipeline
/// renders; ambient occlusion volumes (`ao = aov`) read the `triangles` binding (28,356
/// triangles, 1.3 MiB, over the storage-binding size), a table of texels, and render as on a
/// device as lightbench opens it. A 200² grid's vertex buffer (2.1 MiB) is refused by the
/// mesh's name.
#[test]
fn buffers_over_the_device_limits_are_refused_by_name() {
    let gpu = small_device();
    let s = cornell_with(grid(120));
    let mut ex = executor(&gpu, "deferred.lbp", &[], &s).unwrap_or_else(|e| panic!("{e}"));
    ex.render_frame(&gpu, &ex.inputs(0.0)).unwrap();
    let img = ex.read_texture(&gpu, "hdr", 0, 0).unwrap();
    assert!(img.rgba.iter().all(|v| v.is_finite()) && img.rgba.iter().any(|v| *v > 0.0));

    let aov = |gpu: &Gpu| {
        let mut ex = executor(gpu, "deferred_gi.lbp", &[("ao", "aov")], &s).unwrap_or_else(|e| panic!("{e}"));
        ex.render_frame(gpu, &ex.inputs(0.0)).unwrap();
        ex.read_texture(gpu, "hdr", 0, 0).unwrap().rgba
    };
    let small = aov(&gpu);
    assert!(small.iter().all(|v| v.is_finite()));
    assert!(small == aov(&device_with(|_| {})), "the same volumes from the table");

    let err = executor(&gpu, "deferred.lbp", &[], &cornell_with(grid(200)))
        .err()
        .expect("the mesh does not fit")
        .to_string();
    for want in ["mesh `grid` of scene `cornell`: its vertex buffer", "max_buffer_size of 2.0 MiB"] {
        assert!(err.contains(want), "{err}");
    }
    assert!(gpu.take_uncaptured().is_empty(), "no error escaped: {:?}", gpu.take_uncaptured());
}

/// The path tracer on a device of 1 MiB storage bindings: the grid's ray-hit data (1.7 MiB)
/// and the scene's five 256² maps (1.25 MiB) exceed its storage bindings but are tables of
/// texels (`shaders/lib/table.wgsl`), so the pass renders — and renders the same where the
/// device's 256-texel side splits the tables into layers (113,424 texels of triangles: 2
/// layers of 256 rows; 170,136 of corners: 3; 81,936 of maps: 2), and on a device as
/// lightbench opens it (one layer of 2048-texel rows). A device of two layers refuses the
/// corners' table, naming the figure and the limit, and so does a device whose largest
/// allocation is smaller than that table.
#[test]
fn ray_hit_data_past_the_storage_binding_size_renders_in_layers() {
    let mut s = cornell_with(grid(120));
    // Five 256² maps of stripes, the last on the grid, seen by the camera's rays.
    for width in [4, 6, 8, 10, 12] {
        let stripes = (0..256 * 256u32).flat_map(|i| {
            if (i % 256 / width) % 2 == 0 {
                [230, 60, 40, 255]
            } else {
                [40, 200, 90, 255]
            }
        });
        s.textures.push(lightbench::scene::ImageData {
            width: 256,
            height: 256,
            rgba: stripes.collect(),
            srgb: true,
        });
    }
    let mut material = lightbench::scene::Material::color("stripes", [1.0; 3], 0.6);
    material.base_color_texture = Some(s.textures.len() - 1);
    s.materials.push(material);
    s.meshes.last_mut().unwrap().material = s.materials.len() - 1;
    let render = |gpu: &Gpu| {
        let mut ex = executor(gpu, "pathtrace.lbp", &[("term", "direct")], &s).unwrap_or_else(|e| panic!("{e}"));
        ex.render_frame(gpu, &ex.inputs(0.0)).unwrap();
        assert!(gpu.take_uncaptured().is_empty(), "no error escaped: {:?}", gpu.take_uncaptured());
        ex.read_texture(gpu, "hdr", 0, 0).unwrap().rgba
    };
    let rows = render(&device_with(|l| l.max_storage_buffer_binding_size = LIMIT));
    let layers = render(&device_with(|l| {
        l.max_storage_buffer_binding_size = LIMIT;
        l.max_texture_dimension_2d = 256;
    }));
    assert!(rows.iter().all(|v| v.is_finite()) && rows.iter().any(|v| *v > 0.0));
    let differ = |a: &[f32], b: &[f32]| a.iter().zip(b).filter(|(x, y)| x != y).count();
    assert_eq!(differ(&rows, &layers), 0, "the same hits, whatever the table's shape");
    assert_eq!(differ(&rows, &render(&device_with(|_| {}))), 0);

    // The path tracer refused on `gpu`, its error holding each of `want`.
    let refused = |gpu: &Gpu, want: [&str; 2]| {
        let err = executor(gpu, "pathtrace.lbp", &[("term", "direct")], &s)
            .err()
            .expect("refused")
            .to_string();
        assert!(want.iter().all(|w| err.contains(w)), "{err}");
    };
    // Two layers of 256² texels hold the triangles' table but not the corners' (3 layers).
    let few_layers = device_with(|l| {
        l.max_texture_dimension_2d = 256;
        l.max_texture_array_layers = 2;
    });
    refused(
        &few_layers,
        [
            "scene `cornell`: the texture coordinates of its 28356 traced triangles needs 3 layers of 256×256 texels",
            "over this device's max_texture_array_layers of 2",
        ],
    );
    // A table is one allocation: the corners' 84 rows of 2048 texels pad to 128 (4 MiB), over
    // the small device's largest (2 MiB); the triangles' 56 rows pad to 64 (2 MiB) and fit.
    refused(
        &small_device(),
        [
            "the texture coordinates of its 28356 traced triangles needs a texture of 4.0 MiB (2048×128×1 texels)",
            "over this device's largest allocation (max_buffer_size) of 2.0 MiB",
        ],
    );
}
