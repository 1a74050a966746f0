// One point light whose cube shadow was rendered into a 3×2 atlas (instanced variant), added
// to HDR (entry points in lib/light_entries.wgsl).
#include "lib/light_entries.wgsl"

@group(2) @binding(3) var shadow_atlas: texture_depth_2d;

fn lit(p: LitPixel) -> vec3<f32> {
    // A face's tile is a third of the atlas wide.
    let texel = cube_texel(p.s.world - p.l.position.xyz, f32(textureDimensions(shadow_atlas).x) / 3.0);
    let at = shadow_lookup_point(p.s.world, p.s.n, p.ls.to_light, params.bias_texels, params.normal_offset_texels, texel);
    let to_light = safe_normalize(p.l.position.xyz - at, p.ls.to_light);
    return shade(p.s, p.ls) * atlas_shadow(shadow_atlas, shadow_cmp, p.l, at, to_light, params.pcf != 0u);
}
