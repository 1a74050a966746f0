// One point light with its dual paraboloid shadow maps (seed 003 §4.4.1), added to HDR
// (entry points in lib/light_entries.wgsl).
#include "lib/light_entries.wgsl"
#include "lib/paraboloid.wgsl"

@group(2) @binding(3) var shadow_paraboloid: texture_depth_2d_array;

fn lit(p: LitPixel) -> vec3<f32> {
    let d = p.s.world + p.s.n * params.normal_offset - p.l.position.xyz;
    return shade(p.s, p.ls) * paraboloid_shadow(shadow_paraboloid, shadow_cmp, p.l, d, params.bias, params.pcf != 0u);
}
