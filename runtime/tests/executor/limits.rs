//! Scene buffers against the device's limits: what a device cannot hold is refused by name, as
//! a value (exit 1 from the CLI), never a panic; what no pass reads is not built.

use crate::gpu_common::root;
use lightbench::gpu::{device, Executor, Gpu, HostOptions};

const LIMIT: u64 = 1 << 20;

/// A device whose buffers hold at most 2 MiB and storage bindings 1 MiB, as a host may open it.
fn small_device() -> Gpu {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter =
        pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default())).expect("an adapter (CI installs lavapipe)");
    let mut desc = device::device_descriptor(&adapter);
    desc.required_limits.max_buffer_size = 2 * LIMIT;
    desc.required_limits.max_storage_buffer_binding_size = LIMIT;
    let (dev, queue) = pollster::block_on(adapter.request_device(&desc)).unwrap();
    Gpu::from_host(adapter, dev, queue, HostOptions { probe: false }).unwrap()
}

/// A flat n × n grid of vertices (2 (n − 1)² triangles) on the Cornell box's floor.
fn grid(n: u32) -> lightbench::scene::Mesh {
    let vertex = |i: u32| lightbench::blocks::Vertex {
        position: [(i % n) as f32 / n as f32 - 0.5, 0.01, (i / n) as f32 / n as f32 - 0.5],
        normal: [0.0, 1.0, 0.0],
        uv: [0.0; 2],
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

/// A 120² grid in the Cornell box: its vertex buffer (0.8 MiB) fits, the `triangles` binding
/// (28,356 triangles, 1.3 MiB) does not. The default pipeline reads no `triangles` and renders; ambient occlusion
/// volumes (`ao = aov`) read them and are refused with the figure and the limit, and so are
/// ray-traced shadows, whose ray-hit data does not fit. A 200² grid's vertex buffer (2.1 MiB)
/// is refused by the mesh's name.
#[test]
fn buffers_over_the_device_limits_are_refused_by_name() {
    let gpu = small_device();
    let s = cornell_with(grid(120));
    let mut ex = executor(&gpu, "deferred.lbp", &[], &s).unwrap_or_else(|e| panic!("{e}"));
    ex.render_frame(&gpu, &ex.inputs(0.0)).unwrap();
    let img = ex.read_texture(&gpu, "hdr", 0, 0).unwrap();
    assert!(img.rgba.iter().all(|v| v.is_finite()) && img.rgba.iter().any(|v| *v > 0.0));

    let err = executor(&gpu, "deferred_gi.lbp", &[("ao", "aov")], &s)
        .err()
        .expect("the triangles do not fit")
        .to_string();
    for want in [
        "`triangles` binding of its 28356 drawn triangles",
        "max_storage_buffer_binding_size of 1.0 MiB",
    ] {
        assert!(err.contains(want), "{err}");
    }

    let err = executor(&gpu, "deferred.lbp", &[], &cornell_with(grid(200)))
        .err()
        .expect("the mesh does not fit")
        .to_string();
    for want in ["mesh `grid` of scene `cornell`: its vertex buffer", "max_buffer_size of 2.0 MiB"] {
        assert!(err.contains(want), "{err}");
    }
    // Ray-traced shadows bind the scene's ray-hit data (64 B per triangle: 1.7 MiB here).
    let err = executor(&gpu, "deferred.lbp", &[("shadows", "rt")], &s)
        .err()
        .expect("the hit data does not fit")
        .to_string();
    for want in [
        "scene `cornell`: the ray-hit data of its 28356 traced triangles",
        "max_storage_buffer_binding_size of 1.0 MiB",
    ] {
        assert!(err.contains(want), "{err}");
    }
    assert!(gpu.take_uncaptured().is_empty(), "no error escaped: {:?}", gpu.take_uncaptured());
}
