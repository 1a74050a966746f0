enable wgpu_ray_query;
// Light from emissive surfaces, ray traced (area_lights = rt): per pixel, `samples` points
// drawn on the emitters (an emitter chosen uniformly, a point uniform in its area), each with a
// shadow ray against the scene's acceleration structure — the reference's next-event estimate
// of the emitters' direct light, soft shadows and all. Its noise is left to the blur after it.
#include "lib/frame.wgsl"
#include "lib/math.wgsl"
#include "lib/lighting.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/ray.wgsl"
#include "lib/emitters.wgsl"
#include "lib/sampling.wgsl"

struct Params {
    samples: u32,
};

@group(2) @binding(8) var<uniform> params: Params;
@group(2) @binding(9) var scene_accel: acceleration_structure;

fn lit(s: Surface, frag: vec2<f32>) -> vec4<f32> {
    if !s.covered {
        return vec4<f32>(0.0);
    }
    let eps = surface_offset(s.world);
    let n = max(params.samples, 1u);
    let seed = vec2<u32>(frag);
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < n; k++) {
        let u = random_pair(seed, frame.frame_index, 2u * k);
        let pick = random_pair(seed, frame.frame_index, 2u * k + 1u).x;
        sum += emitter_light(s, vec3<f32>(u, pick), eps);
    }
    return vec4<f32>(sum / f32(n), 1.0);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return lit(load_surface(vec2<i32>(pos.xy)), pos.xy);
}

@fragment
fn fs_fat(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return lit(load_surface_fat(vec2<i32>(pos.xy)), pos.xy);
}
