enable wgpu_ray_query;
// One light of any kind with a ray-traced shadow (shadows = rt), added to the HDR buffer: one
// shadow ray per pixel against the scene's acceleration structure (entry points in
// lib/light_entries.wgsl). Exact hard shadows: no map resolution, bias or acne to trade.
#include "lib/light_entries.wgsl"
#include "lib/ray.wgsl"

@group(2) @binding(3) var scene_accel: acceleration_structure;

fn lit(p: LitPixel) -> vec3<f32> {
    return shade(p.s, p.ls) * light_visibility(p.l, p.s.world, p.s.n, p.ls.to_light);
}
