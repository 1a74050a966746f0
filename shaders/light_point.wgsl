// One point light with its cube shadow map (classic or multiview variants), added to HDR.
#include "lib/frame.wgsl"
#include "lib/lighting.wgsl"
#include "lib/shadow.wgsl"
#include "lib/gbuffer.wgsl"

struct Params {
    bias: f32,
};

@group(2) @binding(3) var shadow_cube: texture_depth_cube;
@group(2) @binding(4) var shadow_cmp: sampler_comparison;
@group(2) @binding(5) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let s = load_surface(vec2<i32>(pos.xy));
    if !s.covered {
        return vec4<f32>(0.0);
    }
    let l = lights[instance.light];
    var to_light: vec3<f32>;
    var dist: f32;
    let radiance = point_light_radiance(l, s, &to_light, &dist);
    var lit = 1.0;
    if l.casts_shadows != 0u {
        let dir = -to_light * dist;
        let a = abs(dir);
        let major = max(a.x, max(a.y, a.z));
        let depth = cube_face_depth(major, l.cone.z, l.cone.w) - params.bias;
        lit = textureSampleCompareLevel(shadow_cube, shadow_cmp, dir, depth);
    }
    return vec4<f32>(radiance * lit, 0.0);
}
