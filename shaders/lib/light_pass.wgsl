// What every deferred light pass shares (seed 003 §3.2): the G-buffer surface under the
// pixel, the light this repetition runs for, its unshadowed radiance and direction.
#include "lib/frame.wgsl"
#include "lib/lighting.wgsl"
#include "lib/shadow.wgsl"
#include "lib/gbuffer.wgsl"

struct LightSample {
    // light arriving at the surface, before shadowing
    radiance: vec3<f32>,
    // unit vector from the surface to the light
    to_light: vec3<f32>,
    // distance to the light (0 for directional lights)
    dist: f32,
};

// Directional: constant radiance from -direction. Spot and point: windowed inverse-square
// attenuation (seed 003 eq. 3.5); spot lights also fade over their cone.
fn sample_light(l: Light, s: Surface) -> LightSample {
    var ls: LightSample;
    ls.radiance = l.color.rgb;
    ls.to_light = -normalize(l.direction.xyz);
    ls.dist = 0.0;
    if l.kind != LIGHT_DIRECTIONAL {
        let d = l.position.xyz - s.world;
        ls.dist = length(d);
        ls.to_light = d / max(ls.dist, 1e-6);
        ls.radiance *= attenuation(ls.dist, l.position.w);
        if l.kind == LIGHT_SPOT {
            ls.radiance *= spot_factor(l, -d);
        }
    }
    return ls;
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

fn lit_pixel(pos: vec4<f32>) -> LitPixel {
    var p: LitPixel;
    p.s = load_surface(vec2<i32>(pos.xy));
    p.l = lights[instance.light];
    p.ls = sample_light(p.l, p.s);
    return p;
}
