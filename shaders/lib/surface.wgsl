// The surface a light shades: read from the G-buffer (lib/gbuffer.wgsl) in deferred passes,
// from the mesh's material (lib/forward.wgsl) in forward passes.

struct Surface {
    world: vec3<f32>,
    n: vec3<f32>,
    // direction to the camera
    v: vec3<f32>,
    albedo: vec3<f32>,
    metallic: f32,
    roughness: f32,
    // false for background pixels (nothing was drawn there)
    covered: bool,
};
