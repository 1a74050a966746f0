//! lightbench-executor, the execution stage: Plans run with wgpu — the device, the resource
//! pool, pipelines cached across Plans, bind groups, frame encoding, timing and read-back —
//! plus compiling a pipeline for a live device (`render`) and, behind the `reload` feature,
//! watching its files (`reload`). No command line, window or path tracer: what a host
//! renderer embeds.

mod bind_groups;
pub mod convert;
pub mod device;
mod encode;
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
mod timing;

pub use device::{DeviceOptions, Gpu, HostOptions};
pub use executor::{halton_jitter, CameraMatrices, Executor, FrameInputs, Part, ReloadReport};
pub use timing::PassTiming;

pub use lightbench_scene::{self as scene, Error, Result};

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
