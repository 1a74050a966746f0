// Multi-view ambient occlusion (seed 000 §4.3.2, §6.3.2; Vardis et al.): the SSAO test of
// each surface evaluated in several views — the camera's G-buffer (`fs_camera`) and every
// directional or spot light's reflective shadow map (`fs_light`, once per light) — so that
// occluders the camera cannot see still count. Each view adds (weight × accessibility,
// weight) to the views buffer; `mvao_resolve.wgsl` divides. The weight mixes the directional
// weight max(0, n · dir_v) (dir_v towards the view's centre of projection) and the distance
// weight 1 - Σ min(|p - s_i|, r) / (K r) (s_i the surfaces the samples found) with the weight
// bias: (1 - bias) · dir + bias · dist. A view that does not see the surface itself (it lies
// in that light's shadow) gets no weight: its samples would describe another surface.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/ao_kernel.wgsl"
#include "lib/rsm.wgsl"

struct Params {
    radius: f32,
    samples: u32,
    bias: f32,
    falloff: u32,
    weight_bias: f32,
    // lengths (radius, bias) in world units, else in the scene's (lib/frame.wgsl); a view's
    // distances are kept in that unit
    world: u32,
};

@group(2) @binding(5) var<uniform> params: Params;
@group(2) @binding(6) var rsm_position: texture_2d<f32>;

// One view's result: occluded samples (weighted) and the summed distance term.
struct ViewAo {
    occluded: f32,
    distance: f32,
};

fn weighted(v: ViewAo, n: u32, dir_weight: f32) -> vec4<f32> {
    let k = f32(n);
    let dist_weight = 1.0 - v.distance / (k * params.radius);
    let w = (1.0 - params.weight_bias) * dir_weight + params.weight_bias * dist_weight;
    return vec4<f32>(w * (1.0 - v.occluded / k), w, 0.0, 0.0);
}

@fragment
fn fs_camera(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(frag.xy);
    let s = load_surface(target_gbuffer_pixel(frag.xy));
    if !s.covered {
        return vec4<f32>(0.0);
    }
    let tbn = kernel_frame(s.n, px);
    let n = kernel_count(params.samples);
    let unit = length_unit(params.world);
    var v = ViewAo(0.0, 0.0);
    for (var i = 0u; i < n; i++) {
        let p = s.world + kernel_point(tbn, i, n, params.radius * unit);
        let c = camera_sample(p, params.bias * unit);
        let d = length(c.seen - p) / unit;
        // Nothing found counts as far as the radius.
        v.distance += select(params.radius, min(d, params.radius), c.found);
        if c.occluded {
            v.occluded += occluder_weight(params.radius, d, params.falloff != 0u);
        }
    }
    return weighted(v, n, max(0.0, dot(s.n, s.v)));
}

// Distance from the light along its view: depth for a directional light, range for a spot.
fn light_depth(l: Light, p: vec3<f32>) -> f32 {
    if l.kind == LIGHT_DIRECTIONAL {
        return dot(p, safe_normalize(l.direction.xyz, vec3<f32>(0.0, -1.0, 0.0)));
    }
    return length(p - l.position.xyz);
}

@fragment
fn fs_light(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(frag.xy);
    let s = load_surface(target_gbuffer_pixel(frag.xy));
    let l = lights[instance.light];
    let own = rsm_seen(rsm_position, l, s.world);
    let unit = length_unit(params.world);
    // The light must see the surface itself (within the bias and a tenth of the radius).
    if !s.covered || own.w == 0.0 || (light_depth(l, s.world) - light_depth(l, own.xyz)) / unit > params.bias + 0.1 * params.radius {
        return vec4<f32>(0.0);
    }
    let to_view = select(safe_normalize(l.position.xyz - s.world, s.n), -safe_normalize(l.direction.xyz, vec3<f32>(0.0, -1.0, 0.0)), l.kind == LIGHT_DIRECTIONAL);
    let tbn = kernel_frame(s.n, px);
    let n = kernel_count(params.samples);
    var v = ViewAo(0.0, 0.0);
    for (var i = 0u; i < n; i++) {
        let p = s.world + kernel_point(tbn, i, n, params.radius * unit);
        let seen = rsm_seen(rsm_position, l, p);
        if seen.w == 0.0 {
            v.distance += params.radius;
            continue;
        }
        let d = length(seen.xyz - p) / unit;
        v.distance += min(d, params.radius);
        if (light_depth(l, p) - light_depth(l, seen.xyz)) / unit > params.bias {
            v.occluded += occluder_weight(params.radius, d, params.falloff != 0u);
        }
    }
    return weighted(v, n, max(0.0, dot(s.n, to_view)));
}
