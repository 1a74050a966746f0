// One point light whose cube shadow was rendered into a 3×2 atlas (instanced variant):
// deferred (`fs_main`) or forward (`fs_forward`), as in light_shadowed.wgsl.
#include "lib/light_pass.wgsl"
#include "lib/forward.wgsl"

struct Params {
    bias: f32,
    pcf: u32,
    normal_offset: f32,
};

@group(2) @binding(3) var shadow_atlas: texture_depth_2d;
@group(2) @binding(4) var shadow_cmp: sampler_comparison;
@group(2) @binding(5) var<uniform> params: Params;

fn lit(p: LitPixel) -> vec3<f32> {
    // Looked up from the surface pushed along its normal (normal offset, against acne).
    let at = p.s.world + p.s.n * params.normal_offset;
    let to_light = safe_normalize(p.l.position.xyz - at, p.ls.to_light);
    return shade(p.s, p.ls) * atlas_shadow(shadow_atlas, shadow_cmp, p.l, at, to_light, params.bias, params.pcf != 0u);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = lit_pixel(pos);
    if !p.s.covered {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(lit(p), 0.0);
}

// Deferred over the fat G-buffer layout.
@fragment
fn fs_fat(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = lit_surface(load_surface_fat(vec2<i32>(pos.xy)));
    if !p.s.covered {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(lit(p), 0.0);
}

@fragment
fn fs_forward(in: VsOut) -> @location(0) vec4<f32> {
    let m = sample_material(in);
    if cut_out(m) {
        discard;
    }
    return vec4<f32>(lit(lit_surface(material_surface(in, m))), 0.0);
}
