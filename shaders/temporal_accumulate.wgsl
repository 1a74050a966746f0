// Temporal accumulation over a reprojected history, for indirect diffuse light (after Lambru
// et al., seed 000 §4.3.3 and ch. 9: the rotated samples of `indirect_diffuse.wgsl`) and for
// GTAO (`ao = gtao_temporal`: gtao.wgsl#fs_temporal turns its slices each frame). At the
// target's size (an occlusion buffer may be smaller than the screen), this frame's `current`
// is averaged with the history over at most `frames` frames. Where the reprojected surface is
// not the same one — it was hidden (disocclusion), or outside the previous view — the history
// is dropped (lib/reproject.wgsl: the previous frame's depth at the reprojected texel must
// reconstruct to this surface, within `reject` of its distance to the camera).
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/reproject.wgsl"

// How many channels `current` has: 3 (irradiance), or 1 (occlusion, kept with its count in
// a two-channel history).
override CHANNELS: u32 = 3u;

struct Params {
    frames: u32,
    reject: f32,
};

@group(2) @binding(3) var current: texture_2d<f32>;
@group(2) @binding(4) var history_prev: texture_2d<f32>;
@group(2) @binding(5) var depth_prev: texture_2d<f32>;
@group(2) @binding(6) var<uniform> params: Params;

struct Out {
    // the accumulated value and the frames in it: rgb and a, or r and g (CHANNELS = 1)
    @location(0) history: vec4<f32>,
    // the depth under this texel, for the next frame's test
    @location(1) depth: vec4<f32>,
};

fn history(value: vec3<f32>, n: f32) -> vec4<f32> {
    if CHANNELS == 1u {
        return vec4<f32>(value.x, n, 0.0, 0.0);
    }
    return vec4<f32>(value, n);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> Out {
    let px = target_gbuffer_pixel(pos.xy);
    let now = textureLoad(current, vec2<i32>(pos.xy), 0).rgb;
    let depth = textureLoad(gbuf_depth, px, 0).x;
    var out: Out;
    out.history = history(now, 1.0);
    out.depth = vec4<f32>(depth, 0.0, 0.0, 0.0);
    if depth >= 1.0 {
        return out;
    }
    let q = reproject(world_from_depth(px, depth), instance.target_size.xy, depth_prev, params.reject);
    if q.x < 0 {
        return out; // no history for this surface
    }
    let prev = textureLoad(history_prev, q, 0);
    let was = select(vec4<f32>(prev.rgb, prev.a), vec4<f32>(prev.r, 0.0, 0.0, prev.g), CHANNELS == 1u);
    let n = min(was.w + 1.0, f32(max(params.frames, 1u)));
    out.history = history(mix(was.xyz, now, 1.0 / n), n);
    return out;
}
