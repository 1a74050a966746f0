//! `cargo bench -p lightbench --bench viewer`: the viewer's frame (render + the shown image
//! for display) while a light is dragged — its position edited every frame, as the panel and
//! the mouse do — against a still scene, in interleaved rounds, as the per-round ratio's median and quartiles (goal ≤ 1.5×).
//! A light edit is a frame input: the G-buffer and everything else that does not depend on the
//! light is reused, the light's shadow map and lighting run again; nothing is uploaded but the
//! light. Scene: `scenes/room.ron` (the Cornell box and a textured glTF chair) at 256×256.
//! Needs an adapter (lavapipe is enough);
//! `cargo test` runs it at its smallest.

use lightbench::gpu::{DeviceOptions, Gpu};
use lightbench::viewer::state::{Action, Viewer};
use lightbench_compiler::Workspace;
use std::path::Path;
use std::time::Instant;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{interleaved, Size};

/// Mean ms per viewer frame over `frames` frames, the light dragged or not.
fn run(gpu: &Gpu, v: &mut Viewer, (frames, drag): (u32, bool)) -> f64 {
    let t = Instant::now();
    for f in 0..frames {
        if drag {
            let mut l = v.scene.lights[0].clone();
            l.position += glam::Vec3::new(if f % 2 == 0 { 0.01 } else { -0.01 }, 0.0, 0.0);
            v.apply(gpu, Action::SetLight(0, Box::new(l))).expect("light edit");
        }
        v.frame(gpu).expect("frame");
        v.view_image(gpu).expect("shown image");
    }
    t.elapsed().as_secs_f64() * 1e3 / frames as f64
}

fn main() {
    let gpu = Gpu::new(&DeviceOptions::default()).expect("a GPU adapter (lavapipe is enough)");
    println!("{}", gpu.describe());
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut scene = lightbench::scene::load(root.join("scenes/room.ron").to_str().unwrap()).expect("scene");
    scene.size = (256, 256);
    let pipeline = root.join("pipelines/deferred.lbp");
    let mut v = Viewer::new(&gpu, (Workspace::disk(), &pipeline, None), scene, &[]).expect("viewer");
    let size = Size::from_args();
    let (frames, rounds) = (size.pick(60, 2), size.pick(6, 1));
    run(&gpu, &mut v, (frames, false)); // warm up
                                        // Both sides borrow the viewer in turn.
    let v = std::cell::RefCell::new(v);
    let p = interleaved(
        rounds,
        || run(&gpu, &mut v.borrow_mut(), (frames, false)),
        || run(&gpu, &mut v.borrow_mut(), (frames, true)),
    );
    println!("viewer on scenes/room.ron at 256×256, deferred.lbp, {frames} frames a round, ms per frame:");
    println!("{}", p.report(("still", "light dragged"), "ms"));
}
