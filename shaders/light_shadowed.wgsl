// One directional or spot light with its shadow map, added to the HDR buffer: deferred
// (`fs_main`, multi-pass deferred lighting, seed 003 §3.2: full-screen or over the light's
// volume) or forward (`fs_forward`, multi-pass forward lighting, seed 003 §5.1.2).
#include "lib/light_pass.wgsl"
#include "lib/forward.wgsl"

struct Params {
    bias: f32,
    pcf: u32,
    normal_offset: f32,
};

@group(2) @binding(3) var shadow_map: texture_depth_2d;
@group(2) @binding(4) var shadow_cmp: sampler_comparison;
@group(2) @binding(5) var<uniform> params: Params;

fn lit(p: LitPixel) -> vec3<f32> {
    // Looked up from the surface pushed along its normal (normal offset, against acne).
    let at = p.s.world + p.s.n * params.normal_offset;
    return shade(p.s, p.ls) * map_shadow(shadow_map, shadow_cmp, p.l, at, p.s.n, p.ls.to_light, params.bias, params.pcf != 0u);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = lit_pixel(pos);
    if !p.s.covered {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(lit(p), 0.0);
}

// Deferred over the fat G-buffer layout.
@fragment
fn fs_fat(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = lit_surface(load_surface_fat(vec2<i32>(pos.xy)));
    if !p.s.covered {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(lit(p), 0.0);
}

@fragment
fn fs_forward(in: VsOut) -> @location(0) vec4<f32> {
    let m = sample_material(in);
    if cut_out(m) {
        discard;
    }
    return vec4<f32>(lit(lit_surface(material_surface(in, m))), 0.0);
}
