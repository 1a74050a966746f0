// Log-average luminance, step 2 of 2 (see `luminance_tiles.wgsl`): the tiles reduced in one
// workgroup, and the exposure the tone mappers apply: key / log-average when automatic, 2^ev
// when manual. `luminance_adapt.wgsl` is the same with eye adaptation over frames.
#include "lib/luminance_reduce.wgsl"

@compute @workgroup_size(16, 16, 1)
fn cs_main(@builtin(local_invocation_index) idx: u32) {
    let r = reduce_tiles(lum_tiles, idx);
    if idx == 0u {
        lum = luminance_record(r, log_average_of(r), lum.adapted_at, metering());
    }
}
