enable wgpu_ray_query;
// Ray-traced reflections (reflections = rt): per pixel, `rays` directions drawn from the
// surface's Blinn-Phong lobe about the mirror direction (the half vector from the lobe, the
// view reflected about it), each traced to the nearest surface it sees; there, its emission
// and its direct light (every light and the emitters, with shadow rays) seen back along the
// ray. The mean is the reference's `indirect_specular` term, the light seen in the reflection
// before the surface's reflectance; w = 1 on every surface, so the compose pass never falls
// back. A rough surface is reflected blurred, as its lobe is wide.
#include "lib/frame.wgsl"
#include "lib/math.wgsl"
#include "lib/lighting.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/ray.wgsl"
#include "lib/hit.wgsl"
#include "lib/emitters.wgsl"
#include "lib/sampling.wgsl"

struct Params {
    rays: u32,
};

@group(2) @binding(8) var<uniform> params: Params;
@group(2) @binding(9) var scene_accel: acceleration_structure;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(frag.xy);
    let s = load_surface(px);
    if !s.covered {
        return vec4<f32>(0.0);
    }
    let eps = surface_offset(s.world);
    let origin = s.world + s.n * eps;
    // lib/lighting.wgsl's exponent, roughness clamped as the reference's is.
    let r = clamp(s.roughness, 0.03, 1.0);
    let e = max(2.0 / max(r * r * r * r, 1e-4) - 2.0, 1.0);
    let rays = max(params.rays, 1u);
    let seed = vec2<u32>(frag.xy);
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < rays; k++) {
        let half = power_lobe(s.n, e, random_pair(seed, frame.frame_index, 2u * k));
        let l = normalize(2.0 * dot(s.v, half) * half - s.v);
        if dot(s.n, l) <= 0.0 {
            continue;
        }
        let h = trace_seen(origin, l, eps, 2.5 * frame.scene_radius);
        if h.found {
            let u = random_pair(seed, frame.frame_index, 2u * k + 1u);
            let pick = random_pair(seed, frame.frame_index ^ 0x9e3779b9u, k).x;
            sum += h.emissive + direct_light(hit_surface(h, -l), vec3<f32>(u, pick));
        }
    }
    return vec4<f32>(sum / f32(rays), 1.0);
}
