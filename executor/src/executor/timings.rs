//! A frame's timings: CPU encode time per pass, and GPU time per pass from timestamp queries,
//! read at once (the frame waited for) or late (mapped as the GPU gets to them), written to
//! `last_timings` and the timing log.

use super::frame::{Recorded, Timestamps};
use super::Executor;
use crate::error::Result;
use crate::timing::PassTiming;
use crate::Gpu;

impl Executor {
    /// This frame's `last_timings`, written over last frame's (no allocation while the
    /// passes stay the same).
    pub(super) fn record_timings(&mut self, run: &[Vec<bool>], gpu_ms: &[Option<f64>], cpu_us: &[f64]) {
        let passes = &self.state.passes;
        let same = self.last_timings.len() == passes.len() && self.last_timings.iter().zip(passes).all(|(t, p)| t.pass == p.plan.name);
        if !same {
            self.last_timings = passes
                .iter()
                .map(|p| PassTiming {
                    pass: p.plan.name.clone(),
                    repetitions: 0,
                    repetitions_run: 0,
                    reused: false,
                    gpu_ms: None,
                    cpu_encode_us: 0.0,
                })
                .collect();
        }
        for (i, (t, p)) in self.last_timings.iter_mut().zip(passes).enumerate() {
            let ran = run[i].iter().filter(|r| **r).count() as u32;
            t.repetitions = p.reps.len() as u32;
            t.repetitions_run = ran;
            t.reused = ran == 0;
            t.gpu_ms = gpu_ms[i].filter(|_| ran > 0);
            t.cpu_encode_us = cpu_us[i];
        }
    }

    /// GPU ms per pass of a frame just submitted: read at once when it was waited for; else
    /// (its late read armed, if it has a slot) the latest that have arrived, a frame or two
    /// back; none where it was not timed.
    pub(super) fn frame_gpu_ms(&mut self, gpu: &Gpu, rec: &Recorded) -> Result<Vec<Option<f64>>> {
        let passes = rec.run.len();
        let Some(timer) = self.state.timer.as_ref().filter(|_| self.timing) else {
            return Ok(vec![None; passes]);
        };
        match rec.timestamps {
            Timestamps::Waited => return Ok(timer.read(gpu)?.into_iter().map(Some).collect()),
            Timestamps::Late(slot) => {
                timer.arm(slot, rec.frame);
                let ran = rec.run.iter().map(|r| r.iter().any(|x| *x)).collect();
                self.late_runs.push_back((rec.frame, ran));
            }
            Timestamps::None => {}
        }
        let _ = gpu.device.poll(wgpu::PollType::Poll);
        self.collect_late()?;
        Ok((0..passes).map(|i| self.late_ms.get(i).copied().flatten()).collect())
    }

    /// Take the late timestamps that have arrived: the latest per pass, and the timing log's
    /// entries of their frames filled in.
    pub(super) fn collect_late(&mut self) -> Result<()> {
        let Some(timer) = self.state.timer.as_ref() else { return Ok(()) };
        for (frame, ms) in timer.collect()? {
            let Some(at) = self.late_runs.iter().position(|(f, _)| *f == frame) else {
                continue;
            };
            let (_, ran) = self.late_runs.remove(at).unwrap_or_default();
            self.late_ms.resize(ms.len(), None);
            // The log's last entry (and `last_timings`) is frame `logged - 1`.
            let back = self.logged.saturating_sub(frame) as usize;
            let logged = self.timing_log.len().checked_sub(back).and_then(|i| self.timing_log.get_mut(i));
            let mut entries: Vec<&mut Vec<PassTiming>> = logged.into_iter().collect();
            if back == 1 {
                entries.push(&mut self.last_timings);
            }
            for (i, v) in ms.iter().enumerate().filter(|(i, _)| ran.get(*i) == Some(&true)) {
                self.late_ms[i] = Some(*v);
                for e in entries.iter_mut() {
                    if let Some(t) = e.get_mut(i) {
                        t.gpu_ms = Some(*v);
                    }
                }
            }
        }
        Ok(())
    }

    /// Read GPU timestamps a frame or two late instead of waiting for each timed frame
    /// (off by default: measurements want each frame's own figures at once). Late, a frame's
    /// `PassTiming::gpu_ms` are the latest that have arrived; the timing log's entries are
    /// filled in as they arrive, and all of them by `wait_idle`.
    pub fn set_late_timestamps(&mut self, on: bool) {
        self.late_timestamps = on;
    }
}
