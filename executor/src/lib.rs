//! lightbench-executor, the execution stage: Plans run with wgpu — the device, the resource
//! pool, pipelines cached across Plans, bind groups, frame encoding, timing and read-back —
//! plus compiling a pipeline for a live device (`render`) and, behind the `reload` feature,
//! watching its files (`reload`). No command line, window or path tracer: what a host
//! renderer embeds.
//!
//! # Embedding
//!
//! A host renderer keeps its device, queue, error handler and frame loop. It opens its device
//! with [`device::device_descriptor`] (the features lightbench's pipelines can use), wraps
//! clones with [`Gpu::from_host`] (its uncaptured-error handler is left alone; errors come back
//! as values), compiles a pipeline for a scene — its own meshes as a [`scene::Scene`], or one
//! loaded with [`scene::load()`] — and records each frame into its own command encoder with
//! [`Executor::encode`]. [`FrameInputs`] carries time, parameters, and optionally the host's
//! view/projection ([`CameraMatrices`]) and lights; [`Executor::output_texture`] (and
//! [`Executor::texture`] for any named resource) is the host's to copy or sample.
//!
//! ```no_run
//! use lightbench_executor::{device, render, scene, Executor, Gpu, HostOptions};
//! # fn main() -> lightbench_executor::Result<()> {
//! # let instance = wgpu::Instance::default();
//! # let adapter = pollster::block_on(instance.request_adapter(&Default::default())).unwrap();
//! let (dev, queue) = pollster::block_on(adapter.request_device(&device::device_descriptor(&adapter))).unwrap();
//! let gpu = Gpu::from_host(adapter, dev.clone(), queue, HostOptions::default())?;
//! let scene = scene::load::load("cornell")?;
//! let (exe, _warnings) = render::compile(&gpu, "pipelines/deferred.lbp".as_ref(), None, &scene, &[])?;
//! let mut ex = Executor::new(&gpu, &exe, &scene)?;
//!
//! let mut encoder = dev.create_command_encoder(&Default::default());
//! let inputs = ex.inputs(0.0);
//! ex.encode(&gpu, &mut encoder, &inputs)?;
//! let shown = ex.output_texture()?; // copy or sample it in the host's own passes
//! # let _ = shown;
//! ex.submit(&gpu, encoder)?; // finish + submit; an error names the pass
//! # Ok(()) }
//! ```
//!
//! `examples/headless.rs` renders into a texture and writes it to PNG; `examples/embed.rs` is
//! a winit program presenting through its own blit pass, reloading the pipeline on save.

pub mod accel;
mod bind_groups;
pub mod convert;
pub mod device;
mod encode;
pub mod error;
pub mod executor;
mod inputs;
pub mod light_volumes;
mod pipelines;
pub use pipelines::PipelineCache;
pub mod pool;
pub mod readback;
#[cfg(feature = "reload")]
pub mod reload;
pub mod render;
/// The reuse rule lives with the Plan it depends on (GPU-free).
pub use lightbench_compiler::plan::reuse;
pub mod scene_gpu;
mod texel_table;
mod timing;

pub use device::{DeviceOptions, Gpu, HostOptions};
pub use executor::{halton_jitter, CameraMatrices, Executor, FrameInputs, Part, ReloadReport};
/// A parameter value, for `Executor::set_param` (the compiler's type, re-exported for hosts).
pub use lightbench_compiler::ir::ParamValue;
pub use timing::PassTiming;

pub use error::{Error, Result};
pub use lightbench_scene as scene;

/// Run `f` inside error scopes for every error kind and report the first error with `what`.
pub(crate) fn err_scope<T>(gpu: &Gpu, what: &str, f: impl FnOnce() -> T) -> Result<T> {
    let oom = gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let internal = gpu.device.push_error_scope(wgpu::ErrorFilter::Internal);
    let validation = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let out = f();
    let errors: Vec<wgpu::Error> = [validation.pop(), internal.pop(), oom.pop()]
        .into_iter()
        .filter_map(pollster::block_on)
        .collect();
    match errors.first() {
        Some(e) => Err(Error::gpu(what, e)),
        None => Ok(out),
    }
}
