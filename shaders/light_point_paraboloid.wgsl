// One point light with its dual paraboloid shadow maps (seed 003 §4.4.1), added to HDR
// (entry points in lib/light_entries.wgsl).
#include "lib/light_entries.wgsl"
#include "lib/paraboloid.wgsl"

@group(2) @binding(3) var shadow_paraboloid: texture_depth_2d_array;

fn lit(p: LitPixel) -> vec3<f32> {
    let texel = paraboloid_texel(distance(p.s.world, p.l.position.xyz), f32(textureDimensions(shadow_paraboloid).x));
    let at = shadow_lookup_point(p.s.world, p.s.n, p.ls.to_light, params.bias_texels, params.normal_offset_texels, texel);
    return shade(p.s, p.ls) * paraboloid_shadow(shadow_paraboloid, shadow_cmp, p.l, at - p.l.position.xyz, params.pcf != 0u);
}
