//! What the headless examples share: the host's device, opened as a host program opens it,
//! and their exit codes (usage errors 2, everything else — bad input, the GPU — 1).

use lightbench_executor::{device, Gpu, HostOptions, Result};

/// Run `run`; on an error say it and exit with its code.
pub fn exit_on_error(run: impl FnOnce() -> Result<()>) {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(if matches!(e, lightbench_executor::Error::Usage(_)) { 2 } else { 1 });
    }
}

/// The host's device, opened by this program with the features lightbench's pipelines use,
/// and lightbench's view of it (the host keeps its error handler).
pub fn host_device() -> Result<(Gpu, wgpu::Device)> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
        .map_err(|e| lightbench_executor::Error::Adapter(format!("no adapter: {e}")))?;
    let (dev, queue) = pollster::block_on(adapter.request_device(&device::device_descriptor(&adapter)))
        .map_err(|e| lightbench_executor::Error::Adapter(format!("no device: {e}")))?;
    let gpu = Gpu::from_host(adapter, dev.clone(), queue, HostOptions { probe: true })?;
    Ok((gpu, dev))
}
