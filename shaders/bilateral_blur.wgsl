// Separable cross-bilateral blur (seed 003 eq. 4.7): along `dir`, texels within `size` are
// averaged with weights that fall with the difference in distance from the camera (relative,
// `depth_sigma`) and in normal, so occlusion does not leak across depth edges. One shader,
// two passes: each fixes `dir` with a per-pass value. The buffer may be smaller than the
// screen: each texel is compared by the surface at the centre of its block.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"

struct Params {
    dir: vec2<f32>,
    size: u32,
    depth_sigma: f32,
};

@group(2) @binding(3) var input: texture_2d<f32>;
@group(2) @binding(4) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(pos.xy);
    let dims = vec2<f32>(textureDimensions(input, 0));
    let centre = load_surface(gbuffer_pixel(px, dims));
    let here = textureLoad(input, px, 0);
    if !centre.covered {
        return here;
    }
    let dist = length(centre.world - frame.camera_pos.xyz);
    let last = vec2<i32>(textureDimensions(input, 0)) - 1;
    let step = vec2<i32>(params.dir);
    let n = i32(params.size);
    var sum = vec4<f32>(0.0);
    var total = 0.0;
    for (var i = -n; i <= n; i++) {
        let q = clamp(px + step * i, vec2<i32>(0), last);
        let s = load_surface(gbuffer_pixel(q, dims));
        if !s.covered {
            continue;
        }
        let dd = (length(s.world - frame.camera_pos.xyz) - dist) / max(dist * params.depth_sigma, 1e-6);
        let w = exp(-0.5 * dd * dd) * pow(max(dot(s.n, centre.n), 0.0), 8.0);
        sum += textureLoad(input, q, 0) * w;
        total += w;
    }
    // The centre always weighs 1, so the total is never 0.
    return sum / max(total, 1e-6);
}
