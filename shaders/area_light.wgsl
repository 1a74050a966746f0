// The scene's emissive triangles as area lights (lib/area_light.wgsl: linearly transformed
// cosines over the G-buffer's surfaces), added to HDR; unshadowed, or (SHADOWS) shadowed by
// what the depth buffer holds.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/lighting.wgsl"
#include "lib/area_light.wgsl"

// Screen-space shadows (`area_lights = ltc_shadowed`).
override SHADOWS: bool = false;

struct Params {
    shadow_steps: u32,
    residual: u32,
};

@group(2) @binding(4) var<uniform> params: Params;

fn lit(s: Surface) -> vec4<f32> {
    if !s.covered {
        return vec4<f32>(0.0);
    }
    let shadows = ScreenShadows(SHADOWS, params.shadow_steps);
    return vec4<f32>(area_lighting(s, shadows, params.residual), 0.0);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return lit(load_surface(vec2<i32>(pos.xy)));
}

@fragment
fn fs_fat(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return lit(load_surface_fat(vec2<i32>(pos.xy)));
}
