// What step 2 of the log-average luminance reads and writes, for both of its shaders
// (`luminance_reduce.wgsl`, and `luminance_adapt.wgsl`, which the `adapting` option
// substitutes in the same pass and so binds the same block): the tiles of step 1, the record
// the tone mappers read, and the metering parameters (the time constants are adaptation's).
#include "lib/log_average.wgsl"

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

fn metering() -> Metering {
    return Metering(params.key, params.automatic, params.ev, params.by_luminance);
}
