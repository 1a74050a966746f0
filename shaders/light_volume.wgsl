// Light volumes (seed 003 §3.2.1): the vertex stage of `draw: LightVolume` passes, which
// place the runtime's unit volume (a corner of the standard `light_volumes` buffer) around
// the repetition's light. With `cull Front` and no depth test, each pixel the volume covers
// is shaded once, from the volume's far side, also with the camera inside the volume.
#include "lib/frame.wgsl"

// w of each corner: 0 a sphere around the light (radius 1 per unit of range), 1 a cone
// from the light along +z (z = 1 at the range; radius 1 there per unit of tan(outer angle)),
// 2 clip-space coordinates (directional lights reach every pixel).
@group(1) @binding(0) var<storage, read> light_volumes: array<vec4<f32>>;

// Two unit vectors perpendicular to `axis` and to each other.
fn basis_of(axis: vec3<f32>) -> mat2x3<f32> {
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(axis.x) > 0.9);
    let b1 = normalize(cross(axis, helper));
    return mat2x3<f32>(b1, cross(axis, b1));
}

fn volume_world(l: Light, corner: vec4<f32>) -> vec3<f32> {
    let range = l.position.w;
    if corner.w < 0.5 {
        return l.position.xyz + corner.xyz * range;
    }
    let axis = normalize(l.direction.xyz);
    let b = basis_of(axis);
    // cone.y: cosine of the outer angle (the volume picks the sphere for spots near 90°).
    let c = clamp(l.cone.y, 0.05, 1.0);
    let spread = sqrt(1.0 - c * c) / c;
    return l.position.xyz + range * (corner.z * axis + spread * (corner.x * b[0] + corner.y * b[1]));
}

@vertex
fn vs_volume(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let corner = light_volumes[i];
    if corner.w > 1.5 {
        return vec4<f32>(corner.xy, 0.0, 1.0);
    }
    var clip = frame.view_proj * vec4<f32>(volume_world(lights[instance.light], corner), 1.0);
    // A far side beyond the far plane would be clipped away, and with it the light on every
    // surface in front of it: without a depth test its depth is free to pull in.
    if clip.w > 0.0 {
        clip.z = min(clip.z, clip.w * 0.999999);
    }
    return clip;
}
