//! The log-average luminance of seed 003 §4.2 (Table 6.2) as the bundled pipelines compute it:
//! the parallel two-step reduction (`luminance_tiles.wgsl`, `luminance_reduce.wgsl`) against a
//! CPU computation over the read-back HDR image at three sizes, against the single-workgroup
//! option, on a black frame and an empty one; and eye adaptation (`luminance = adapting`)
//! following the exponential law its shader states.

use crate::gpu_common;

use gpu_common::*;
use lightbench::gpu::Executor;
use lightbench::scene::{builtin, Scene};
use lightbench_compiler::ir::ParamValue;
use lightbench_compiler::Workspace;

/// (log-average, brightest, pixels) over the drawn pixels, as the shaders define them.
fn cpu_log_average(hdr: &lightbench::io::Image, depth: &lightbench::io::Image) -> (f64, f64, f64) {
    let (mut s, mut m, mut n) = (0.0f64, 0.0f64, 0.0f64);
    for y in 0..hdr.height {
        for x in 0..hdr.width {
            if depth.pixel(x, y)[0] >= 1.0 {
                continue;
            }
            let [r, g, b, _] = hdr.pixel(x, y);
            let l = r.max(g).max(b) as f64;
            let l = if (0.0..65504.0).contains(&l) { l } else { 0.0 };
            s += (1e-4 + l).ln();
            m = m.max(l);
            n += 1.0;
        }
    }
    ((s / n.max(1.0)).exp(), m, n)
}

fn executor(g: &lightbench::gpu::Gpu, scene: &Scene, variants: &[(&str, &str)]) -> Executor {
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let (exe, _) = lightbench::render::compile_in(&Workspace::disk(), g, &deferred(), None, scene, &v).unwrap_or_else(|e| panic!("{e}"));
    Executor::new(g, &exe, scene).unwrap()
}

#[test]
fn the_parallel_log_average_matches_the_cpu_at_any_size() {
    let g = gpu();
    for size in [(64, 64), (333, 197), (1024, 1024)] {
        let mut scene = builtin::cornell();
        scene.size = size;
        let mut lums = vec![];
        for option in ["parallel", "single"] {
            let mut ex = executor(&g, &scene, &[("luminance", option)]);
            let inputs = ex.inputs(0.0);
            ex.render_frame(&g, &inputs).unwrap();
            lums.push(ex.read_buffer(&g, "lum", 0).unwrap());
            if option == "parallel" {
                let hdr = ex.read_texture(&g, "hdr", 0, 0).unwrap();
                let depth = ex.read_texture(&g, "gbuf.depth", 0, 0).unwrap();
                let (avg, white, n) = cpu_log_average(&hdr, &depth);
                let lum = &lums[0];
                assert!(((lum[0] as f64 - avg) / avg).abs() < 0.01, "{size:?}: GPU {} vs CPU {avg}", lum[0]);
                assert!(
                    ((lum[1] as f64 - white) / white).abs() < 1e-3,
                    "{size:?}: white {} vs {white}",
                    lum[1]
                );
                assert_eq!(lum[3] as f64, n, "{size:?}: pixels counted");
            }
        }
        // The one-workgroup option (the benchmark's baseline) agrees.
        let (p, s) = (&lums[0], &lums[1]);
        assert!(
            ((p[0] - s[0]) / s[0]).abs() < 1e-3 && p[1] == s[1] && p[3] == s[3],
            "{size:?}: {p:?} vs {s:?}"
        );
    }
}

/// Nothing lit (no lights, no ambient) and nothing drawn both give the floor, 1e-4, and a
/// finite exposure.
#[test]
fn a_black_or_empty_frame_gives_a_finite_result() {
    let g = gpu();
    let mut scene = builtin::cornell();
    scene.size = (64, 64);
    scene.lights.clear();
    let mut ex = executor(&g, &scene, &[]);
    let mut inputs = ex.inputs(0.0);
    inputs
        .params
        .set(&ex.plan().params, "ambient.color", ParamValue::Vec(vec![0.0, 0.0, 0.0]))
        .unwrap();
    ex.render_frame(&g, &inputs).unwrap();
    let black = ex.read_buffer(&g, "lum", 0).unwrap();
    assert!(black[3] > 0.0, "the box is drawn: {black:?}");
    let mut empty = builtin::cornell();
    empty.size = (64, 64);
    empty.camera.yaw += 180.0; // looking out of the open box, at nothing
    let mut ex = executor(&g, &empty, &[]);
    let inputs = ex.inputs(0.0);
    ex.render_frame(&g, &inputs).unwrap();
    let nothing = ex.read_buffer(&g, "lum", 0).unwrap();
    for lum in [&black, &nothing] {
        assert!(lum.iter().all(|v| v.is_finite()), "{lum:?}");
        assert!((lum[0] - 1e-4).abs() < 1e-7, "the floor: {lum:?}");
        assert!(lum[2] > 0.0, "a finite, positive exposure: {lum:?}");
    }
    assert_eq!(nothing[3], 0.0, "nothing drawn: {nothing:?}");
}

/// `luminance = adapting`: the first frame takes the measured log-average; after the scene
/// gets brighter, the adapted value follows a ← a + (m − a)(1 − e^(−Δt/τ)) frame by frame with
/// τ = `exposure.tau_brighter`, and after 5τ less than 1% of the jump is left; darker, with
/// `exposure.tau_darker`. The exposure applied is key / adapted.
#[test]
fn eye_adaptation_converges_at_its_stated_rate() {
    let g = gpu();
    let mut scene = builtin::cornell();
    scene.size = (32, 32);
    let mut ex = executor(&g, &scene, &[("luminance", "adapting")]);
    let plan_params = ex.plan().params.clone();
    let (tau_up, tau_down, dt) = (0.1f32, 0.25f32, 1.0f32 / 60.0);
    let frame = |ex: &mut Executor, k: u32, ambient: f64| -> Vec<f32> {
        let mut inputs = ex.inputs(k as f32 * dt);
        let set = |i: &mut lightbench::gpu::FrameInputs, n: &str, v| i.params.set(&plan_params, n, v).unwrap();
        set(&mut inputs, "ambient.color", ParamValue::Vec(vec![ambient; 3]));
        set(&mut inputs, "exposure.tau_brighter", ParamValue::Float(tau_up as f64));
        set(&mut inputs, "exposure.tau_darker", ParamValue::Float(tau_down as f64));
        ex.render_frame(&g, &inputs).unwrap();
        ex.read_buffer(&g, "lum", 0).unwrap()
    };
    // Words: log_average, white, exposure, covered, by_luminance, adapted, adapted_at.
    let first = frame(&mut ex, 0, 0.03);
    assert_eq!(first[5], first[0], "the first frame takes the measured value: {first:?}");
    let mut a = first[5];
    let mut k = 1;
    for (ambient, tau, frames) in [(0.6, tau_up, 30), (0.03, tau_down, 75)] {
        let mut last = vec![];
        let start = a;
        for _ in 0..frames {
            let lum = frame(&mut ex, k, ambient);
            let expected = a + (lum[0] - a) * (1.0 - (-dt / tau).exp());
            assert!(
                ((lum[5] - expected) / expected).abs() < 1e-3,
                "frame {k}: adapted {} vs {expected}",
                lum[5]
            );
            assert!(
                ((lum[2] - 0.18 / lum[5]) / lum[2]).abs() < 1e-4,
                "exposure = key / adapted: {lum:?}"
            );
            a = lum[5];
            k += 1;
            last = lum;
        }
        // frames × Δt = 5τ: the gap to the measured value is e^-5 < 1% of the jump.
        let gap = ((last[5] - last[0]) / (start - last[0])).abs();
        assert!(gap < 0.01, "converged after 5τ: {gap} of the jump left, {last:?}");
    }
}
