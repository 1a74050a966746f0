// Blended surfaces (glTF alphaMode BLEND), drawn over the lit HDR image after the deferred
// lighting: `draw: Transparent` gives the blended meshes from far to near, each shaded
// forward by every light (Blinn-Phong, unshadowed) plus ambient and emission, and composited
// with "over" blending (alpha: the material's opacity). Depth is tested against the
// G-buffer's, not written, so nearer opaque surfaces hide them and they hide nothing.
// Transparent surfaces cast no shadows (shadow passes draw the opaque scene).
#include "lib/frame.wgsl"
#include "lib/lighting.wgsl"
#include "lib/material.wgsl"

struct Params {
    color: vec3<f32>,
};

@group(2) @binding(0) var<uniform> params: Params;

@vertex
fn vs_main(v: VertexIn) -> VsOut {
    return camera_vertex(v);
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let m = sample_material(in);
    // Panes are seen from both sides: light the side facing the camera.
    let n = select(-m.n, m.n, front);
    // Hazard: a pane at the camera position.
    let v = safe_normalize(frame.camera_pos.xyz - in.world_pos, n);
    var c = m.base.rgb * params.color * (1.0 - m.metallic) * m.occlusion + m.emissive;
    for (var i = 0u; i < frame.light_count; i++) {
        let ls = light_at(lights[i], in.world_pos);
        c += blinn_phong(n, ls.to_light, v, m.base.rgb, m.metallic, m.roughness) * ls.radiance;
    }
    return vec4<f32>(c, clamp(m.base.a, 0.0, 1.0));
}
