//! A frame recorded and submitted: one recording path for `render_frame` (the executor's
//! own encoder, submitted and paced here) and `encode` (the host's encoder, which the host
//! submits). Both time the passes with timestamp queries written into the encoder they record
//! into, the resolve of the timestamps recorded after the passes.

use super::{Executor, FrameInputs};
use crate::encode::encode;
use crate::error::{Error, Result};
use crate::scene_gpu::DrawOrder;
use crate::Gpu;
use std::time::Instant;

/// How a recorded frame's timestamps are read.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Timestamps {
    /// Not timed (timing off, no timestamp queries, or every late read-back slot busy).
    None,
    /// Read at once: the frame is waited for.
    Waited,
    /// Read as the GPU gets to them, from this late read-back slot.
    Late(usize),
}

/// A frame recorded into an encoder, until it is finished (submitted, paced, timed).
pub(super) struct Recorded {
    pub(super) frame: u64,
    pub(super) run: Vec<Vec<bool>>,
    pub(super) parity: usize,
    pub(super) eye: glam::Vec3,
    pub(super) cpu_us: Vec<f64>,
    pub(super) timestamps: Timestamps,
}

impl Executor {
    /// Render one frame: recorded into an encoder of the executor's, submitted, paced
    /// (`set_frames_in_flight`) and timed. GPU errors come back as values naming the pass.
    pub fn render_frame(&mut self, gpu: &Gpu, inputs: &FrameInputs) -> Result<()> {
        // One error scope for the frame: a scope per pass costs more than encoding a pass.
        // Should it catch an error, the frame is encoded again pass by pass to name the pass.
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut enc = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        let recorded = self.record(gpu, &mut enc, inputs, true);
        let buffer = enc.finish();
        let error = pollster::block_on(scope.pop());
        let rec = recorded?;
        if let Some(e) = error {
            return Err(self
                .blame_recorded(gpu, &rec)
                .unwrap_or_else(|| Error::gpu("encoding the frame", e)));
        }
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let submitted = gpu.queue.submit([buffer]);
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::gpu("submitting the frame", e));
        }
        self.finish(gpu, rec, Some(submitted))?;
        let errors = gpu.take_uncaptured();
        if !errors.is_empty() {
            return Err(Error::gpu("rendering", errors.join("; ")));
        }
        Ok(())
    }

    /// Record one frame into `enc`: a frame the host submitted itself finished first, the
    /// inputs written, every pass encoded (with timestamp queries where timing is on) and the
    /// timestamps' resolve after them — into the read-back that is read at once when `wait`
    /// (and timings are not read late), else into a late read-back slot. The frame counts as
    /// rendered from here (its parity is the one read-backs and `texture` see).
    pub(super) fn record(&mut self, gpu: &Gpu, enc: &mut wgpu::CommandEncoder, inputs: &FrameInputs, wait: bool) -> Result<Recorded> {
        self.finish_pending(gpu)?;
        let run = self.begin_frame(gpu, inputs)?;
        let parity = (self.frame_index & 1) as usize;
        let (state, scene) = (&self.state, &self.shared.scene_gpu);
        let timer = state.timer.as_ref().filter(|_| self.timing);
        let eye = inputs.eye();
        let order = scene.draw_order(eye);
        let mut cpu_us = Vec::with_capacity(state.passes.len());
        // A render pass the next pass may continue (consecutive passes into the same targets).
        let mut open = None;
        for (pi, pass) in state.passes.iter().enumerate() {
            let start = Instant::now();
            encode(
                enc,
                (pass, pi, &run[pi]),
                (parity, self.merge),
                timer,
                (scene, &order),
                Some(&mut open),
            );
            cpu_us.push(start.elapsed().as_secs_f64() * 1e6);
        }
        drop(open);
        let timestamps = match timer {
            None => Timestamps::None,
            Some(t) if wait && !self.late_timestamps => {
                t.resolve_into(enc);
                Timestamps::Waited
            }
            Some(t) => t.resolve_late_into(enc).map_or(Timestamps::None, Timestamps::Late),
        };
        let frame = self.frame_index;
        self.frame_index += 1;
        Ok(Recorded {
            frame,
            run,
            parity,
            eye,
            cpu_us,
            timestamps,
        })
    }

    /// After a recorded frame was submitted (`submitted`: by the executor, which then paces
    /// the frames in flight): its GPU timings taken (read, or their late read armed), and
    /// `last_timings` and the timing log written.
    pub(super) fn finish(&mut self, gpu: &Gpu, rec: Recorded, submitted: Option<wgpu::SubmissionIndex>) -> Result<()> {
        if let Some(index) = submitted {
            self.bound_in_flight(gpu, index, rec.timestamps == Timestamps::Waited)?;
        }
        let gpu_ms = self.frame_gpu_ms(gpu, &rec)?;
        self.record_timings(&rec.run, &gpu_ms, &rec.cpu_us);
        if self.log_timings {
            self.timing_log.push(self.last_timings.clone());
        }
        self.logged = rec.frame + 1;
        Ok(())
    }

    /// Finish the frame `encode` recorded, which the host has submitted (`submit`, or the
    /// host's own `queue.submit`, which must come before the next frame is recorded).
    pub(super) fn finish_pending(&mut self, gpu: &Gpu) -> Result<()> {
        match self.recorded.take() {
            Some(rec) => self.finish(gpu, rec, None),
            None => Ok(()),
        }
    }

    /// The first pass of a recorded frame whose encoding raises a validation error.
    pub(super) fn blame_recorded(&self, gpu: &Gpu, rec: &Recorded) -> Option<Error> {
        let order = self.shared.scene_gpu.draw_order(rec.eye);
        self.blame(gpu, (&rec.run, rec.parity), &order)
    }

    /// How many frames may still be on the GPU when `render_frame` returns: 0 waits for the
    /// frame just submitted (serial); 1 lets it run while the caller records the next, and
    /// waits for the one before; 2 (the default) waits for the frame two back. A frame timed
    /// with timestamp queries is waited for (its timings are read at once) unless they are
    /// read late (`set_late_timestamps`). Read-backs wait for every frame.
    pub fn set_frames_in_flight(&mut self, n: u32) {
        self.frames_in_flight = n as usize;
    }

    /// How many submitted frames `render_frame` has not waited for (at most the bound set by
    /// `set_frames_in_flight`; some may have finished already).
    pub fn frames_in_flight(&self) -> usize {
        self.in_flight.len()
    }

    /// Wait until the GPU has run every submitted frame (late timestamps included: the
    /// timing log is complete after it, a frame the host submitted itself included).
    pub fn wait_idle(&mut self, gpu: &Gpu) -> Result<()> {
        self.finish_pending(gpu)?;
        self.in_flight.clear();
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::gpu("waiting for the GPU", e))?;
        self.collect_late()
    }

    /// After a submission: wait for it if it is timed, else for the frames beyond the bound.
    fn bound_in_flight(&mut self, gpu: &Gpu, submitted: wgpu::SubmissionIndex, timed: bool) -> Result<()> {
        if timed {
            return self.wait_idle(gpu);
        }
        self.in_flight.push_back(submitted);
        while self.in_flight.len() > self.frames_in_flight {
            let oldest = self.in_flight.pop_front();
            let wait = wgpu::PollType::Wait {
                submission_index: oldest,
                timeout: None,
            };
            gpu.device.poll(wait).map_err(|e| Error::gpu("waiting for the GPU", e))?;
        }
        Ok(())
    }

    /// Render one frame pass by pass, waiting for each and calling `after(self, pass index)`
    /// once it is done, so its results can be read back (`verify` names the first pass that
    /// produced a non-finite value this way). `after` returning `true` stops the frame there.
    /// Slower than `render_frame` (one submission per pass) and untimed. `after`'s errors
    /// are the caller's type, which takes the executor's.
    pub fn render_frame_probed<E: From<Error>>(
        &mut self,
        gpu: &Gpu,
        inputs: &FrameInputs,
        after: &mut dyn FnMut(&Executor, usize) -> std::result::Result<bool, E>,
    ) -> std::result::Result<bool, E> {
        self.finish_pending(gpu)?;
        let run = self.begin_frame(gpu, inputs)?;
        let parity = (self.frame_index & 1) as usize;
        // Counted as rendered from the start, so that reads in `after` see this frame's copies.
        self.frame_index += 1;
        let order = self.shared.scene_gpu.draw_order(inputs.eye());
        let mut stopped = false;
        for (pi, run) in run.iter().enumerate() {
            let pass = &self.state.passes[pi];
            let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let mut enc = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some(&pass.plan.name),
            });
            encode(
                &mut enc,
                (pass, pi, run),
                (parity, self.merge),
                None,
                (&self.shared.scene_gpu, &order),
                None,
            );
            gpu.queue.submit([enc.finish()]);
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(Error::gpu(format!("pass `{}`", pass.plan.name), e).into());
            }
            gpu.device
                .poll(wgpu::PollType::wait_indefinitely())
                .map_err(|e| Error::gpu("waiting for the GPU", e))?;
            if after(self, pi)? {
                stopped = true;
                break;
            }
        }
        Ok(stopped)
    }

    /// The first pass whose encoding raises a validation error, as that error (nothing is
    /// submitted: encoding alone raises it).
    pub(super) fn blame(&self, gpu: &Gpu, (run, parity): (&[Vec<bool>], usize), order: &DrawOrder) -> Option<Error> {
        for (pi, pass) in self.state.passes.iter().enumerate() {
            let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
            let mut enc = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some(&pass.plan.name),
            });
            encode(
                &mut enc,
                (pass, pi, &run[pi]),
                (parity, self.merge),
                None,
                (&self.shared.scene_gpu, order),
                None,
            );
            drop(enc.finish());
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Some(Error::gpu(format!("pass `{}`", pass.plan.name), e));
            }
        }
        None
    }
}
