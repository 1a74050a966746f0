// Bloom, steps 3 and 4: one level of the chain, filtered bilinearly to the target's size and
// scaled by `strength`, for the target's `blend: Add`. The up-sample pass fixes strength to 1
// with a per-pass value; the pass that adds the chain to the HDR image takes the
// `bloom.strength` parameter. One shader, two passes.
#include "lib/frame.wgsl"

struct Params {
    strength: f32,
};

@group(2) @binding(0) var input: texture_2d<f32>;
@group(2) @binding(1) var bloom_linear: sampler;
@group(2) @binding(2) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let uv = pos.xy * instance.target_size.zw;
    return vec4<f32>(textureSampleLevel(input, bloom_linear, uv, 0.0).rgb * params.strength, 0.0);
}
