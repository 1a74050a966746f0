// One point light with its cube shadow map (classic or multiview variants), added to HDR
// (entry points in lib/light_entries.wgsl).
#include "lib/light_entries.wgsl"

@group(2) @binding(3) var shadow_cube: texture_depth_cube;

fn lit(p: LitPixel) -> vec3<f32> {
    let texel = cube_texel(p.s.world - p.l.position.xyz, f32(textureDimensions(shadow_cube).x));
    let at = shadow_lookup_point(p.s.world, p.s.n, p.ls.to_light, params.bias_texels, params.normal_offset_texels, texel);
    return shade(p.s, p.ls) * cube_shadow(shadow_cube, shadow_cmp, p.l, at - p.l.position.xyz, params.pcf != 0u);
}
