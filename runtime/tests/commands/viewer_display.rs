//! What the viewer's window draws: the output straight from the GPU (a texture copy, no
//! read-back per frame); resources that need the display mapping (HDR, depth, data) read back
//! and mapped on the CPU as before.

use crate::gpu_common::*;
use lightbench::viewer::state::{Action, Viewer};
use lightbench_compiler::Workspace;

#[test]
fn the_output_is_shown_from_its_gpu_texture_and_mapped_views_are_not() {
    let g = gpu();
    let mut scene = lightbench::scene::builtin::cornell();
    scene.size = (40, 32);
    let pipeline = root().join("pipelines/deferred.lbp");
    let mut v = Viewer::new(&g, (Workspace::disk(), &pipeline, None), scene, &[]).unwrap_or_else(|e| panic!("{e}"));
    v.frame(&g).unwrap();
    let (texture, layer, caption) = v.shown_texture().unwrap().expect("the output is drawn from the GPU");
    assert_eq!((texture.width(), texture.height(), layer), (40, 32, 0));
    assert!(caption.starts_with("ldr (Rgba8UnormSrgb)"), "{caption}");
    // The texture the window copies holds the bytes the read-back path shows, exactly.
    let shown = lightbench::gpu::readback::read_texture(&g, &texture, 0).unwrap();
    let (w, h, rgb, mapped_caption) = v.view_image(&g).unwrap();
    assert_eq!((w, h, caption), (40, 32, mapped_caption));
    let copied: Vec<u8> = shown
        .rgba
        .chunks_exact(4)
        .flat_map(|p| p[..3].iter().map(|c| (c * 255.0).round() as u8))
        .collect();
    assert!(copied == rgb, "the copied texture is what the read-back path shows");
    // HDR needs tone mapping for display: read back and mapped, not drawn as it is.
    v.apply(&g, Action::View("hdr".into())).unwrap();
    assert!(v.shown_texture().unwrap().is_none());
    assert!(v.view_image(&g).unwrap().3.starts_with("hdr (Rgba16Float)"));
}
