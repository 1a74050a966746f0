// Temporal accumulation of GTAO (`ao = gtao_temporal`), at the occlusion buffer's size: this
// frame's occlusion, its slices turned (gtao.wgsl#fs_temporal), averaged with the history
// reprojected through the previous frame's view-projection over at most `frames` frames. Where
// the reprojected surface is not the same one — it was hidden, or outside the previous view —
// the history is dropped (lib/reproject.wgsl: the previous frame's depth at the
// reprojected texel must reconstruct to this surface, within `reject` of its distance).
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/reproject.wgsl"

struct Params {
    frames: u32,
    reject: f32,
};

@group(2) @binding(3) var ao_raw: texture_2d<f32>;
@group(2) @binding(4) var ao_history_prev: texture_2d<f32>;
@group(2) @binding(5) var ao_depth_prev: texture_2d<f32>;
@group(2) @binding(6) var<uniform> params: Params;

struct Out {
    // r: accumulated occlusion; g: frames in it
    @location(0) history: vec4<f32>,
    // the depth under this texel, for the next frame's test
    @location(1) depth: vec4<f32>,
};

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> Out {
    let texel = vec2<i32>(pos.xy);
    let px = target_gbuffer_pixel(pos.xy);
    let current = textureLoad(ao_raw, texel, 0).r;
    let depth = textureLoad(gbuf_depth, px, 0).x;
    var out: Out;
    out.history = vec4<f32>(current, 1.0, 0.0, 0.0);
    out.depth = vec4<f32>(depth, 0.0, 0.0, 0.0);
    if depth >= 1.0 {
        return out;
    }
    let q = reproject(world_from_depth(px, depth), instance.target_size.xy, ao_depth_prev, params.reject);
    if q.x < 0 {
        return out; // no history for this surface
    }
    let prev = textureLoad(ao_history_prev, q, 0);
    let n = min(prev.g + 1.0, f32(max(params.frames, 1u)));
    out.history = vec4<f32>(mix(prev.r, current, 1.0 / n), n, 0.0, 0.0);
    return out;
}
