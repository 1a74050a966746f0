// Log-average luminance and the brightest luminance (Lwhite) of the HDR buffer by a GPU
// reduction (seed 003 §4.2, §5.4), one workgroup striding over the whole image.
// A black frame gives exp(log(delta)) = delta, kept away from 0 by the tone mapper.
#include "lib/luminance.wgsl"

@group(2) @binding(0) var hdr: texture_2d<f32>;
@group(2) @binding(1) var<storage, read_write> lum: Luminance;

const SIZE: u32 = 256u;
const DELTA: f32 = 1e-4;
var<workgroup> sum_log: array<f32, SIZE>;
var<workgroup> max_lum: array<f32, SIZE>;

@compute @workgroup_size(16, 16, 1)
fn cs_main(@builtin(local_invocation_index) idx: u32) {
    let size = textureDimensions(hdr);
    let count = size.x * size.y;
    var s = 0.0;
    var m = 0.0;
    for (var i = idx; i < count; i += SIZE) {
        var l = luminance(textureLoad(hdr, vec2<u32>(i % size.x, i / size.x), 0).rgb);
        // Inf/NaN from an overflowing f16 target must not poison the average.
        l = select(0.0, l, l >= 0.0 && l < 65504.0);
        s += log(DELTA + l);
        m = max(m, l);
    }
    sum_log[idx] = s;
    max_lum[idx] = m;
    workgroupBarrier();
    for (var stride = SIZE / 2u; stride > 0u; stride /= 2u) {
        if idx < stride {
            sum_log[idx] += sum_log[idx + stride];
            max_lum[idx] = max(max_lum[idx], max_lum[idx + stride]);
        }
        workgroupBarrier();
    }
    if idx == 0u {
        lum.log_average = exp(sum_log[0] / f32(max(count, 1u)));
        lum.white = max_lum[0];
    }
}
