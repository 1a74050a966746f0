// The log-average luminance (seed 003 §4.2, §5.4) written once for its reductions: the
// one-workgroup `luminance.wgsl`, and the parallel `luminance_tiles.wgsl` then
// `luminance_reduce.wgsl` / `luminance_adapt.wgsl`.
#include "lib/luminance.wgsl"

// log(delta + L) keeps a black pixel finite; a frame with nothing drawn or nothing lit
// averages to delta.
const LOG_DELTA: f32 = 1e-4;

// One pixel as the average counts it: (log(delta + L), L, 1) where something was drawn
// (depth < 1: an object alone on an empty background is exposed for itself), zeros where not.
// L is the tone value of lib/luminance.wgsl; Inf/NaN from an overflowing f16 target counts as
// 0 rather than poisoning the average.
fn metered(hdr: texture_2d<f32>, depth: texture_2d<f32>, pixel: vec2<u32>, by_luminance: bool) -> vec3<f32> {
    if textureLoad(depth, pixel, 0).x >= 1.0 {
        return vec3<f32>(0.0);
    }
    var l = tone_value(textureLoad(hdr, pixel, 0).rgb, by_luminance);
    l = select(0.0, l, l >= 0.0 && l < 65504.0);
    return vec3<f32>(log(LOG_DELTA + l), l, 1.0);
}

const GROUP: u32 = 256u;
var<workgroup> group_sum: array<f32, GROUP>;
var<workgroup> group_max: array<f32, GROUP>;
var<workgroup> group_count: array<u32, GROUP>;

// Each of a workgroup's 256 invocations `idx` gives its (sum of logs, brightest, pixels);
// every invocation gets the workgroup's, by a tree reduction (pixels counted exactly, as u32).
fn reduce_group(idx: u32, sum: f32, brightest: f32, pixels: u32) -> vec3<f32> {
    group_sum[idx] = sum;
    group_max[idx] = brightest;
    group_count[idx] = pixels;
    workgroupBarrier();
    for (var stride = GROUP / 2u; stride > 0u; stride /= 2u) {
        if idx < stride {
            group_sum[idx] += group_sum[idx + stride];
            group_max[idx] = max(group_max[idx], group_max[idx + stride]);
            group_count[idx] += group_count[idx + stride];
        }
        workgroupBarrier();
    }
    return vec3<f32>(group_sum[0], group_max[0], f32(group_count[0]));
}

// Step 2 of the parallel reduction: the tiles step 1 wrote (sum of logs, brightest, pixels),
// summed by the workgroup striding over them.
fn reduce_tiles(tiles: texture_2d<f32>, idx: u32) -> vec3<f32> {
    let size = textureDimensions(tiles);
    let count = size.x * size.y;
    var s = 0.0;
    var m = 0.0;
    var n = 0u;
    for (var i = idx; i < count; i += GROUP) {
        let t = textureLoad(tiles, vec2<u32>(i % size.x, i / size.x), 0);
        s += t.x;
        m = max(m, t.y);
        n += u32(t.z);
    }
    return reduce_group(idx, s, m, n);
}

// exp(mean(log(delta + L))) of a reduction, delta where nothing was counted.
fn log_average_of(r: vec3<f32>) -> f32 {
    return select(LOG_DELTA, exp(r.x / max(r.z, 1.0)), r.z > 0.0);
}

// The metering settings each reduction's parameter block starts with.
struct Metering {
    key: f32,
    automatic: u32,
    ev: f32,
    by_luminance: u32,
};

// What a reduction `r` leaves for the tone mappers: the averages, and the exposure for
// `adapted` (the log-average the exposure follows, set at `adapted_at`): key / adapted when
// automatic, 2^ev when manual.
fn luminance_record(r: vec3<f32>, adapted: f32, adapted_at: f32, m: Metering) -> Luminance {
    var out: Luminance;
    out.log_average = log_average_of(r);
    out.white = r.y;
    out.covered = r.z;
    out.by_luminance = select(0.0, 1.0, m.by_luminance != 0u);
    out.adapted = adapted;
    out.adapted_at = adapted_at;
    out.exposure = select(exp2(m.ev), m.key / max(adapted, LOG_DELTA), m.automatic != 0u);
    return out;
}
