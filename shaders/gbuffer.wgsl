// G-buffer pass (seed 000 §4.2.1, seed 003 §3.1, §5.2), in one of two layouts (variant
// `gbuffer` of pipelines/deferred.ron; lib/gbuffer.wgsl reads them):
// - packed (`fs_main`, 24 bytes per pixel with depth): the normal in 2 × 16-bit fixed point
//   and roughness as 16-bit fixed point (Rgba16Uint), albedo + metallic, emission + ambient
//   occlusion; world positions are reconstructed from depth;
// - fat (`fs_fat`, then `fs_fat_position`; 40 bytes per pixel): the world normal as half
//   floats with roughness, the same albedo and emission, and the world position stored as
//   32-bit floats.
#include "lib/frame.wgsl"
#include "lib/material.wgsl"
#include "lib/normal_packing.wgsl"

struct Packed {
    @location(0) normal: vec4<u32>,
    @location(1) albedo: vec4<f32>,
    @location(2) emissive: vec4<f32>,
};

struct Fat {
    @location(0) normal: vec4<f32>,
    @location(1) albedo: vec4<f32>,
    @location(2) emissive: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VsOut {
    return camera_vertex(v);
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) facing: bool) -> Packed {
    let m = sample_material(in, facing);
    if cut_out(m) {
        discard; // alphaMode MASK, or the back of a single-sided surface
    }
    var out: Packed;
    out.normal = pack_normal_roughness(m.n, m.roughness);
    out.albedo = vec4<f32>(m.base.rgb, m.metallic);
    // Alpha carries ambient occlusion (1: none), which the ambient pass applies.
    out.emissive = vec4<f32>(m.emissive, m.occlusion);
    return out;
}

@fragment
fn fs_fat(in: VsOut, @builtin(front_facing) facing: bool) -> Fat {
    let m = sample_material(in, facing);
    if cut_out(m) {
        discard;
    }
    var out: Fat;
    out.normal = vec4<f32>(m.n, m.roughness);
    out.albedo = vec4<f32>(m.base.rgb, m.metallic);
    out.emissive = vec4<f32>(m.emissive, m.occlusion);
    return out;
}

// The fat layout's world positions (w = 1: something was drawn here), in a second pass with
// depth test `Equal` (all the fat targets at once exceed WebGPU's bytes-per-sample limit).
@fragment
fn fs_fat_position(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    if cut_out(sample_material(in, facing)) {
        discard;
    }
    return vec4<f32>(in.world_pos, 1.0);
}
