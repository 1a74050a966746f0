//! The executor embedded in a host's device (README "Embedding"): the host's error handler
//! stays the host's, a frame recorded into the host's encoder renders what `render_frame`
//! renders, the host's matrices and lights drive the frame, and what does not fit the Plan
//! is refused.

use crate::gpu_common;

use gpu_common::*;
use lightbench::gpu::{device, CameraMatrices, Executor, Gpu, HostOptions};
use lightbench::io::rmse;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

/// A device the test opens itself, as a host renderer would.
fn host_device() -> (wgpu::Adapter, wgpu::Device, wgpu::Queue) {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter =
        pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default())).expect("an adapter (CI installs lavapipe)");
    let (dev, queue) = pollster::block_on(adapter.request_device(&device::device_descriptor(&adapter))).unwrap();
    (adapter, dev, queue)
}

#[test]
fn a_host_device_keeps_its_error_handler_and_renders_through_its_own_encoder() {
    let (adapter, dev, queue) = host_device();
    let seen = Arc::new(AtomicUsize::new(0));
    let counter = seen.clone();
    dev.on_uncaptured_error(Arc::new(move |_| {
        counter.fetch_add(1, Ordering::SeqCst);
    }));
    let gpu = Gpu::from_host(adapter, dev.clone(), queue.clone(), HostOptions { probe: false }).unwrap();
    let mut s = lightbench::scene::load("cornell").unwrap();
    s.size = (48, 48);
    let (exe, _) =
        lightbench::render::compile(&gpu, &root().join("pipelines/deferred.lbp"), None, &s, &[]).unwrap_or_else(|e| panic!("{e}"));

    // The host's encoder, submitted with the explicit helper.
    let mut ex = Executor::new(&gpu, &exe, &s).unwrap();
    let mut enc = dev.create_command_encoder(&Default::default());
    let inputs = ex.inputs(0.0);
    ex.encode(&gpu, &mut enc, &inputs).unwrap_or_else(|e| panic!("{e}"));
    ex.submit(&gpu, enc).unwrap_or_else(|e| panic!("{e}"));
    let encoded = output(&gpu, &ex);
    assert_eq!(ex.output_texture().unwrap().size().width, 48);

    // The same frame rendered the executor's own way.
    let mut own = Executor::new(&gpu, &exe, &s).unwrap();
    own.render_frame(&gpu, &own.inputs(0.0)).unwrap();
    let e = rmse(&encoded, &output(&gpu, &own)).unwrap();
    assert!(e <= 1e-6, "encode + submit vs render_frame: RMSE {e}");
    assert_eq!(encoded.non_finite(), 0);

    // An error outside any scope still reaches the host's handler.
    assert_eq!(seen.load(Ordering::SeqCst), 0, "rendering raised no error");
    let bad = dev.create_buffer(&wgpu::BufferDescriptor {
        label: Some("mapped for reading and writing at once: invalid"),
        size: 16,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE,
        mapped_at_creation: false,
    });
    drop(bad);
    dev.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    assert_eq!(seen.load(Ordering::SeqCst), 1, "the host's handler saw the error");
    assert!(gpu.take_uncaptured().is_empty(), "the executor did not take it");
}

/// One recording path (issue 55): `encode` records the frame `render_frame` records, GPU
/// timestamps included, into the host's encoder and submits nothing; the host submits it
/// with its own `queue.submit`, and the frame's timings arrive late, all of them by
/// `wait_idle`.
#[test]
fn a_frame_in_the_hosts_encoder_is_timed_and_submitted_only_by_the_host() {
    let (adapter, dev, queue) = host_device();
    assert!(
        dev.features().contains(wgpu::Features::TIMESTAMP_QUERY),
        "lavapipe has timestamp queries"
    );
    let gpu = Gpu::from_host(adapter, dev.clone(), queue.clone(), HostOptions { probe: false }).unwrap();
    let mut s = lightbench::scene::load("cornell").unwrap();
    s.size = (32, 32);
    let (exe, _) =
        lightbench::render::compile(&gpu, &root().join("pipelines/deferred.lbp"), None, &s, &[]).unwrap_or_else(|e| panic!("{e}"));
    let mut ex = Executor::new(&gpu, &exe, &s).unwrap();
    ex.log_timings = true;
    // Every pass runs every frame (nothing would change between these frames).
    ex.set_reuse(false);
    for frame in 0..3 {
        let mut enc = dev.create_command_encoder(&Default::default());
        let inputs = ex.inputs(frame as f32 / 60.0);
        ex.encode(&gpu, &mut enc, &inputs).unwrap_or_else(|e| panic!("{e}"));
        if frame == 0 {
            // Recorded, not submitted: the output is still the cleared texture.
            let before = output(&gpu, &ex);
            assert!(before.rgba.iter().all(|v| *v == 0.0), "encode submitted nothing");
        }
        queue.submit([enc.finish()]);
    }
    ex.wait_idle(&gpu).unwrap();
    assert_eq!(ex.timing_log.len(), 3, "every frame's timings taken once the host submitted it");
    for (frame, timings) in ex.timing_log.iter().enumerate() {
        let ran: Vec<_> = timings.iter().filter(|t| t.repetitions_run > 0).collect();
        assert!(!ran.is_empty(), "frame {frame} ran passes");
        for t in &ran {
            let ms = t
                .gpu_ms
                .unwrap_or_else(|| panic!("frame {frame}: pass `{}` has no GPU time", t.pass));
            assert!(ms.is_finite() && ms >= 0.0, "frame {frame}: pass `{}` took {ms} ms", t.pass);
            assert!(t.cpu_encode_us > 0.0, "frame {frame}: pass `{}` encode time", t.pass);
        }
    }
    let gbuffer: f64 = ex.timing_log[0].iter().filter_map(|t| t.gpu_ms).sum();
    assert!(gbuffer > 0.0, "the first frame took GPU time: {gbuffer} ms");
    assert!(
        output(&gpu, &ex).rgba.iter().any(|v| *v > 0.0),
        "the host's submit rendered the frame"
    );

    // The executor's own frame is timed by the same code, at once.
    ex.render_frame(&gpu, &ex.inputs(0.1)).unwrap();
    assert_eq!(ex.timing_log.len(), 4);
    assert!(ex.last_timings.iter().filter(|t| t.repetitions_run > 0).all(|t| t.gpu_ms.is_some()));
}

#[test]
fn host_matrices_and_lights_drive_the_frame_and_lights_must_fit_the_plan() {
    let g = gpu();
    let mut s = lightbench::scene::load("cornell").unwrap();
    s.size = (48, 48);
    let (exe, _) = lightbench::render::compile(&g, &root().join("pipelines/deferred.lbp"), None, &s, &[]).unwrap_or_else(|e| panic!("{e}"));
    let mut ex = Executor::new(&g, &exe, &s).unwrap();
    ex.set_timing(false);
    // A fixed exposure, so that dimmer lights show as a darker image.
    ex.set_param("exposure.automatic", lightbench_compiler::ir::ParamValue::Bool(false))
        .unwrap();
    let render = |ex: &mut Executor, inputs: &lightbench::gpu::FrameInputs| {
        ex.render_frame(&g, inputs).unwrap_or_else(|e| panic!("{e}"));
        output(&g, ex)
    };
    let mut inputs = ex.inputs(0.0);
    let from_camera = render(&mut ex, &inputs);
    // The scene camera's own matrices as a host would pass them: the same image.
    inputs.matrices = Some(CameraMatrices {
        view: s.camera.view(),
        proj: s.camera.proj(1.0),
    });
    let e = rmse(&from_camera, &render(&mut ex, &inputs)).unwrap();
    assert!(e <= 1e-6, "matrices equal to the camera's: RMSE {e}");
    // The host's lights, dimmed: a darker image.
    let mut dim = s.lights.clone();
    for l in &mut dim {
        l.intensity *= 0.25;
    }
    inputs.lights = Some(dim);
    let dimmed = render(&mut ex, &inputs);
    let mean = |i: &lightbench::io::Image| i.mean_rgb(0, 0, 48, 48);
    assert!(
        mean(&dimmed) < 0.8 * mean(&from_camera),
        "{} vs {}",
        mean(&dimmed),
        mean(&from_camera)
    );
    // One light too many: refused, naming what to do.
    let mut more = s.lights.clone();
    more.push(s.lights[0].clone());
    inputs.lights = Some(more);
    let err = ex.render_frame(&g, &inputs).unwrap_err().to_string();
    assert!(err.contains("compiled for the scene's") && err.contains("replace_scene"), "{err}");
}

#[test]
fn a_hosts_own_meshes_are_a_scene() {
    use lightbench::scene::{geometry, Material, Mesh, Scene};
    let g = gpu();
    let (mut floor_v, mut floor_i) = (vec![], vec![]);
    geometry::quad(
        glam::Vec3::ZERO,
        glam::Vec3::X * 2.0,
        -glam::Vec3::Z * 2.0,
        &mut floor_v,
        &mut floor_i,
    );
    let (box_v, box_i) = geometry::cuboid(glam::Vec3::splat(0.3));
    let meshes = vec![
        Mesh::new("floor", floor_v, floor_i, 0, glam::Mat4::IDENTITY),
        Mesh::new(
            "box",
            box_v.clone(),
            box_i.clone(),
            1,
            glam::Mat4::from_translation(glam::Vec3::Y * 0.3),
        ),
    ];
    let materials = vec![Material::color("grey", [0.6; 3], 0.8), Material::color("red", [0.8, 0.1, 0.1], 0.4)];
    let s = Scene::from_meshes("host", (48, 48), meshes, materials.clone(), vec![]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.lights.len(), 2, "no lights given: the default rig");
    let (exe, _) = lightbench::render::compile(&g, &root().join("pipelines/deferred.lbp"), None, &s, &[]).unwrap_or_else(|e| panic!("{e}"));
    let ex = lightbench::render::render(&g, &exe, &s, 1).unwrap_or_else(|e| panic!("{e}"));
    let img = output(&g, &ex);
    assert_eq!(img.non_finite(), 0);
    // The framed camera sees the red box in the middle and the grey floor around it.
    let centre = img.pixel(24, 24);
    assert!(centre[0] > 1.5 * centre[1], "the box is red at the centre: {centre:?}");
    assert!(img.mean_rgb(0, 0, 48, 48) > 0.02, "lit");
    // A mesh indexing past its vertices is refused, named.
    let bad = vec![Mesh::new("box", box_v, vec![0, 1, 9999], 0, glam::Mat4::IDENTITY)];
    let err = Scene::from_meshes("host", (48, 48), bad, materials, vec![])
        .unwrap_err()
        .to_string();
    assert!(err.contains("mesh `box`") && err.contains("9999"), "{err}");
}

/// External inputs from the host (docs/embedding.md): bytes in memory (`supply_input`,
/// exactly the declared size), or what the host wrote into the resource's own storage with
/// its queue (`mark_supplied`); before either, the frame is refused and names the resource;
/// what is not an external resource is refused by name; a reload that recreates the
/// resource needs it supplied again, one that keeps it does not.
#[test]
fn a_host_supplies_external_inputs_from_memory_or_its_own_writes() {
    let g = gpu();
    let d = scene_dir("host-inputs", &[]);
    let pipeline = external_inputs_pipeline(&d, &d.join("shaders"));
    let mut s = lightbench::scene::load("cornell").unwrap();
    s.size = (4, 4);
    let (exe, _) = lightbench::render::compile(&g, &pipeline, Some(&d.join("shaders")), &s, &[]).unwrap_or_else(|e| panic!("{e}"));
    let mut ex = Executor::new(&g, &exe, &s).unwrap();
    let err = ex.render_frame(&g, &ex.inputs(0.0)).unwrap_err().to_string();
    assert!(err.contains("resource `weights` is external: supply its contents"), "{err}");
    let weights: Vec<u8> = [0.25f32, 0.5, 0.75, 1.0].iter().flat_map(|f| f.to_le_bytes()).collect();
    let err = ex.supply_input(&g, "weights", &weights[..8]).unwrap_err().to_string();
    assert!(
        err.contains("supply_input `weights`: the input has 8 bytes, the buffer is declared with 16"),
        "{err}"
    );
    let err = ex.supply_input(&g, "noise", &[0; 60]).unwrap_err().to_string();
    assert!(
        err.contains("supply_input `noise`: the input has 60 bytes; 4×4 × 1 layer(s) of Rgba8Unorm is 64 bytes"),
        "{err}"
    );
    let err = ex.supply_input(&g, "out", &[0; 16]).unwrap_err().to_string();
    assert!(err.contains("supply_input `out`: the resource is not `external: true`"), "{err}");
    let err = ex.mark_supplied("nothing").unwrap_err().to_string();
    assert!(err.contains("mark_supplied `nothing`: no such resource"), "{err}");
    ex.supply_input(&g, "weights", &weights).unwrap();
    let err = ex.render_frame(&g, &ex.inputs(0.0)).unwrap_err().to_string();
    assert!(err.contains("resource `noise` is external"), "{err}");
    // The host writes the texture itself, then says so.
    let texels: Vec<u8> = [0u8, 128, 255, 255].repeat(16);
    g.queue.write_texture(
        ex.texture("noise").unwrap().as_image_copy(),
        &texels,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(16),
            rows_per_image: Some(4),
        },
        wgpu::Extent3d {
            width: 4,
            height: 4,
            depth_or_array_layers: 1,
        },
    );
    ex.mark_supplied("noise").unwrap();
    ex.render_frame(&g, &ex.inputs(0.0)).unwrap_or_else(|e| panic!("{e}"));
    let img = output(&g, &ex);
    assert_eq!(img.pixel(0, 0), [0.25, 0.5, 0.75, 1.0], "the host's buffer");
    let t = img.pixel(3, 0);
    assert!(
        t[0] == 0.0 && (t[1] - 128.0 / 255.0).abs() < 1e-3 && t[2] == 1.0,
        "the host's texels: {t:?}"
    );
    // Bytes in memory for the texture too: the next frame reads them.
    ex.supply_input(&g, "noise", &[255u8, 0, 0, 255].repeat(16)).unwrap();
    ex.render_frame(&g, &ex.inputs(0.0)).unwrap();
    assert_eq!(output(&g, &ex).pixel(3, 0), [1.0, 0.0, 0.0, 1.0]);
    // A reload that keeps the resources keeps what was supplied; one that recreates `noise`
    // (another size) needs it supplied again.
    ex.replace(&g, &exe).unwrap();
    ex.render_frame(&g, &ex.inputs(0.0)).unwrap_or_else(|e| panic!("{e}"));
    let text = std::fs::read_to_string(&pipeline).unwrap().replace("Fixed(4, 4)", "Fixed(8, 8)");
    std::fs::write(&pipeline, text).unwrap();
    let (bigger, _) = lightbench::render::compile(&g, &pipeline, Some(&d.join("shaders")), &s, &[]).unwrap_or_else(|e| panic!("{e}"));
    ex.replace(&g, &bigger).unwrap();
    let err = ex.render_frame(&g, &ex.inputs(0.0)).unwrap_err().to_string();
    assert!(err.contains("resource `noise` is external"), "{err}");
    ex.supply_input(&g, "noise", &[0u8; 256]).unwrap();
    ex.render_frame(&g, &ex.inputs(0.0)).unwrap_or_else(|e| panic!("{e}"));
}
