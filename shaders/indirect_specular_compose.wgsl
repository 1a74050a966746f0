// Indirect specular light added to the HDR image (seed 000 §4.3.1: IndiSpec = SSR on the
// G-buffer + b · SSR on the RSMs, b = 1 only where the G-buffer march missed): the reflected
// light found by SSR, else by the RSM fallback, times the surface's specular reflectance. Deviation: the seed multiplies by a specular
// strength map; glTF materials give F0 = mix(0.04, albedo, metallic), scaled by
// (1 - roughness)² so that rough surfaces reflect little (no blur of the reflection), and,
// with `max_roughness` below 1, faded out from 3/4 of it to it: one reflected ray is a sharp
// mirror image, which a rough surface's wide lobe would blur away. Off by default: measured
// against the reference, dropping the reflection loses more than its sharpness costs.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"

@group(2) @binding(3) var ssr_color: texture_2d<f32>;
@group(2) @binding(4) var ssr_fallback: texture_2d<f32>;

struct Params {
    max_roughness: f32,
};

@group(2) @binding(5) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(frag.xy);
    let screen = textureLoad(ssr_color, px, 0);
    let r = select(textureLoad(ssr_fallback, px, 0), screen, screen.w > 0.0);
    let s = load_surface(px);
    if !s.covered || r.w <= 0.0 {
        return vec4<f32>(0.0);
    }
    let f0 = mix(vec3<f32>(0.04), s.albedo, s.metallic);
    let cut = 1.0 - smoothstep(0.75 * params.max_roughness, params.max_roughness, s.roughness);
    let fade = select(1.0, cut, params.max_roughness < 1.0);
    let gloss = (1.0 - s.roughness) * (1.0 - s.roughness) * fade;
    return vec4<f32>(r.rgb * f0 * gloss, 0.0);
}
