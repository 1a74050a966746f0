// One directional or spot light, added to the HDR buffer (multi-pass deferred lighting,
// seed 003 §3.2), with its shadow map.
#include "lib/light_pass.wgsl"

struct Params {
    bias: f32,
    pcf: u32,
    normal_offset: f32,
};

@group(2) @binding(3) var shadow_map: texture_depth_2d;
@group(2) @binding(4) var shadow_cmp: sampler_comparison;
@group(2) @binding(5) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = lit_pixel(pos);
    if !p.s.covered {
        return vec4<f32>(0.0);
    }
    // Looked up from the surface pushed along its normal (normal offset, against acne).
    let at = p.s.world + p.s.n * params.normal_offset;
    return vec4<f32>(shade(p.s, p.ls) * map_shadow(shadow_map, shadow_cmp, p.l, at, p.s.n, p.ls.to_light, params.bias, params.pcf != 0u), 0.0);
}
