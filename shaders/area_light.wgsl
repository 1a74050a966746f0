// The scene's emissive triangles as area lights (lib/area_light.wgsl: linearly transformed
// cosines over the G-buffer's surfaces), added to HDR. Unshadowed.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/area_light.wgsl"

fn lit(s: Surface) -> vec4<f32> {
    if !s.covered {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(area_lighting(s), 0.0);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return lit(load_surface(vec2<i32>(pos.xy)));
}

@fragment
fn fs_fat(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return lit(load_surface_fat(vec2<i32>(pos.xy)));
}
