// Reflective shadow map (seed 000 §4.2.2, §6.2.2) of one directional (orthographic, fitted to
// the scene) or spot (perspective, cone-fitted) light, or of an emissive mesh (perspective from
// its centre about its normal, 150° across; its light as lib/lighting.wgsl's `light_at` has
// it): per texel the world position (w: 1
// where a surface was drawn, 0 cleared), the normal and the flux — the light arriving per unit
// of the surface's own area (colour × intensity × attenuation × cone × cos θ, θ the light's
// incidence) times its diffuse albedo (the seed's "colour × specular strength"; here glTF base
// colour × (1 - metallic)): the radiosity a gathering pass multiplies by a texel's world area. The light's
// view-projection is the one its shadow map uses. Every surface is drawn (`cull None`): all
// of them block light; the normal is the side facing the light.
#include "lib/frame.wgsl"
#include "lib/lighting.wgsl"
#include "lib/material.wgsl"

struct Rsm {
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) flux: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VsOut {
    var out = camera_vertex(v);
    out.clip = lights[instance.light].view_proj * vec4<f32>(out.world_pos, 1.0);
    return out;
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) facing: bool) -> Rsm {
    let m = sample_material(in, facing);
    if m.base.a < material.alpha_cutoff {
        discard;
    }
    let ls = light_at(lights[instance.light], in.world_pos);
    var out: Rsm;
    out.position = vec4<f32>(in.world_pos, 1.0);
    out.normal = vec4<f32>(m.n, 0.0);
    // The lit back of a single-sided surface blocks the light but reflects none of it
    // where it can be seen (it is seen from its front only).
    let reflected = select(1.0, 0.0, m.hidden);
    let incidence = max(dot(m.n, ls.to_light), 0.0);
    out.flux = vec4<f32>(ls.radiance * incidence * m.base.rgb * (1.0 - m.metallic) * reflected, 0.0);
    return out;
}
