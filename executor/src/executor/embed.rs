//! Embedding: a frame recorded into a host renderer's command encoder, submitted when the
//! host says, and the Plan's textures handed to the host's own passes.

use super::{encode, Executor, FrameInputs};
use crate::Gpu;
use lightbench_scene::error::{Error, Result};

/// What `encode` recorded, kept for `submit` to name the pass an error came from.
pub(super) struct Recorded {
    run: Vec<Vec<bool>>,
    parity: usize,
    eye: glam::Vec3,
}

impl Executor {
    /// Record one frame into the host's `encoder`: the frame and light blocks and parameter
    /// blocks are written with `queue.write_buffer` (so submit each frame before encoding the
    /// next, as [`Executor::submit`] does), then every pass is recorded. Untimed (GPU timings
    /// come from `render_frame`). Validation errors in the recorded commands surface when the
    /// encoder is finished: [`Executor::submit`] returns them naming the pass.
    pub fn encode(&mut self, gpu: &Gpu, encoder: &mut wgpu::CommandEncoder, inputs: &FrameInputs) -> Result<()> {
        let run = self.begin_frame(gpu, inputs)?;
        let parity = (self.frame_index & 1) as usize;
        let eye = inputs.eye();
        let scene = &self.shared.scene_gpu;
        let order = scene.draw_order(eye);
        let mut open = None;
        for (pi, pass) in self.state.passes.iter().enumerate() {
            encode(
                encoder,
                (pass, pi, &run[pi]),
                (parity, self.merge),
                None,
                (scene, &order),
                Some(&mut open),
            );
        }
        drop(open);
        self.recorded = Some(Recorded { run, parity, eye });
        self.frame_index += 1;
        Ok(())
    }

    /// Finish `encoder` and submit it: the explicit submit that goes with [`Executor::encode`].
    /// A validation error in what was recorded comes back as an error naming the first pass
    /// that raises it (the host's own commands in the encoder are named as "the encoder").
    pub fn submit(&mut self, gpu: &Gpu, encoder: wgpu::CommandEncoder) -> Result<wgpu::SubmissionIndex> {
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let buffer = encoder.finish();
        let finished = pollster::block_on(scope.pop());
        if let Some(e) = finished {
            let blamed = self.recorded.take().and_then(|r| {
                let order = self.shared.scene_gpu.draw_order(r.eye);
                self.blame(gpu, (&r.run, r.parity), &order)
            });
            return Err(blamed.unwrap_or_else(|| Error::gpu("finishing the encoder", e)));
        }
        self.recorded = None;
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let index = gpu.queue.submit([buffer]);
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(Error::gpu("submitting the encoder", e)),
            None => Ok(index),
        }
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

    /// The Plan's output image (what `render --out` writes): the texture to show. Every
    /// texture of the Plan can be copied from (`COPY_SRC`); it can be sampled where the Plan
    /// itself samples it, so a host that wants to sample the output copies it first (as
    /// `examples/embed.rs` does).
    pub fn output_texture(&self) -> Result<&wgpu::Texture> {
        self.texture(&self.state.plan.output_resource().name)
    }
}
