// One point light with its cube shadow map (classic or multiview variants), added to HDR
// (entry points in lib/light_entries.wgsl).
#include "lib/light_entries.wgsl"

@group(2) @binding(3) var shadow_cube: texture_depth_cube;

fn lit(p: LitPixel) -> vec3<f32> {
    let dir = p.s.world + p.s.n * params.normal_offset - p.l.position.xyz;
    return shade(p.s, p.ls) * cube_shadow(shadow_cube, shadow_cmp, p.l, dir, params.bias, params.pcf != 0u);
}
