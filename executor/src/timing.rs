//! Per-pass GPU time from timestamp queries: the first repetition of a pass writes its
//! start, the last its end. CPU encode time is measured around each pass's encoding. Read
//! either at once (the frame is waited for: exact figures per frame, what measurements use)
//! or late (`LATE_SLOTS` read-back buffers mapped as the GPU gets to them: no wait, the
//! figures arrive a frame or two later — for interactive use).

use super::Gpu;
use crate::error::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// Read-back buffers for late reads: frames whose timestamps may be on their way at once.
const LATE_SLOTS: usize = 4;

/// One late read-back buffer: the frame it holds and whether its mapping has completed.
struct LateSlot {
    buffer: wgpu::Buffer,
    ready: Arc<AtomicBool>,
    frame: Option<u64>,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct PassTiming {
    pub pass: String,
    pub repetitions: u32,
    /// Repetitions that ran this frame (the others were reused: nothing they depend on changed).
    pub repetitions_run: u32,
    /// Nothing ran: the pass's results from an earlier frame were still valid.
    pub reused: bool,
    /// GPU time from timestamp queries (None where the adapter has none, or when reused).
    pub gpu_ms: Option<f64>,
    pub cpu_encode_us: f64,
}

/// The (begin, end) timestamp query indices one GPU pass writes, either or both.
pub type Writes = (Option<u32>, Option<u32>);

pub struct Timer {
    pub set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    late: Mutex<Vec<LateSlot>>,
    period_ns: f32,
    passes: u32,
}

impl Timer {
    /// `None` where the device has no timestamp queries or there is nothing to time.
    pub fn new(gpu: &Gpu, passes: usize) -> Option<Timer> {
        if !gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY) || passes == 0 {
            return None;
        }
        let n = (passes * 2) as u32;
        let buffer = |label, usage| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: n as u64 * 8,
                usage,
                mapped_at_creation: false,
            })
        };
        Some(Timer {
            set: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: n,
            }),
            resolve: buffer("timestamps", wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC),
            readback: buffer("timestamps readback", wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST),
            late: Mutex::new(
                (0..LATE_SLOTS)
                    .map(|_| LateSlot {
                        buffer: buffer(
                            "timestamps late readback",
                            wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                        ),
                        ready: Arc::new(AtomicBool::new(false)),
                        frame: None,
                    })
                    .collect(),
            ),
            period_ns: gpu.queue.get_timestamp_period(),
            passes: passes as u32,
        })
    }

    /// The (begin, end) query indices the GPU pass recording repetitions `first..last`
    /// (`last` exclusive) of `reps` of pass `pass` writes: the pass's first and last.
    pub fn writes(&self, pass: usize, (first, last): (usize, usize), reps: usize) -> Option<Writes> {
        let begin = (first == 0).then_some(2 * pass as u32);
        let end = (last == reps).then_some(2 * pass as u32 + 1);
        (begin.is_some() || end.is_some()).then_some((begin, end))
    }

    /// Record, after the frame's passes in `enc`, the copy of its timestamps to where `read`
    /// finds them.
    pub fn resolve_into(&self, enc: &mut wgpu::CommandEncoder) {
        enc.resolve_query_set(&self.set, 0..self.passes * 2, &self.resolve, 0);
        enc.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, self.resolve.size());
    }

    /// Milliseconds per pass of the frame just submitted.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<f64>> {
        let slice = self.readback.slice(..);
        slice.map_async(wgpu::MapMode::Read, |_| {});
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::gpu("reading timestamps", e))?;
        let ms = self.ms(&self.readback)?;
        self.readback.unmap();
        Ok(ms)
    }

    /// Milliseconds per pass in a mapped read-back buffer.
    fn ms(&self, buffer: &wgpu::Buffer) -> Result<Vec<f64>> {
        let data = buffer
            .slice(..)
            .get_mapped_range()
            .map_err(|e| Error::gpu("reading timestamps", e))?;
        let ticks: &[u64] = bytemuck::cast_slice(&data);
        Ok((0..self.passes as usize)
            .map(|i| ticks[2 * i + 1].saturating_sub(ticks[2 * i]) as f64 * self.period_ns as f64 / 1e6)
            .collect())
    }

    /// Record, after the frame's passes in `enc`, the copy of its timestamps into a free
    /// late slot, and return the slot; `None` when every slot still waits for the GPU (the
    /// frame then goes untimed).
    pub fn resolve_late_into(&self, enc: &mut wgpu::CommandEncoder) -> Option<usize> {
        let slots = self.late.lock().ok()?;
        let slot = slots.iter().position(|s| s.frame.is_none())?;
        enc.resolve_query_set(&self.set, 0..self.passes * 2, &self.resolve, 0);
        enc.copy_buffer_to_buffer(&self.resolve, 0, &slots[slot].buffer, 0, self.resolve.size());
        Some(slot)
    }

    /// After the submission holding `resolve_late_into`'s commands: map the slot when the GPU is
    /// done with it (no wait), for frame `frame`.
    pub fn arm(&self, slot: usize, frame: u64) {
        let Ok(mut slots) = self.late.lock() else { return };
        let s = &mut slots[slot];
        s.frame = Some(frame);
        s.ready.store(false, Ordering::SeqCst);
        let ready = s.ready.clone();
        s.buffer
            .slice(..)
            .map_async(wgpu::MapMode::Read, move |r| ready.store(r.is_ok(), Ordering::SeqCst));
    }

    /// The frames whose timestamps have arrived (after a `device.poll`), each with its
    /// milliseconds per pass, oldest first; their slots are free again.
    pub fn collect(&self) -> Result<Vec<(u64, Vec<f64>)>> {
        let Ok(mut slots) = self.late.lock() else { return Ok(vec![]) };
        let mut out = vec![];
        for s in slots.iter_mut().filter(|s| s.frame.is_some() && s.ready.load(Ordering::SeqCst)) {
            out.push((s.frame.take().unwrap_or_default(), self.ms(&s.buffer)?));
            s.buffer.unmap();
            s.ready.store(false, Ordering::SeqCst);
        }
        out.sort_by_key(|(f, _)| *f);
        Ok(out)
    }
}
