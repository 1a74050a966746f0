// Log-average luminance, step 2 of 2 (see `luminance_tiles.wgsl`): the tiles reduced in one
// workgroup, and the exposure the tone mappers apply: key / log-average when automatic, 2^ev
// when manual. `luminance_adapt.wgsl` is the same with eye adaptation over frames.
#include "lib/log_average.wgsl"

// The block of `luminance_adapt.wgsl`, which the `adapting` option substitutes for this
// shader in the same pass: the time constants are unused here.
struct Params {
    key: f32,
    automatic: u32,
    ev: f32,
    by_luminance: u32,
    tau_brighter: f32,
    tau_darker: f32,
};

@group(2) @binding(0) var lum_tiles: texture_2d<f32>;
@group(2) @binding(1) var<storage, read_write> lum: Luminance;
@group(2) @binding(2) var<uniform> params: Params;

@compute @workgroup_size(16, 16, 1)
fn cs_main(@builtin(local_invocation_index) idx: u32) {
    let r = reduce_tiles(lum_tiles, idx);
    if idx == 0u {
        let m = Metering(params.key, params.automatic, params.ev, params.by_luminance);
        lum = luminance_record(r, log_average_of(r), lum.adapted_at, m);
    }
}
