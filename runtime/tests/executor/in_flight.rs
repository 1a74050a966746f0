//! Frames in flight (`Executor::set_frames_in_flight`): `render_frame` returns before the GPU
//! is done, yet a read-back right after it sees that frame, and the images are those of
//! waiting for every frame.

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
    let (waiting, overlapped) = (images(1), images(3));
    for (i, (a, b)) in waiting.iter().zip(&overlapped).enumerate() {
        let e = rmse(a, b).unwrap();
        assert!(e <= 1e-6, "frame {}: RMSE {e}", 2 * i + 1);
    }
    // The frames differ from each other (the lights move), so a stale read would show.
    assert!(rmse(&waiting[0], &waiting[2]).unwrap() > 1e-4);
}
