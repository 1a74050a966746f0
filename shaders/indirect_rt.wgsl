enable wgpu_ray_query;
// Ray-traced indirect diffuse (indirect_diffuse = rt): one bounce, as the reference's
// `indirect_diffuse` term defines it — per pixel, `rays` cosine-weighted directions about the
// normal, each traced to the nearest surface it sees; there, the direct light of every light
// (with a shadow ray) and of the emitters (one point on one, with a shadow ray) reflected back
// along the ray. The mean is irradiance / π (what a white Lambertian receiver reflects), as
// `gi.indirect` holds it before the albedo; its noise is left to the blur after it.
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
    let rays = max(params.rays, 1u);
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < rays; k++) {
        let seed = vec2<u32>(frag.xy);
        let d = cosine_direction(s.n, random_pair(seed, frame.frame_index, 2u * k));
        let h = trace_seen(origin, d, eps, 2.5 * frame.scene_radius);
        if h.found {
            let u = random_pair(seed, frame.frame_index, 2u * k + 1u);
            let pick = random_pair(seed, frame.frame_index ^ 0x9e3779b9u, k).x;
            sum += direct_light(hit_surface(h, -d), vec3<f32>(u, pick));
        }
    }
    return vec4<f32>(sum / f32(rays), 1.0);
}
