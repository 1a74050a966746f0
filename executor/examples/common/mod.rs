//! What the example host programs share: their error type and exit codes (usage errors 2,
//! everything else — bad input, the GPU, the window — 1), and the host's device, opened as a
//! host program opens it.
// Each example uses part of this.
#![allow(dead_code)]

use lightbench_executor::{device, Gpu, HostOptions};

/// A host program's errors: its own (a bad argument; its window or event loop) and
/// lightbench's, which it takes with `?`.
#[derive(Debug)]
pub enum HostError {
    Usage(String),
    Host(String),
    Lightbench(lightbench_executor::Error),
}

impl std::fmt::Display for HostError {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            HostError::Usage(m) | HostError::Host(m) => f.write_str(m),
            HostError::Lightbench(e) => e.fmt(f),
        }
    }
}

impl<E: Into<lightbench_executor::Error>> From<E> for HostError {
    fn from(e: E) -> HostError {
        HostError::Lightbench(e.into())
    }
}

pub type Result<T> = std::result::Result<T, HostError>;

/// Run `run`; on an error say it and exit with its code.
pub fn exit_on_error(run: impl FnOnce() -> Result<()>) {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(if matches!(e, HostError::Usage(_)) { 2 } else { 1 });
    }
}

/// The host's device, opened by this program with the features lightbench's pipelines use,
/// and lightbench's view of it (the host keeps its error handler).
pub fn host_device() -> Result<(Gpu, wgpu::Device)> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
        .map_err(|e| HostError::Host(format!("no adapter: {e}")))?;
    let (dev, queue) = pollster::block_on(adapter.request_device(&device::device_descriptor(&adapter)))
        .map_err(|e| HostError::Host(format!("no device: {e}")))?;
    let gpu = Gpu::from_host(adapter, dev.clone(), queue, HostOptions { probe: true })?;
    Ok((gpu, dev))
}
