enable wgpu_ray_query;
// One bounce of ray-traced light, two ways of choosing the bounce (`rays` per pixel, each
// traced to the nearest surface it sees and shaded there with the direct light of every light
// and emitter, with shadow rays, seen back along the ray; its maps looked up, cut-outs passed):
// - `fs_diffuse` (indirect_diffuse = rt): cosine-weighted directions about the normal — the
//   reference's `indirect_diffuse` term, irradiance / π (what a white Lambertian receiver
//   reflects), as `gi.indirect` holds it before the albedo;
// - `fs_specular` (reflections = rt): directions from the surface's Blinn-Phong lobe about the
//   mirror direction (the half vector from the lobe, the view reflected about it), the hit's
//   emission counted too — the reference's `indirect_specular` term, the light seen in the
//   reflection before the surface's reflectance; w = 1 on every surface, so the compose pass
//   never falls back. A rough surface is reflected blurred, as its lobe is wide.
// The noise is left to the blur after them.
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

// Bounce `k`'s direction at surface `s` (below the surface when the lobe's reflection is).
fn bounce_direction(s: Surface, specular: bool, u: vec2<f32>) -> vec3<f32> {
    if !specular {
        return cosine_direction(s.n, u);
    }
    // lib/lighting.wgsl's exponent, roughness clamped as the reference's is.
    let r = clamp(s.roughness, 0.03, 1.0);
    let e = max(2.0 / max(r * r * r * r, 1e-4) - 2.0, 1.0);
    let half = power_lobe(s.n, e, u);
    return normalize(2.0 * dot(s.v, half) * half - s.v);
}

// The mean over `rays` bounces of the light they bring back to the pixel's surface.
fn gather(frag: vec4<f32>, specular: bool) -> vec4<f32> {
    let s = load_surface(vec2<i32>(frag.xy));
    if !s.covered {
        return vec4<f32>(0.0);
    }
    let eps = surface_offset(s.world);
    let origin = s.world + s.n * eps;
    let rays = max(params.rays, 1u);
    let seed = vec2<u32>(frag.xy);
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < rays; k++) {
        let d = bounce_direction(s, specular, random_pair(seed, frame.frame_index, 2u * k));
        if dot(s.n, d) <= 0.0 {
            continue;
        }
        // Blended surfaces are seen by coins (stochastic transparency), as the reference sees them.
        ray_coin = random_bits(seed, frame.frame_index ^ 0x85ebca6bu, k);
        let h = trace_seen_mapped(origin, d, eps, 2.5 * frame.scene_radius);
        if h.found {
            let u = random_pair(seed, frame.frame_index, 2u * k + 1u);
            let pick = random_pair(seed, frame.frame_index ^ 0x9e3779b9u, k).x;
            let emitted = select(vec3<f32>(0.0), h.emissive, specular);
            sum += emitted + direct_light(hit_surface(h, -d), vec3<f32>(u, pick));
        }
    }
    return vec4<f32>(sum / f32(rays), 1.0);
}

@fragment
fn fs_diffuse(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return gather(frag, false);
}

@fragment
fn fs_specular(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return gather(frag, true);
}
