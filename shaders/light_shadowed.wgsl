// One directional or spot light with its shadow map, added to the HDR buffer (multi-pass
// lighting, seed 003 §3.2, §5.1.2; entry points in lib/light_entries.wgsl).
#include "lib/light_entries.wgsl"

@group(2) @binding(3) var shadow_map: texture_depth_2d;

fn lit(p: LitPixel) -> vec3<f32> {
    let texel = texel_width(p.l.view_proj, p.s.world, f32(textureDimensions(shadow_map).x));
    let at = shadow_lookup_point(p.s.world, p.s.n, p.ls.to_light, params.bias_texels, params.normal_offset_texels, texel);
    return shade(p.s, p.ls) * map_shadow(shadow_map, shadow_cmp, p.l, at, params.pcf != 0u);
}
