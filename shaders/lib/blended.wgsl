// Shading of blended surfaces (glTF alphaMode BLEND), the same for every transparency option
// (variant `transparency`): forward, by every light (Blinn-Phong, unshadowed) plus ambient and
// emission; the alpha is the material's opacity. Transparent surfaces cast no shadows (shadow
// passes draw the opaque scene).
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

struct Blended {
    // Linear radiance and opacity (not premultiplied).
    color: vec4<f32>,
    // The back of a single-sided pane: not drawn.
    hidden: bool,
};

fn shade_blended(in: VsOut, facing: bool) -> Blended {
    let m = sample_material(in, facing);
    var s = material_surface(in, m);
    // Hazard: a pane at the camera position.
    s.v = safe_normalize(frame.camera_pos.xyz - in.world_pos, s.n);
    let c = ambient_term(m, params.color) + all_lights(s);
    return Blended(vec4<f32>(c, clamp(m.base.a, 0.0, 1.0)), m.hidden);
}
