// Screen-space ambient occlusion (seed 000 §4.2.3, §6.2.3; seed 003 §4.6.3): `samples` points
// of a hemisphere kernel (a data resource, scaled towards the centre) around each surface,
// oriented by its normal and turned by a 4×4 tiled rotation (a data resource), projected to
// the screen; a point is occluded when the surface the camera sees there is nearer than it
// by more than `bias`, counted with the range check smoothstep(0, 1, radius / |difference|).
// With `falloff`, each occluder also weighs 1/(1 + d²), d its distance (seed 003 eq. 4.6).
// The buffer may be smaller than the screen (seed 003 Table 6.4): each texel
// evaluates the surface at the centre of its block. Output: 1 unoccluded … 0 fully occluded.
// World-space positions from depth (the seed works in view space; the test is the same).
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/ao_kernel.wgsl"

struct Params {
    radius: f32,
    samples: u32,
    bias: f32,
    falloff: u32,
    // lengths (radius, bias) in world units, else in the scene's (lib/frame.wgsl)
    world: u32,
};

@group(2) @binding(5) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(frag.xy);
    let s = load_surface(target_gbuffer_pixel(frag.xy));
    if !s.covered {
        return vec4<f32>(1.0);
    }
    let tbn = kernel_frame(s.n, px);
    let n = kernel_count(params.samples);
    let unit = length_unit(params.world);
    var occluded = 0.0;
    for (var i = 0u; i < n; i++) {
        let p = s.world + kernel_point(tbn, i, n, params.radius * unit);
        let c = camera_sample(p, params.bias * unit);
        if c.occluded {
            // Distances in the length unit, so that the falloff 1/(1 + d²) is scale-free too.
            occluded += occluder_weight(params.radius, length(c.seen - p) / unit, params.falloff != 0u);
        }
    }
    return vec4<f32>(1.0 - occluded / f32(n));
}
