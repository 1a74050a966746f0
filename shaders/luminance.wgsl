// Log-average luminance and the brightest luminance (Lwhite) of the HDR buffer by a GPU
// reduction (seed 003 §4.2, §5.4), one workgroup striding over the whole image, and the
// exposure the tone mappers apply. "Luminance" is lib/luminance.wgsl's tone value: each
// pixel's largest channel unless `by_luminance` (the seed's luminance).
// Which pixels count and how (drawn pixels only, a deviation from the seed, which averages
// every pixel) is lib/log_average.wgsl's `metered`; the parallel reduction
// (`luminance_tiles.wgsl`, `luminance_reduce.wgsl`) shares it.
#include "lib/log_average.wgsl"

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

@compute @workgroup_size(16, 16, 1)
fn cs_main(@builtin(local_invocation_index) idx: u32) {
    let size = textureDimensions(hdr);
    let count = size.x * size.y;
    var s = 0.0;
    var m = 0.0;
    var n = 0u;
    for (var i = idx; i < count; i += GROUP) {
        let p = metered(hdr, gbuf_depth, vec2<u32>(i % size.x, i / size.x), params.by_luminance != 0u);
        s += p.x;
        m = max(m, p.y);
        n += u32(p.z);
    }
    let r = reduce_group(idx, s, m, n);
    if idx == 0u {
        let m = Metering(params.key, params.automatic, params.ev, params.by_luminance);
        lum = luminance_record(r, log_average_of(r), lum.adapted_at, m);
    }
}
