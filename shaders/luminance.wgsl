// Log-average luminance and the brightest luminance (Lwhite) of the HDR buffer by a GPU
// reduction (seed 003 §4.2, §5.4), one workgroup striding over the whole image, and the
// exposure the tone mappers apply. "Luminance" is lib/luminance.wgsl's tone value: each
// pixel's largest channel unless `by_luminance` (the seed's luminance).
// Only pixels something was drawn on count (depth < 1): an object alone on an empty
// background is exposed for the object, not for the black around it (a deviation from the
// seed, which averages every pixel). A frame with nothing drawn, or nothing lit, gives
// exp(log(delta)) = delta, kept away from 0 by the exposure's clamp.
#include "lib/luminance.wgsl"

struct Params {
    key: f32,
    automatic: u32,
    ev: f32,
    by_luminance: u32,
};

@group(2) @binding(0) var hdr: texture_2d<f32>;
@group(2) @binding(1) var gbuf_depth: texture_2d<f32>;
@group(2) @binding(2) var<storage, read_write> lum: Luminance;
@group(2) @binding(3) var<uniform> params: Params;

const SIZE: u32 = 256u;
const DELTA: f32 = 1e-4;
var<workgroup> sum_log: array<f32, SIZE>;
var<workgroup> max_lum: array<f32, SIZE>;
var<workgroup> covered: array<u32, SIZE>;

@compute @workgroup_size(16, 16, 1)
fn cs_main(@builtin(local_invocation_index) idx: u32) {
    let size = textureDimensions(hdr);
    let count = size.x * size.y;
    var s = 0.0;
    var m = 0.0;
    var n = 0u;
    for (var i = idx; i < count; i += SIZE) {
        let pixel = vec2<u32>(i % size.x, i / size.x);
        if textureLoad(gbuf_depth, pixel, 0).x >= 1.0 {
            continue; // background: nothing drawn here
        }
        var l = tone_value(textureLoad(hdr, pixel, 0).rgb, params.by_luminance != 0u);
        // Inf/NaN from an overflowing f16 target must not poison the average.
        l = select(0.0, l, l >= 0.0 && l < 65504.0);
        s += log(DELTA + l);
        m = max(m, l);
        n += 1u;
    }
    sum_log[idx] = s;
    max_lum[idx] = m;
    covered[idx] = n;
    workgroupBarrier();
    for (var stride = SIZE / 2u; stride > 0u; stride /= 2u) {
        if idx < stride {
            sum_log[idx] += sum_log[idx + stride];
            max_lum[idx] = max(max_lum[idx], max_lum[idx + stride]);
            covered[idx] += covered[idx + stride];
        }
        workgroupBarrier();
    }
    if idx == 0u {
        let average = exp(sum_log[0] / f32(max(covered[0], 1u)));
        lum.log_average = select(DELTA, average, covered[0] > 0u);
        lum.white = max_lum[0];
        lum.covered = f32(covered[0]);
        lum.by_luminance = select(0.0, 1.0, params.by_luminance != 0u);
        lum.adapted = lum.log_average;
        lum.exposure = select(exp2(params.ev), params.key / max(lum.log_average, DELTA), params.automatic != 0u);
    }
}
