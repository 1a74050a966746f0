// Log-average luminance with eye adaptation (variant `luminance = adapting`): step 2 of the
// parallel reduction (`luminance_reduce.wgsl`), then the luminance the exposure follows moves
// towards the measured one over time, exponentially with time constant `exposure.tau_brighter`
// when the scene gets brighter and `exposure.tau_darker` when it gets darker (seconds; eyes
// adapt to light faster than to dark): adapted += (measured − adapted)(1 − e^(−Δt/τ)). The
// first frame (or a τ of 0) takes the measured value. Reads `frame.time`, so the pass runs
// every frame.
#include "lib/frame.wgsl"
#include "lib/luminance_reduce.wgsl"

@compute @workgroup_size(16, 16, 1)
fn cs_main(@builtin(local_invocation_index) idx: u32) {
    let r = reduce_tiles(lum_tiles, idx);
    if idx == 0u {
        let measured = log_average_of(r);
        let previous = lum.adapted;
        let tau = select(params.tau_darker, params.tau_brighter, measured > previous);
        let dt = max(frame.time - lum.adapted_at, 0.0);
        let step = 1.0 - exp(-dt / max(tau, 1e-6));
        let fresh = !(previous > 0.0) || tau <= 0.0;
        let adapted = select(previous + (measured - previous) * step, measured, fresh);
        lum = luminance_record(r, adapted, frame.time, metering());
    }
}
