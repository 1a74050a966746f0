// Bloom, step 1: the light above a threshold, at half resolution (the mean of each 2×2
// block of the HDR image), into mip 0 of the bloom chain. `mip_down.wgsl` then fills the
// smaller levels and `bloom_resample.wgsl` adds them back up.
#include "lib/frame.wgsl"

struct Params {
    threshold: f32,
};

@group(2) @binding(0) var hdr: texture_2d<f32>;
@group(2) @binding(1) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let q = vec2<i32>(pos.xy) * 2;
    let last = vec2<i32>(textureDimensions(hdr, 0)) - 1;
    var c = vec3<f32>(0.0);
    for (var i = 0; i < 4; i++) {
        c += textureLoad(hdr, min(q + vec2<i32>(i & 1, i >> 1), last), 0).rgb;
    }
    c *= 0.25;
    let l = dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
    // Keep the part of the light above the threshold, in its own colour.
    let keep = max(l - params.threshold, 0.0) / max(l, 1e-6);
    return vec4<f32>(c * keep, 1.0);
}
