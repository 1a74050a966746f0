//! Frames in flight (`Executor::set_frames_in_flight`): `render_frame` returns before the GPU
//! is done, yet a read-back right after it sees that frame, and the images are those of
//! waiting for every frame; 0, 1 and 2 are told apart by what is left on the GPU; and
//! `--bench inflight` runs at its smallest.

use crate::gpu_common;

use gpu_common::*;
use lightbench::gpu::Executor;
use lightbench::io::rmse;

#[test]
fn frames_in_flight_render_what_waiting_renders() {
    let g = gpu();
    let mut s = lightbench::scene::load("many_lights").unwrap();
    s.size = (48, 48);
    let path = root().join("pipelines/deferred.lbp");
    // TAA: each frame builds on the last (history), so a frame read too early would differ.
    let v = [("aa".to_string(), "taa".to_string())];
    let (exe, _) = lightbench::render::compile(&g, &path, None, &s, &v).unwrap_or_else(|e| panic!("{e}"));
    let images = |in_flight: u32| {
        let mut ex = Executor::new(&g, &exe, &s).unwrap();
        ex.set_timing(false);
        ex.set_frames_in_flight(in_flight);
        let mut out = vec![];
        for f in 0..6 {
            let inputs = ex.inputs(f as f32 / 10.0);
            ex.render_frame(&g, &inputs).unwrap_or_else(|e| panic!("{e}"));
            if f % 2 == 1 {
                out.push(output(&g, &ex));
            }
        }
        ex.wait_idle(&g).unwrap();
        out
    };
    let (waiting, overlapped) = (images(0), images(3));
    for (i, (a, b)) in waiting.iter().zip(&overlapped).enumerate() {
        let e = rmse(a, b).unwrap();
        assert!(e <= 1e-6, "frame {}: RMSE {e}", 2 * i + 1);
    }
    // The frames differ from each other (the lights move), so a stale read would show.
    assert!(rmse(&waiting[0], &waiting[2]).unwrap() > 1e-4);
}

/// What `set_frames_in_flight` means (its doc, docs/benchmarks.md): when `render_frame`
/// returns, at most that many frames are left unwaited — 0: none, and the queue is empty
/// (serial); 1: the frame just submitted; 2: it and the one before.
#[test]
fn frames_in_flight_bound_what_is_left_on_the_gpu() {
    let g = gpu();
    let mut s = lightbench::scene::load("cornell").unwrap();
    s.size = (32, 32);
    let (exe, _) = lightbench::render::compile(&g, &root().join("pipelines/deferred.lbp"), None, &s, &[]).unwrap_or_else(|e| panic!("{e}"));
    for n in [0u32, 1, 2] {
        let mut ex = Executor::new(&g, &exe, &s).unwrap();
        ex.set_timing(false);
        ex.set_frames_in_flight(n);
        for f in 0..4 {
            ex.render_frame(&g, &ex.inputs(f as f32)).unwrap();
            assert_eq!(ex.frames_in_flight(), (f + 1).min(n as usize), "{n} in flight, frame {f}");
            if n == 0 {
                let status = g.device.poll(wgpu::PollType::Poll).unwrap();
                assert!(status.is_queue_empty(), "serial: nothing left on the GPU: {status:?}");
            }
        }
        ex.wait_idle(&g).unwrap();
        assert_eq!(ex.frames_in_flight(), 0);
    }
}

/// Late timestamps (`set_late_timestamps`, what the viewer uses): timed frames are not waited
/// for, the figures arrive later, and by `wait_idle` every frame's are in the timing log —
/// for each pass that ran, none for those reused; the images are those of waiting.
#[test]
fn late_timestamps_fill_every_frame_by_the_end() {
    let g = gpu();
    assert!(
        g.profile.has(lightbench_compiler::profile::Feature::TimestampQuery),
        "lavapipe has timestamps"
    );
    let mut s = lightbench::scene::load("cornell").unwrap();
    s.size = (48, 48);
    let (exe, _) = lightbench::render::compile(&g, &root().join("pipelines/deferred.lbp"), None, &s, &[]).unwrap_or_else(|e| panic!("{e}"));
    let run = |late: bool| {
        let mut ex = Executor::new(&g, &exe, &s).unwrap();
        ex.log_timings = true;
        ex.set_late_timestamps(late);
        for f in 0..8 {
            let inputs = ex.inputs(f as f32 / 60.0);
            ex.render_frame(&g, &inputs).unwrap_or_else(|e| panic!("{e}"));
        }
        ex.wait_idle(&g).unwrap();
        (output(&g, &ex), ex.timing_log.clone(), ex.last_timings.clone())
    };
    let (waited, waited_log, _) = run(false);
    let (late, log, last) = run(true);
    assert!(rmse(&waited, &late).unwrap() <= 1e-6);
    assert_eq!(log.len(), 8);
    for (f, (frame, same)) in log.iter().zip(&waited_log).enumerate() {
        for (t, w) in frame.iter().zip(same) {
            assert_eq!(t.reused, w.reused, "frame {f}, {}: the same work ran", t.pass);
            match t.reused {
                false => assert!(
                    t.gpu_ms.is_some_and(|ms| ms.is_finite() && ms >= 0.0),
                    "frame {f}, {}: {:?}",
                    t.pass,
                    t.gpu_ms
                ),
                true => assert_eq!(t.gpu_ms, None, "frame {f}, {}: reused, untimed", t.pass),
            }
        }
    }
    // The last frame's own figures, after the wait.
    for (t, logged) in last.iter().zip(&log[7]) {
        assert_eq!(t.gpu_ms, logged.gpu_ms, "{}", t.pass);
    }
}
