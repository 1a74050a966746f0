// Indirect specular, RSM fallback (seed 000 §4.3.1, §6.3.1, after Sousa et al.): where the
// screen-space march found nothing (w = 0 in `ssr.color`), the same reflected ray is marched
// through this light's reflective shadow map, which sees what the camera cannot (a wall
// behind the camera, Fig. 6.15). A hit is where the ray passes just behind the surface the
// light sees (within `thickness`, world units); the reflected light is that surface's
// outgoing diffuse radiance, flux / π. As the seed does, it counts only where the receiver
// itself is lit by this light (its (1 - shadow) factor): the receiver faces the light and the
// light's RSM sees it there (the RSM holds both faces of every surface). Per light, added up; the seed's b (fallback only on a G-buffer miss) is the
// w test here. `fallback` off writes nothing.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/rsm.wgsl"
#include "lib/lighting.wgsl"

struct Params {
    step: f32,
    max_steps: u32,
    thickness: f32,
    fallback: u32,
    // lengths (step, thickness) in world units, else in the scene's (lib/frame.wgsl)
    world: u32,
};

// The march step and the thickness, in world units.
fn march_step() -> f32 {
    return params.step * length_unit(params.world);
}

fn thickness() -> f32 {
    return params.thickness * length_unit(params.world);
}

@group(2) @binding(3) var ssr_color: texture_2d<f32>;
@group(2) @binding(4) var rsm_position: texture_2d<f32>;
@group(2) @binding(5) var rsm_flux: texture_2d<f32>;
@group(2) @binding(6) var<uniform> params: Params;

// Does the light reach the receiver at `p` facing `n` (its shadow term from the RSM)? It faces
// the light, and is within `thickness` of the surface the map holds there.
fn lit(l: Light, p: vec3<f32>, n: vec3<f32>) -> bool {
    let seen = rsm_seen(rsm_position, l, p);
    let faces = dot(n, light_at(l, p).to_light) > 0.0;
    return faces && seen.w > 0.0 && length(seen.xyz - p) < thickness();
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(frag.xy);
    if params.fallback == 0u || textureLoad(ssr_color, px, 0).w > 0.0 {
        return vec4<f32>(0.0);
    }
    let s = load_surface(px);
    if !s.covered {
        return vec4<f32>(0.0);
    }
    let l = lights[instance.light];
    let size = vec2<f32>(textureDimensions(rsm_flux, 0));
    if !lit(l, s.world, s.n) {
        return vec4<f32>(0.0);
    }
    let dir = reflect(-s.v, s.n);
    var pos = s.world + s.n * march_step() * 0.5;
    for (var i = 0u; i < params.max_steps; i++) {
        pos += dir * march_step();
        let on = on_texture(l.view_proj, pos);
        if !on.inside {
            continue; // off the map, or behind a spot light
        }
        let t = vec2<i32>(on.uv * size);
        let seen = textureLoad(rsm_position, t, 0);
        if seen.w == 0.0 {
            continue;
        }
        let behind = on.depth > on_texture(l.view_proj, seen.xyz).depth;
        if behind && length(pos - seen.xyz) < thickness() {
            return vec4<f32>(textureLoad(rsm_flux, t, 0).rgb / 3.14159265, 1.0);
        }
    }
    return vec4<f32>(0.0);
}
