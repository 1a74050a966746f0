enable wgpu_ray_query;
// Ray-traced ambient occlusion (ao = rtao): per pixel, `rays` cosine-weighted directions about
// the surface normal, each traced against the scene's acceleration structure out to the
// radius; the share that meets nothing (with `falloff`, a hit at distance d still lets
// 1 − 1/(1 + d²) through). This is the reference's `ao` term estimated with few rays: its
// noise is left to the blur after it. Output: 1 unoccluded … 0 fully occluded.
#include "lib/frame.wgsl"
#include "lib/math.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/ray.wgsl"
#include "lib/sampling.wgsl"

struct Params {
    radius: f32,
    rays: u32,
    falloff: u32,
    // the radius in world units, else in the scene's (lib/frame.wgsl)
    world: u32,
};

@group(2) @binding(3) var<uniform> params: Params;
@group(2) @binding(4) var scene_accel: acceleration_structure;

// What one ray along `d` from `origin` lets through (1: it meets nothing within the radius;
// cut-outs passed, blended surfaces by the coin `ray_coin`, as the reference's AO rays).
fn ray_visibility(origin: vec3<f32>, d: vec3<f32>, eps: f32, radius: f32) -> f32 {
    let t = nearest_occluder(origin, d, eps, radius);
    if t < 0.0 {
        return 1.0;
    }
    return select(0.0, 1.0 - 1.0 / (1.0 + t * t), params.falloff != 0u);
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let px = target_gbuffer_pixel(frag.xy);
    let s = load_surface(px);
    if !s.covered {
        return vec4<f32>(1.0);
    }
    let radius = params.radius * length_unit(params.world);
    let eps = surface_offset(s.world);
    let origin = s.world + s.n * eps;
    let rays = max(params.rays, 1u);
    var sum = 0.0;
    for (var k = 0u; k < rays; k++) {
        let d = cosine_direction(s.n, random_pair(vec2<u32>(frag.xy), frame.frame_index, k));
        ray_coin = random_bits(vec2<u32>(frag.xy), frame.frame_index ^ 0x85ebca6bu, k);
        sum += ray_visibility(origin, d, eps, radius);
    }
    return vec4<f32>(sum / f32(rays));
}
