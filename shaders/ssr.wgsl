// Screen-space reflections (seed 000 §4.2.4, Algorithm 1, §6.2.4): the view ray reflected
// at each pixel is marched through the G-buffer with a fixed world-space step until it is
// behind the surface seen there by less than `thickness`, then refined by binary search; the
// lit colour (the HDR image so far) at the hit is the reflected light, w = 1 marks a hit.
// Rays that leave the screen, reach behind the camera (w ≤ 0) or run out of steps miss
// (w = 0). Deviation: depth is compared as distance from the camera along the ray (the seed
// compares view-space z), which is the same test for a pinhole camera and needs no view
// matrix split.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"

struct Params {
    step: f32,
    max_steps: u32,
    thickness: f32,
    binary_steps: u32,
    // lengths (step, thickness) in world units, else in the scene's (lib/frame.wgsl)
    world: u32,
};

// The march step and the thickness, in world units.
fn march_step() -> f32 {
    return params.step * length_unit(params.world);
}

fn thickness() -> f32 {
    return params.thickness * length_unit(params.world);
}

@group(2) @binding(3) var hdr: texture_2d<f32>;
@group(2) @binding(4) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let s = load_surface(vec2<i32>(frag.xy));
    if !s.covered {
        return vec4<f32>(0.0);
    }
    let dir = reflect(-s.v, s.n);
    var pos = s.world + s.n * march_step() * 0.5;
    var step = dir * march_step();
    for (var i = 0u; i < params.max_steps; i++) {
        pos += step;
        let p = probe(pos);
        if p.miss || p.behind <= 0.0 {
            continue;
        }
        if p.behind > thickness() {
            continue; // passed behind a surface too far: not the one it hits
        }
        // Binary search between the last two positions.
        var best = p;
        for (var j = 0u; j < params.binary_steps; j++) {
            step *= 0.5;
            let q = probe(pos - step);
            if !q.miss && q.behind > 0.0 {
                pos -= step;
                best = q;
            }
        }
        return vec4<f32>(textureLoad(hdr, best.pixel, 0).rgb, 1.0);
    }
    return vec4<f32>(0.0);
}
