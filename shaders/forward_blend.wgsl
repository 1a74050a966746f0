// Blended surfaces (glTF alphaMode BLEND), drawn over the lit HDR image after the deferred
// lighting: `draw: Transparent` gives the blended meshes from far to near, each shaded
// forward by every light (Blinn-Phong, unshadowed) plus ambient and emission, and composited
// with "over" blending (alpha: the material's opacity). Depth is tested against the
// G-buffer's, not written, so nearer opaque surfaces hide them and they hide nothing.
// Transparent surfaces cast no shadows (shadow passes draw the opaque scene).
#include "lib/frame.wgsl"
#include "lib/forward.wgsl"

struct Params {
    color: vec3<f32>,
};

@group(2) @binding(0) var<uniform> params: Params;

@vertex
fn vs_main(v: VertexIn) -> VsOut {
    return camera_vertex(v);
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let m = sample_material(in, facing);
    if m.hidden {
        discard; // the back of a single-sided pane
    }
    var s = material_surface(in, m);
    // Hazard: a pane at the camera position.
    s.v = safe_normalize(frame.camera_pos.xyz - in.world_pos, s.n);
    let c = ambient_term(m, params.color) + all_lights(s);
    return vec4<f32>(c, clamp(m.base.a, 0.0, 1.0));
}
