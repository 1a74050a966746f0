// G-buffer pass (seed 000 §4.2.1, seed 003 §3.1): normal + roughness, albedo + metallic,
// emission + ambient occlusion. World positions are reconstructed from depth (the packed
// layout of seed 003 §5.2), which keeps the targets at 20 bytes per pixel.
#include "lib/frame.wgsl"
#include "lib/material.wgsl"

struct GBuffer {
    @location(0) normal: vec4<f32>,
    @location(1) albedo: vec4<f32>,
    @location(2) emissive: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VsOut {
    return camera_vertex(v);
}

@fragment
fn fs_main(in: VsOut) -> GBuffer {
    let m = sample_material(in);
    if m.base.a < material.alpha_cutoff {
        discard; // alphaMode MASK: a cut-out
    }
    var out: GBuffer;
    out.normal = vec4<f32>(m.n, m.roughness);
    out.albedo = vec4<f32>(m.base.rgb, m.metallic);
    // Alpha carries ambient occlusion (1: none), which the ambient pass applies.
    out.emissive = vec4<f32>(m.emissive, m.occlusion);
    return out;
}
