// One point light whose cube shadow was rendered into a 3×2 atlas (instanced variant).
#include "lib/light_pass.wgsl"

struct Params {
    bias: f32,
    pcf: u32,
    normal_offset: f32,
};

@group(2) @binding(3) var shadow_atlas: texture_depth_2d;
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
    let to_light = safe_normalize(p.l.position.xyz - at, p.ls.to_light);
    return vec4<f32>(shade(p.s, p.ls) * atlas_shadow(shadow_atlas, shadow_cmp, p.l, at, to_light, params.bias, params.pcf != 0u), 0.0);
}
