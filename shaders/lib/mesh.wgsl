// Per-draw bindings of `draw: Scene` passes (group 1) and the scene vertex layout.

struct Mesh {
    model: mat4x4<f32>,
    // inverse-transpose of the model matrix (columns 0..2 used)
    normal_matrix: mat4x4<f32>,
};

struct Material {
    base_color: vec4<f32>,
    // rgb: emissive colour (linear); w: unused
    emissive: vec4<f32>,
    // rows of the 2×3 UV transform (KHR_texture_transform: offset · rotation · scale)
    uv_row0: vec4<f32>,
    uv_row1: vec4<f32>,
    metallic: f32,
    roughness: f32,
    normal_scale: f32,
    has_normal_map: u32,
    // alphaMode MASK: fragments with alpha below this are discarded (0 when opaque)
    alpha_cutoff: f32,
    // how much the occlusion map darkens the ambient term (glTF occlusion strength)
    occlusion_strength: f32,
    // bit k: map k (base colour, metallic-roughness, normal, emissive, occlusion) reads uv1
    uv_sets: u32,
    // glTF doubleSided (1): back faces are drawn with the normal flipped; else not seen
    double_sided: u32,
};

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    @location(4) uv1: vec2<f32>,
};

@group(1) @binding(0) var<uniform> mesh: Mesh;
@group(1) @binding(1) var<uniform> material: Material;
@group(1) @binding(2) var base_color_map: texture_2d<f32>;
@group(1) @binding(3) var normal_map: texture_2d<f32>;
@group(1) @binding(4) var metallic_roughness_map: texture_2d<f32>;
@group(1) @binding(5) var emissive_map: texture_2d<f32>;
@group(1) @binding(6) var material_sampler: sampler;
@group(1) @binding(7) var occlusion_map: texture_2d<f32>;

#include "lib/map_slots.wgsl"

// The texture coordinates map `map` samples: its UV set, through the material's transform.
fn material_uv(uv0: vec2<f32>, uv1: vec2<f32>, map: u32) -> vec2<f32> {
    let uv = select(uv0, uv1, (material.uv_sets & (1u << map)) != 0u);
    let p = vec3<f32>(uv, 1.0);
    return vec2<f32>(dot(material.uv_row0.xyz, p), dot(material.uv_row1.xyz, p));
}

fn world_position(v: VertexIn) -> vec4<f32> {
    return mesh.model * vec4<f32>(v.position, 1.0);
}
