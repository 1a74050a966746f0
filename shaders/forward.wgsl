// Forward shading (seed 003 §2.4, §5.1): the scene drawn with its lighting computed as it is
// drawn, no G-buffer. `fs_single` shades every light in one pass (§2.4.1, listing 5.3);
// `fs_depth` and `fs_ambient` open multi-pass lighting (§5.1.2), whose per-light passes use
// `fs_forward` of the deferred light shaders over this file's `vs_main`.
#include "lib/frame.wgsl"
#include "lib/forward.wgsl"

struct Params {
    // ambient light (linear RGB)
    color: vec3<f32>,
};

@group(2) @binding(0) var<uniform> params: Params;

// Every forward pass transforms vertices here, so that the depth of the pre-pass and the
// depth the later passes test with `Equal` come from the same arithmetic.
@vertex
fn vs_main(v: VertexIn) -> VsOut {
    return camera_vertex(v);
}

// The depth pre-pass: depth only (cut-outs discarded, so that `Equal` later matches).
@fragment
fn fs_depth(in: VsOut, @builtin(front_facing) facing: bool) {
    if cut_out(sample_material(in, facing)) {
        discard;
    }
}

@fragment
fn fs_ambient(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let m = sample_material(in, facing);
    if cut_out(m) {
        discard;
    }
    return vec4<f32>(ambient_term(m, params.color), 1.0);
}

// Single-pass lighting: ambient, emission and every light of the storage buffer, without
// shadows (one shader would need every light's shadow map bound at once, seed 003 §4.4).
@fragment
fn fs_single(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let m = sample_material(in, facing);
    if cut_out(m) {
        discard;
    }
    return vec4<f32>(ambient_term(m, params.color) + all_lights(material_surface(in, m)), 1.0);
}
