// The entry points every light shader has, around the `lit(p: LitPixel) -> vec3<f32>` the
// including file defines (what its light adds, shadowed its way): deferred over the packed
// G-buffer (`fs_main`, full screen or over the light's volume) or the fat one (`fs_fat`), and
// forward (`fs_forward`, multi-pass forward lighting over forward.wgsl's `vs_main`). Also the
// shadow parameters and sampler every light shader reads (group 2, bindings 4 and 5; the
// including file binds its shadow map at 3).
#include "lib/light_pass.wgsl"
#include "lib/forward.wgsl"

// Against acne, in shadow-map texels at the receiver (lib/shadow.wgsl's shadow_lookup_point).
struct Params {
    // receivers are looked up this many texels towards the light
    bias_texels: f32,
    pcf: u32,
    // and this many along their normal, at grazing light
    normal_offset_texels: f32,
};

@group(2) @binding(4) var shadow_cmp: sampler_comparison;
@group(2) @binding(5) var<uniform> params: Params;

// Background pixels (nothing drawn) get no light.
fn lit_covered(p: LitPixel) -> vec4<f32> {
    if !p.s.covered {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(lit(p), 0.0);
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return lit_covered(lit_pixel(pos));
}

@fragment
fn fs_fat(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return lit_covered(lit_surface(load_surface_fat(vec2<i32>(pos.xy))));
}

@fragment
fn fs_forward(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let m = sample_material(in, facing);
    if cut_out(m) {
        discard;
    }
    return vec4<f32>(lit(lit_surface(material_surface(in, m))), 0.0);
}
