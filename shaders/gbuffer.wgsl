// G-buffer pass (seed 000 §4.2.1, seed 003 §3.1): normal + roughness, albedo + metallic,
// emission. World positions are reconstructed from depth (the packed layout of seed 003 §5.2),
// which keeps the targets at 20 bytes per pixel.
#include "lib/frame.wgsl"
#include "lib/mesh.wgsl"

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
};

struct GBuffer {
    @location(0) normal: vec4<f32>,
    @location(1) albedo: vec4<f32>,
    @location(2) emissive: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VsOut {
    let world = world_position(v);
    var out: VsOut;
    out.clip = frame.view_proj * world;
    out.world_pos = world.xyz;
    out.normal = (mesh.normal_matrix * vec4<f32>(v.normal, 0.0)).xyz;
    out.uv = v.uv;
    out.tangent = vec4<f32>((mesh.model * vec4<f32>(v.tangent.xyz, 0.0)).xyz, v.tangent.w);
    return out;
}

@fragment
fn fs_main(in: VsOut) -> GBuffer {
    let uv = material_uv(in.uv);
    let base = material.base_color * textureSample(base_color_map, material_sampler, uv);
    let mr = textureSample(metallic_roughness_map, material_sampler, uv);
    // Sampled before the discard: implicit derivatives need uniform control flow.
    let occlusion = textureSample(occlusion_map, material_sampler, uv).r;
    let emissive = material.emissive.rgb * textureSample(emissive_map, material_sampler, uv).rgb;
    let mapped_normal = textureSample(normal_map, material_sampler, uv).xyz;
    if base.a < material.alpha_cutoff {
        discard; // alphaMode MASK: a cut-out
    }
    var n = normalize(in.normal);
    if material.has_normal_map != 0u {
        // Tangent-space normal map; a degenerate tangent falls back to the vertex normal.
        let t_len = length(in.tangent.xyz);
        if t_len > 1e-6 {
            let t = normalize(in.tangent.xyz - n * dot(n, in.tangent.xyz) / t_len * t_len);
            let b = cross(n, t) * in.tangent.w;
            let m = mapped_normal * 2.0 - 1.0;
            let mapped = normalize(t * m.x * material.normal_scale + b * m.y * material.normal_scale + n * m.z);
            n = select(n, mapped, all(mapped == mapped));
        }
    }
    var out: GBuffer;
    out.normal = vec4<f32>(n, clamp(material.roughness * mr.g, 0.03, 1.0));
    out.albedo = vec4<f32>(base.rgb, clamp(material.metallic * mr.b, 0.0, 1.0));
    // Alpha carries ambient occlusion (1: none), which the ambient pass applies.
    out.emissive = vec4<f32>(emissive, mix(1.0, occlusion, material.occlusion_strength));
    return out;
}
