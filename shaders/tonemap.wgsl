// Reinhard's global operator with white point (seed 003 §4.2, §5.4):
// L = exposure * Lw,  Ld = L (1 + L / Lwhite²) / (1 + L), applied to the tone value Lw (the
// largest channel, or luminance: lib/luminance.wgsl) and the colour scaled by Ld / Lw, so hue
// is kept. The exposure is key / Lavg (automatic) or 2^ev (manual), from the luminance pass.
#include "lib/luminance.wgsl"

@group(2) @binding(0) var hdr: texture_2d<f32>;
@group(2) @binding(1) var<storage, read> lum: Luminance;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(hdr, vec2<i32>(pos.xy), 0).rgb;
    let lw = tone_value(c, lum.by_luminance > 0.5);
    if !(lw > 0.0) {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    let scale = lum.exposure;
    let white = max(lum.white * scale, 1e-4);
    let l = lw * scale;
    let ld = l * (1.0 + l / (white * white)) / (1.0 + l);
    return vec4<f32>(clamp(c * (ld / lw), vec3<f32>(0.0), vec3<f32>(1.0)), 1.0);
}
