// One directional or spot light, added to the HDR buffer (multi-pass deferred lighting,
// seed 003 §3.2), with its shadow map.
#include "lib/frame.wgsl"
#include "lib/lighting.wgsl"
#include "lib/shadow.wgsl"
#include "lib/gbuffer.wgsl"

struct Params {
    bias: f32,
    pcf: u32,
};

@group(2) @binding(3) var shadow_map: texture_depth_2d;
@group(2) @binding(4) var shadow_cmp: sampler_comparison;
@group(2) @binding(5) var<uniform> params: Params;

fn shadow(l: Light, world: vec3<f32>, n: vec3<f32>, to_light: vec3<f32>) -> f32 {
    if l.casts_shadows == 0u {
        return 1.0;
    }
    let c = l.view_proj * vec4<f32>(world, 1.0);
    if c.w <= 1e-6 {
        return 1.0; // behind a spot light: lit by nothing, shadowed by nothing
    }
    let ndc = c.xyz / c.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0 {
        return 1.0;
    }
    // Slope-scaled bias against acne; small enough to avoid peter-panning.
    let slope = sqrt(max(1.0 - pow(dot(n, to_light), 2.0), 0.0)) / max(dot(n, to_light), 0.05);
    let depth = ndc.z - params.bias * (1.0 + min(slope, 8.0));
    if params.pcf != 0u {
        return pcf_2d(shadow_map, shadow_cmp, uv, depth);
    }
    return textureSampleCompareLevel(shadow_map, shadow_cmp, uv, depth);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let s = load_surface(vec2<i32>(pos.xy));
    if !s.covered {
        return vec4<f32>(0.0);
    }
    let l = lights[instance.light];
    var to_light = -normalize(l.direction.xyz);
    var radiance = l.color.rgb;
    if l.kind == LIGHT_SPOT {
        let d = l.position.xyz - s.world;
        let dist = length(d);
        to_light = d / max(dist, 1e-6);
        radiance *= attenuation(dist, l.position.w) * spot_factor(l, -d);
    }
    let lit = blinn_phong(s.n, to_light, s.v, s.albedo, s.metallic, s.roughness) * radiance;
    return vec4<f32>(lit * shadow(l, s.world, s.n, to_light), 0.0);
}
