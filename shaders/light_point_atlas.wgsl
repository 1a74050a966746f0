// One point light whose cube shadow was rendered into a 3×2 atlas (instanced variant), added
// to HDR (entry points in lib/light_entries.wgsl).
#include "lib/light_entries.wgsl"

@group(2) @binding(3) var shadow_atlas: texture_depth_2d;

fn lit(p: LitPixel) -> vec3<f32> {
    let at = p.s.world + p.s.n * params.normal_offset;
    let to_light = safe_normalize(p.l.position.xyz - at, p.ls.to_light);
    return shade(p.s, p.ls) * atlas_shadow(shadow_atlas, shadow_cmp, p.l, at, to_light, params.bias, params.pcf != 0u);
}
