//! A host program's frame loop around the executor (docs/embedding.md, "A host program"): its
//! own device and camera, the bundled pipeline extended in memory by a pass of the host's (its
//! own picture over the finished image, an `external` texture the host writes every frame),
//! parameters set from the host and one changed while it runs, a variant changed too (compiled again and swapped in
//! with `Executor::replace`), frames recorded into the host's encoder and submitted by the
//! host, and the last frame's GPU time per pass.
//!
//! ```sh
//! cargo run -p lightbench-executor --example host_loop -- FIRST.png LAST.png [FRAMES]
//! ```
//! From the repository root: the Cornell box at 64×64 through `pipelines/deferred.lbp`, the
//! camera turning about the box to end where the scene's own camera is, manual exposure, and
//! the host's progress bar along the bottom `BAR` rows, full on the last frame; after half of
//! FRAMES (8) frames the tone mapping switches from `reinhard` to `simple` and the exposure
//! from 0.5 EV to 1. Writes the first
//! and the last frame; above the bar the last equals `lightbench render --size 64x64 --variant
//! tonemap=simple --param exposure.automatic=false --param exposure.ev=1` (a test checks it).

mod common;

use common::{HostError, Result};
use glam::Vec3;
use lightbench_compiler::{vfs::Overlay, Workspace};
use lightbench_executor::render::compile_in;
use lightbench_executor::scene::math::{look_to, perspective};
use lightbench_executor::{CameraMatrices, Executor, ParamValue};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The host's pipeline, held in memory beside the bundled one it uses: that pipeline plus the
/// host's picture over its output (straight alpha), which the host supplies.
const HOST_PIPELINE: &str = r#"pipeline host_loop

use "deferred.lbp"

texture overlay: Rgba8UnormSrgb viewport external

fullscreen host_overlay "host/overlay.wgsl" {
    reads overlay
    color ldr load blend Alpha
}
"#;

/// The host's pass: its picture, texel for pixel.
const HOST_SHADER: &str = "@group(2) @binding(0) var overlay: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(overlay, vec2<i32>(pos.xy), 0);
}
";

/// The progress bar: its height in rows and its colour (sRGB, opaque).
const BAR: u32 = 6;
const BAR_COLOR: [u8; 4] = [32, 200, 255, 255];

fn main() {
    common::exit_on_error(run);
}

fn run() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(first_png), Some(last_png)) = (args.first().map(PathBuf::from), args.get(1).map(PathBuf::from)) else {
        return Err(HostError::Usage("usage: host_loop FIRST.png LAST.png [FRAMES]".into()));
    };
    let frames: u32 = match args.get(2) {
        Some(n) => n
            .parse()
            .ok()
            .filter(|n| *n >= 2)
            .ok_or_else(|| HostError::Usage(format!("FRAMES `{n}`: expected a whole number of at least 2")))?,
        None => 8,
    };
    let scene = lightbench_executor::scene::load::load_sized("cornell", Some((64, 64)), &[])?;
    // The host's pipeline and shader in memory, over the files on disk it builds on.
    let files = Overlay::default();
    let pipeline = Path::new("pipelines/host_loop.lbp");
    files.set(pipeline, HOST_PIPELINE.into());
    files.set(Path::new("shaders/host/overlay.wgsl"), HOST_SHADER.into());
    let ws = Workspace::new(Arc::new(files));

    // The host's device, opened by this program (`common::host_device`).
    let (gpu, dev) = common::host_device()?;

    let (exe, _warnings) = compile_in(&ws, &gpu, pipeline, None, &scene, &[])?;
    let mut ex = Executor::new(&gpu, &exe, &scene)?;
    // Parameters are set by name, checked against their type and range.
    ex.set_param("exposure.automatic", ParamValue::Bool(false))?;
    ex.set_param("exposure.ev", ParamValue::Float(0.5))?;

    let (w, h) = scene.size;
    let proj = perspective(40f32.to_radians(), w as f32 / h as f32, 0.05, 20.0);
    for frame in 0..frames {
        if frame == frames / 2 {
            // A variant changed at run time: compile with the new choice, swap the Plan in
            // (resources and pipelines that did not change are kept, parameters too).
            let variants = [("tonemap".to_string(), "simple".to_string())];
            let (exe, _warnings) = compile_in(&ws, &gpu, pipeline, None, &scene, &variants)?;
            let report = ex.replace(&gpu, &exe)?;
            // A parameter changed between frames: a frame input, no new Plan.
            ex.set_param("exposure.ev", ParamValue::Float(1.0))?;
            println!(
                "frame {frame}: tonemap = simple, {} pipeline(s) built; exposure.ev = 1",
                report.pipelines_built.len()
            );
        }
        // The host's picture, written with its own queue into the executor's texture.
        let texels = progress_bar((w, h), (frame + 1) as f32 / frames as f32);
        let layout = wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(4 * w),
            rows_per_image: Some(h),
        };
        let size = wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        };
        let overlay = ex.texture("overlay")?;
        gpu.queue.write_texture(overlay.as_image_copy(), &texels, layout, size);
        ex.mark_supplied("overlay")?;
        // The host's camera: turning about the box's centre, looking at it.
        let angle = 0.3 * (1.0 - frame as f32 / (frames - 1) as f32);
        let eye = Vec3::new(3.6 * angle.sin(), 1.0, 3.6 * angle.cos());
        let view = look_to(eye, (Vec3::new(0.0, 1.0, 0.0) - eye).normalize(), Vec3::Y);
        let mut inputs = ex.inputs(frame as f32 / 60.0);
        inputs.matrices = Some(CameraMatrices { view, proj });
        let mut encoder = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("host frame") });
        // Recorded into the host's encoder, GPU timestamps included; the host submits it.
        ex.encode(&gpu, &mut encoder, &inputs)?;
        gpu.queue.submit([encoder.finish()]);
        if frame == 0 || frame == frames - 1 {
            let out = if frame == 0 { &first_png } else { &last_png };
            let output = ex.plan().output_resource().name.clone();
            ex.read_texture(&gpu, &output, 0, 0)?.save(out)?;
            println!("frame {frame}: wrote {}", out.display());
        }
    }
    // The last frame's per-pass GPU times, once the GPU has run it.
    ex.wait_idle(&gpu)?;
    for t in ex.last_timings.iter().filter(|t| !t.reused) {
        let gpu_ms = t.gpu_ms.map_or("no timestamps".into(), |ms| format!("{ms:.3} ms"));
        println!("pass {:<28} GPU {gpu_ms}, recorded in {:.0} µs", t.pass, t.cpu_encode_us);
    }
    Ok(())
}

/// RGBA8 texels, row by row: a bar `done` of the width long along the bottom `BAR` rows,
/// clear elsewhere.
fn progress_bar((w, h): (u32, u32), done: f32) -> Vec<u8> {
    let end = (done * w as f32).round() as u32;
    let texel = |x: u32, y: u32| if y + BAR >= h && x < end { BAR_COLOR } else { [0; 4] };
    (0..h).flat_map(|y| (0..w).flat_map(move |x| texel(x, y))).collect()
}
