//! The viewer's path-traced view (`trace on`, key T): the GPU reference of what the viewer
//! shows, refining frame by frame, starting again when the camera or a light changes.

use crate::gpu_common;
use lightbench::gpu_reference::{render, Tracer};
use lightbench::reference::{Budget, Settings, Term};
use lightbench::viewer::state::{parse_action, Action, Viewer};
use lightbench_compiler::Workspace;

#[test]
fn the_path_traced_view_is_the_gpu_reference_and_restarts_on_change() {
    let g = gpu_common::gpu();
    let mut scene = lightbench::scene::builtin::cornell();
    scene.size = (24, 24);
    let pipeline = gpu_common::root().join("pipelines/deferred.lbp");
    let mut v = Viewer::new(&g, (Workspace::disk(), &pipeline, None), scene.clone(), &[]).unwrap();
    v.apply(&g, parse_action("trace on", None).unwrap()).unwrap();
    for _ in 0..3 {
        v.frame(&g).unwrap();
    }
    let t = v.traced.as_ref().unwrap();
    assert_eq!(t.samples, 12, "4 paths a frame");
    assert!(t.caption().contains("12 paths per pixel"), "{}", t.caption());
    // The same paths as `reference --device gpu` with 12 samples (seed 0).
    let traced = t.ex.read_texture(&g, "pt.mean", 0, 0).unwrap();
    // The path tracer the viewer runs, from where the viewer finds it.
    let (tracer_path, ws) = lightbench::gpu_reference::source(None).unwrap();
    let s = Settings {
        budget: Budget::Spp(12),
        terms: vec![Term::Full],
        ..Settings::default()
    };
    let r = render(
        &g,
        &Tracer {
            ws: &ws,
            pipeline: &tracer_path,
        },
        &scene,
        &s,
        false,
    )
    .unwrap();
    let reference = &r.term(Term::Full).unwrap().mean;
    for (a, b) in traced.rgba.chunks_exact(4).zip(reference.rgba.chunks_exact(4)) {
        assert_eq!(a[..3], b[..3]);
    }
    let (w, h, rgb, caption) = v.view_image(&g).unwrap();
    assert_eq!((w, h), (24, 24));
    assert!(rgb.iter().any(|c| *c > 20), "a lit image");
    assert!(caption.starts_with("path traced"), "{caption}");
    // The camera moves: the accumulation starts again, in the shader and in the count.
    v.apply(&g, Action::Move(glam::Vec3::new(0.05, 0.0, 0.0))).unwrap();
    v.frame(&g).unwrap();
    let t = v.traced.as_ref().unwrap();
    assert_eq!(t.samples, 4);
    let counts = t.ex.read_texture(&g, "pt.mean", 0, 0).unwrap();
    assert!(counts.rgba.chunks_exact(4).all(|p| p[3] == 4.0), "restarted at the move");
    // A light moves (a frame input for the raster): the path tracer starts again too.
    v.frame(&g).unwrap();
    let mut moved = v.scene.lights[0].clone();
    moved.position += glam::Vec3::new(0.2, 0.0, 0.0);
    v.apply(&g, Action::SetLight(0, Box::new(moved))).unwrap();
    v.frame(&g).unwrap();
    assert_eq!(v.traced.as_ref().unwrap().samples, 4);
    // Off: the raster output is shown again.
    v.apply(&g, Action::ToggleTrace).unwrap();
    assert!(v.traced.is_none());
    v.frame(&g).unwrap();
    let (_, _, _, caption) = v.view_image(&g).unwrap();
    assert!(caption.starts_with("ldr"), "{caption}");
    assert!(parse_action("trace maybe", None).is_err());
}
