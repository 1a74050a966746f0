//! Render a pipeline file into a texture of a device this program owns, and write it to PNG:
//! the embedding path without a window (`embed.rs` is the same into a window).
//!
//! ```sh
//! cargo run -p lightbench-executor --example headless -- out.png [WxH] [PIPELINE] [SCENE]
//! ```
//! From the repository root; defaults: the scene's own size, `pipelines/deferred.lbp`, the
//! built-in Cornell box. The image equals `lightbench render --pipeline PIPELINE --scene
//! SCENE --size WxH --out out.png` (a test checks it).

mod common;

use common::{HostError, Result};
use lightbench_executor::render::compile;
use lightbench_executor::Executor;
use std::path::PathBuf;

fn main() {
    common::exit_on_error(run);
}

fn run() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(out) = args.first().map(PathBuf::from) else {
        eprintln!("usage: headless OUT.png [WxH] [PIPELINE] [SCENE]");
        std::process::exit(2);
    };
    let size = args.get(1).map(|s| parse_size(s)).transpose()?;
    let pipeline = PathBuf::from(args.get(2).map_or("pipelines/deferred.lbp", |s| s.as_str()));
    let scene = lightbench_executor::scene::load::load_sized(args.get(3).map_or("cornell", |s| s.as_str()), size, &[])?;

    // The host's device, opened by this program (`common::host_device`).
    let (gpu, dev) = common::host_device()?;

    // Compile the pipeline for this scene and device, then record a frame into our encoder.
    let (exe, warnings) = compile(&gpu, &pipeline, None, &scene, &[])?;
    eprint!("{warnings}");
    let mut ex = Executor::new(&gpu, &exe, &scene)?;
    let mut encoder = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("host frame") });
    let inputs = ex.inputs(0.0);
    ex.encode(&gpu, &mut encoder, &inputs)?;
    ex.submit(&gpu, encoder)?;

    // The output texture is ours to use; here it is read back and written out.
    let output = ex.plan().output_resource().name.clone();
    let texture = ex.output_texture()?;
    println!("{output}: {}×{} {:?}", texture.width(), texture.height(), texture.format());
    ex.read_texture(&gpu, &output, 0, 0)?.save(&out)?;
    println!("wrote {}", out.display());
    Ok(())
}

fn parse_size(s: &str) -> Result<(u32, u32)> {
    let bad = || HostError::Usage(format!("size `{s}`: expected WxH, e.g. 128x128"));
    let (w, h) = s.split_once('x').ok_or_else(bad)?;
    Ok((w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?))
}
