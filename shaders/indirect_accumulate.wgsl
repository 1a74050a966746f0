// Temporal accumulation of the rotated indirect diffuse samples (after Lambru et al., seed
// 000 §4.3.3 and ch. 9): this frame's estimate is averaged with the history reprojected
// through the previous frame's view-projection, over at most `frames` frames. Where the
// reprojected surface is not the same one — it was hidden (disocclusion), or outside the
// previous view — the history is dropped (the position test: the previous frame's depth at
// the reprojected pixel must reconstruct to this surface, within `reject` of its distance
// to the camera).
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/reproject.wgsl"

struct Params {
    frames: u32,
    reject: f32,
};

@group(2) @binding(3) var gi_indirect: texture_2d<f32>;
@group(2) @binding(4) var gi_history_prev: texture_2d<f32>;
@group(2) @binding(5) var gi_depth_prev: texture_2d<f32>;
@group(2) @binding(6) var<uniform> params: Params;

struct Out {
    // rgb: accumulated irradiance / π; a: frames in it
    @location(0) history: vec4<f32>,
    // this frame's depth, for the next frame's test
    @location(1) depth: vec4<f32>,
};

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> Out {
    let px = vec2<i32>(pos.xy);
    let current = textureLoad(gi_indirect, px, 0).rgb;
    let depth = textureLoad(gbuf_depth, px, 0).x;
    var out: Out;
    out.history = vec4<f32>(current, 1.0);
    out.depth = vec4<f32>(depth, 0.0, 0.0, 0.0);
    if depth >= 1.0 {
        return out;
    }
    let q = reproject(world_from_depth(px, depth), frame.resolution.xy, gi_depth_prev, params.reject);
    if q.x < 0 {
        return out; // no history for this surface
    }
    let prev = textureLoad(gi_history_prev, q, 0);
    let n = min(prev.a + 1.0, f32(max(params.frames, 1u)));
    out.history = vec4<f32>(mix(prev.rgb, current, 1.0 / n), n);
    return out;
}
