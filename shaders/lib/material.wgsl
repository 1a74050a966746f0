// Scene meshes seen by the camera, and their materials evaluated at a fragment: what the
// G-buffer and forward (transparent) passes share. Needs lib/frame.wgsl included first.
#include "lib/mesh.wgsl"
#include "lib/math.wgsl"

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) tangent: vec4<f32>,
    @location(4) uv1: vec2<f32>,
};

// A scene vertex in the camera's clip space, with what the fragment stage needs.
fn camera_vertex(v: VertexIn) -> VsOut {
    let world = world_position(v);
    var out: VsOut;
    out.clip = frame.view_proj * world;
    out.world_pos = world.xyz;
    out.normal = (mesh.normal_matrix * vec4<f32>(v.normal, 0.0)).xyz;
    out.uv = v.uv;
    out.uv1 = v.uv1;
    out.tangent = vec4<f32>((mesh.model * vec4<f32>(v.tangent.xyz, 0.0)).xyz, v.tangent.w);
    return out;
}

struct MaterialSample {
    // base colour × texture (rgb linear, a: coverage/opacity)
    base: vec4<f32>,
    n: vec3<f32>,
    metallic: f32,
    roughness: f32,
    emissive: vec3<f32>,
    // ambient occlusion to apply (1: none)
    occlusion: f32,
    // the back of a single-sided surface: not seen (callers discard it, see `cut_out`)
    hidden: bool,
};

// Sidedness, one rule (glTF `doubleSided`): the front of a triangle is the side its
// counter-clockwise winding faces, swapped by a mirroring transform (negative determinant,
// glTF §3.7.4). `facing` is the rasterizer's `front_facing`.
fn seen_from_front(facing: bool) -> bool {
    let m = mat3x3<f32>(mesh.model[0].xyz, mesh.model[1].xyz, mesh.model[2].xyz);
    return facing != (determinant(m) < 0.0);
}

// Fragments that draw nothing: cut-outs (alphaMode MASK) and the backs of single-sided
// surfaces.
fn cut_out(m: MaterialSample) -> bool {
    return m.base.a < material.alpha_cutoff || m.hidden;
}

// Every map of the material at this fragment, its normal turned to the side seen (`facing`:
// the `front_facing` builtin). All samples come first: implicit derivatives need uniform
// control flow, so callers may discard (`cut_out`) only afterwards.
fn sample_material(in: VsOut, facing: bool) -> MaterialSample {
    let uv = array<vec2<f32>, 5>(
        material_uv(in.uv, in.uv1, MAP_BASE_COLOR),
        material_uv(in.uv, in.uv1, MAP_METALLIC_ROUGHNESS),
        material_uv(in.uv, in.uv1, MAP_NORMAL),
        material_uv(in.uv, in.uv1, MAP_EMISSIVE),
        material_uv(in.uv, in.uv1, MAP_OCCLUSION),
    );
    var m: MaterialSample;
    m.base = material.base_color * textureSample(base_color_map, material_sampler, uv[MAP_BASE_COLOR]);
    let mr = textureSample(metallic_roughness_map, material_sampler, uv[MAP_METALLIC_ROUGHNESS]);
    let occlusion = textureSample(occlusion_map, material_sampler, uv[MAP_OCCLUSION]).r;
    m.emissive = material.emissive.rgb * textureSample(emissive_map, material_sampler, uv[MAP_EMISSIVE]).rgb;
    let mapped = textureSample(normal_map, material_sampler, uv[MAP_NORMAL]).xyz;
    // Hazard (scenes/hard/zero_normals.ron): zero-length vertex normals. The face normal
    // from the position's screen derivatives stands in: dpdy × dpdx faces the viewer
    // (framebuffer y points down), so the front's normal is it, or its opposite on a back.
    let front = seen_from_front(facing);
    let towards_viewer = safe_normalize(cross(dpdy(in.world_pos), dpdx(in.world_pos)), vec3<f32>(0.0, 1.0, 0.0));
    m.n = safe_normalize(in.normal, select(-towards_viewer, towards_viewer, front));
    if material.has_normal_map != 0u {
        // Tangent-space normal map; a degenerate tangent falls back to the vertex normal.
        let t_len = length(in.tangent.xyz);
        if t_len > 1e-6 {
            let n = m.n;
            let t = normalize(in.tangent.xyz - n * dot(n, in.tangent.xyz) / t_len * t_len);
            let b = cross(n, t) * in.tangent.w;
            let k = mapped * 2.0 - 1.0;
            let bent = normalize(t * k.x * material.normal_scale + b * k.y * material.normal_scale + n * k.z);
            m.n = select(n, bent, all(bent == bent));
        }
    }
    m.roughness = clamp(material.roughness * mr.g, 0.03, 1.0);
    m.metallic = clamp(material.metallic * mr.b, 0.0, 1.0);
    m.occlusion = mix(1.0, occlusion, material.occlusion_strength);
    m.hidden = !front && material.double_sided == 0u;
    // The back of a double-sided surface is lit as its own side: the normal flips.
    m.n = select(-m.n, m.n, front);
    return m;
}
