// A second bounce of indirect diffuse light, gathered in screen space (gi_bounces = two): every
// pixel the camera sees is a sender whose first-bounce light (`gi.indirect`, the irradiance / π
// that indirect_diffuse.wgsl or bounce_rt.wgsl gathered, noise and all: the gather averages it)
// it reflects diffusely, radiance albedo × gi.indirect. Samples are spread over the whole
// screen on a shifted rank-1 lattice, each standing for the same number of pixels; a pixel's
// surface area is its width at the sender squared over the cosine at which the camera sees
// it; each sender is tested for occlusion in the depth buffer as the first bounce's are
// (`segment_clear`). Writes the first bounce plus the second into `gi.bounced`, which the
// cross-bilateral blur then filters as it does the first alone. What the camera does not see
// sends nothing: the second bounce is short where its senders are off screen or hidden.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/sampling.wgsl"

struct Params {
    samples: u32,
    min_distance: f32,
    steps: u32,
    thickness: f32,
    world: u32,
};

@group(2) @binding(3) var gi_indirect: texture_2d<f32>;
@group(2) @binding(4) var<uniform> params: Params;

const PI: f32 = 3.14159265;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(pos.xy);
    let first = textureLoad(gi_indirect, px, 0);
    let s = load_surface(px);
    if !s.covered {
        return first;
    }
    let size = vec2<i32>(frame.resolution.xy);
    let n = max(params.samples, 1u);
    let shift = pixel_shift(vec2<u32>(px));
    let unit = length_unit(params.world);
    let min_d2 = params.min_distance * params.min_distance * unit * unit;
    // Pixels each sample stands for.
    let per_sample = f32(size.x * size.y) / f32(n);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < n; i++) {
        let q = min(vec2<i32>(fract(lattice(i, n) + shift) * vec2<f32>(size)), size - 1);
        let r = load_surface(q);
        if !r.covered {
            continue;
        }
        let d = r.world - s.world;
        let facing = max(dot(s.n, d), 0.0) * max(dot(r.n, -d), 0.0);
        let jitter = fract(shift.y + f32(i) * 0.618034);
        if facing == 0.0 || !segment_clear(s.world, r.world, params.steps, params.thickness * unit, 0.01 * unit, jitter) {
            continue;
        }
        // The sender pixel's area: its width there squared, over the cosine the camera sees it at.
        let w = texel_width(frame.view_proj, r.world, frame.resolution.x);
        let seen = max(dot(r.n, normalize(frame.camera_pos.xyz - r.world)), 0.05);
        let radiance = r.albedo * (1.0 - r.metallic) * textureLoad(gi_indirect, q, 0).rgb;
        let d2 = max(dot(d, d), min_d2);
        sum += radiance * facing * w * w / seen * per_sample / (d2 * d2);
    }
    // ∫ L cos θ_r cos θ_s / |d|² dA = E (the receiver's irradiance); the term held is E / π.
    return vec4<f32>(first.rgb + sum / PI, first.a);
}
