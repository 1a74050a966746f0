// Blended surfaces (glTF alphaMode BLEND) sorted by object (transparency = sorted), drawn
// over the lit HDR image after the deferred lighting: `draw: Transparent` gives the blended
// meshes from far to near, each composited with "over" blending. Depth is tested against the
// G-buffer's, not written, so nearer opaque surfaces hide them and they hide nothing. Wrong
// where surfaces interpenetrate or overlap cyclically: the order is per object, not per
// fragment (transparency = fragment_lists or depth_peeling sort per pixel).
#include "lib/blended.wgsl"

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let b = shade_blended(in, facing);
    if b.hidden {
        discard;
    }
    return b.color;
}
