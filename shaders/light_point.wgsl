// One point light with its cube shadow map (classic or multiview variants), added to HDR.
#include "lib/light_pass.wgsl"

struct Params {
    bias: f32,
    pcf: u32,
    normal_offset: f32,
};

@group(2) @binding(3) var shadow_cube: texture_depth_cube;
@group(2) @binding(4) var shadow_cmp: sampler_comparison;
@group(2) @binding(5) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = lit_pixel(pos);
    if !p.s.covered {
        return vec4<f32>(0.0);
    }
    // Looked up from the surface pushed along its normal (normal offset, against acne).
    let dir = p.s.world + p.s.n * params.normal_offset - p.l.position.xyz;
    return vec4<f32>(shade(p.s, p.ls) * cube_shadow(shadow_cube, shadow_cmp, p.l, dir, params.bias, params.pcf != 0u), 0.0);
}
