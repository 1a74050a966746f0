// Depth peeling (transparency = depth_peeling; seed 003 §4.5, §5.8): the blended surfaces are
// drawn `peel.layers` times (`repeat`). Run k keeps, per pixel, the nearest fragment behind the
// one run k − 1 kept — whose depth is in layer k − 1 of `peel.depth` — and in front of the
// opaque scene (the depth test against this run's own layer keeps the nearest of the rest),
// and writes it to layer k of `peel.color`: the layers come out sorted front to back, and
// `peel_resolve.wgsl` blends them. A fragment at exactly the depth of the one peeled before is
// peeled with it (of coplanar surfaces, one is kept).
#include "lib/blended.wgsl"

@group(2) @binding(1) var gbuf_depth: texture_2d<f32>;
// Layer k − 1 of `peel.depth` (in the first run, another layer, not read).
@group(2) @binding(2) var peel_depth: texture_2d<f32>;

@fragment
fn fs_peel(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let px = vec2<i32>(in.clip.xy);
    let depth = in.clip.z;
    if depth >= textureLoad(gbuf_depth, px, 0).x {
        discard; // behind the opaque scene (the depth attachment is this run's own)
    }
    if instance.repetition > 0u && depth <= textureLoad(peel_depth, px, 0).x {
        discard; // peeled in an earlier run
    }
    let b = shade_blended(in, facing);
    if b.hidden {
        discard;
    }
    return b.color;
}
