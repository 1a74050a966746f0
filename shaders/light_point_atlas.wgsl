// One point light whose cube shadow was rendered into a 3×2 atlas (instanced variant).
#include "lib/frame.wgsl"
#include "lib/lighting.wgsl"
#include "lib/shadow.wgsl"
#include "lib/gbuffer.wgsl"

struct Params {
    bias: f32,
};

@group(2) @binding(3) var shadow_atlas: texture_depth_2d;
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
        let face = cube_face(-to_light);
        let c = l.face_view_proj[face] * vec4<f32>(s.world, 1.0);
        if c.w > 1e-6 {
            let ndc = c.xyz / c.w;
            let tile = vec2<f32>(f32(face % 3u), f32(face / 3u));
            // Stay half a texel inside the tile so filtering never reads the neighbour face.
            let half_texel = 0.5 / vec2<f32>(textureDimensions(shadow_atlas));
            let in_tile = clamp(vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5), half_texel * vec2<f32>(3.0, 2.0), 1.0 - half_texel * vec2<f32>(3.0, 2.0));
            let uv = (tile + in_tile) / vec2<f32>(3.0, 2.0);
            lit = textureSampleCompareLevel(shadow_atlas, shadow_cmp, uv, ndc.z - params.bias);
        }
    }
    return vec4<f32>(radiance * lit, 0.0);
}
