//! Embedding: a frame recorded into a host renderer's command encoder (the recording
//! `render_frame` does, `frame`), submitted when the host says, and the Plan's textures
//! handed to the host's own passes.

use super::{Executor, FrameInputs};
use crate::error::{Error, Result};
use crate::Gpu;

impl Executor {
    /// Record one frame into the host's `encoder`, by the code `render_frame` records with:
    /// the frame, light and parameter blocks are written with `queue.write_buffer` (so the
    /// host submits each frame before encoding the next), then every pass is recorded, with
    /// GPU timestamps where timing is on (`set_timing`) and their resolve after the passes.
    /// Nothing is submitted here: the host submits the encoder, with its own `queue.submit`
    /// or with [`Executor::submit`], which also names the pass a validation error comes from.
    /// The frame's GPU timings arrive late, as with `set_late_timestamps`: its read starts
    /// when the executor learns the frame was submitted (`submit`, else the next `encode`,
    /// `render_frame`, `replace` or `wait_idle`), and `wait_idle` waits for all of them
    /// (`last_timings`, and the timing log when `log_timings` is set).
    pub fn encode(&mut self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, inputs: &FrameInputs) -> Result<()> {
        let rec = self.record(gpu, encoder, inputs, false)?;
        self.recorded = Some(rec);
        Ok(())
    }

    /// Finish `encoder` and submit it: the explicit submit that goes with [`Executor::encode`].
    /// A validation error in what was recorded comes back as an error naming the first pass
    /// that raises it (the host's own commands in the encoder are named as "the encoder").
    pub fn submit(&mut self, gpu: &Gpu, encoder: wgpu::CommandEncoder) -> Result<wgpu::SubmissionIndex> {
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let buffer = encoder.finish();
        if let Some(e) = pollster::block_on(scope.pop()) {
            let blamed = self.recorded.take().and_then(|r| self.blame_recorded(gpu, &r));
            return Err(blamed.unwrap_or_else(|| Error::gpu("finishing the encoder", e)));
        }
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let index = gpu.queue.submit([buffer]);
        if let Some(e) = pollster::block_on(scope.pop()) {
            self.recorded = None;
            return Err(Error::gpu("submitting the encoder", e));
        }
        self.finish_pending(gpu)?;
        Ok(index)
    }

    /// The texture of resource `name` as the last recorded frame left it (instance 0; a
    /// resource kept from frame to frame alternates between two textures, this is the one
    /// written last): for the host's own passes to sample or copy. It belongs to the executor
    /// and is valid until the next `replace`.
    pub fn texture(&self, name: &str) -> Result<&wgpu::Texture> {
        self.entry(name)?
            .texture(0, false, self.last_parity())
            .ok_or_else(|| Error::Resource(format!("`{name}` is a buffer; use buffer")))
    }

    /// The buffer of resource `name` as the last recorded frame left it (instance 0).
    pub fn buffer(&self, name: &str) -> Result<&wgpu::Buffer> {
        self.entry(name)?
            .buffer(0, false, self.last_parity())
            .ok_or_else(|| Error::Resource(format!("`{name}` is a texture; use texture")))
    }

    /// The Plan's output image (`Plan::output_resource`): the texture to show. Every
    /// texture of the Plan can be copied from (`COPY_SRC`); it can be sampled where the Plan
    /// itself samples it, so a host that wants to sample the output copies it first (as
    /// `examples/embed.rs` does).
    pub fn output_texture(&self) -> Result<&wgpu::Texture> {
        self.texture(&self.state.plan.output_resource().name)
    }
}
