// What every light pass shares (seed 003 §3.2): the surface (from the G-buffer under the
// pixel in deferred passes, else from a mesh fragment: lib/forward.wgsl), the light this
// repetition runs for, its unshadowed radiance and direction.
#include "lib/frame.wgsl"
#include "lib/lighting.wgsl"
#include "lib/shadow.wgsl"
#include "lib/gbuffer.wgsl"

// What arrives at the surface from light `l` (lib/lighting.wgsl: seed 003 eq. 3.5 and cones).
fn sample_light(l: Light, s: Surface) -> LightSample {
    return light_at(l, s.world);
}

// Reflected radiance towards the camera (Blinn-Phong), before shadowing.
fn shade(s: Surface, ls: LightSample) -> vec3<f32> {
    return blinn_phong(s.n, ls.to_light, s.v, s.albedo, s.metallic, s.roughness) * ls.radiance;
}

// The pixel a light pass shades: its surface, the repetition's light and what arrives from it.
struct LitPixel {
    s: Surface,
    l: Light,
    ls: LightSample,
};

fn lit_surface(s: Surface) -> LitPixel {
    var p: LitPixel;
    p.s = s;
    p.l = lights[instance.light];
    p.ls = sample_light(p.l, p.s);
    return p;
}

fn lit_pixel(pos: vec4<f32>) -> LitPixel {
    return lit_surface(load_surface(vec2<i32>(pos.xy)));
}
