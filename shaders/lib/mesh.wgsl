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
    metallic: f32,
    roughness: f32,
    normal_scale: f32,
    has_normal_map: u32,
};

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
};

@group(1) @binding(0) var<uniform> mesh: Mesh;
@group(1) @binding(1) var<uniform> material: Material;
@group(1) @binding(2) var base_color_map: texture_2d<f32>;
@group(1) @binding(3) var normal_map: texture_2d<f32>;
@group(1) @binding(4) var metallic_roughness_map: texture_2d<f32>;
@group(1) @binding(5) var emissive_map: texture_2d<f32>;
@group(1) @binding(6) var material_sampler: sampler;

fn world_position(v: VertexIn) -> vec4<f32> {
    return mesh.model * vec4<f32>(v.position, 1.0);
}
