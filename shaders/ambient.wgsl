// Clears the HDR lighting buffer with ambient light and emission; the light passes add to it.
#include "lib/frame.wgsl"

struct Params {
    color: vec3<f32>,
};

@group(2) @binding(0) var gbuf_albedo: texture_2d<f32>;
@group(2) @binding(1) var gbuf_emissive: texture_2d<f32>;
@group(2) @binding(2) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let albedo = textureLoad(gbuf_albedo, p, 0);
    // Alpha of the emission target is the material's ambient occlusion (1 where it has none).
    let emissive = textureLoad(gbuf_emissive, p, 0);
    return vec4<f32>(albedo.rgb * params.color * (1.0 - albedo.a) * emissive.a + emissive.rgb, 1.0);
}
