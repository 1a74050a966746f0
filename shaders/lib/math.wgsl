// Numerically safe helpers: each guards a hazard `lightbench verify` finds in the hard-case
// scenes (scenes/hard/).

// normalize(v), or `fallback` where v has (nearly) no length: zero-length glTF normals, a
// light exactly on the lit surface, a camera touching a wall. normalize(0) is NaN.
fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(v, v);
    return select(fallback, v * inverseSqrt(len2), len2 > 1e-30);
}

// Where world position `p` falls on a texture seen through `view_proj` (the camera's or a
// light's; wgpu: NDC y up, texture v down): its texture coordinates, whether it lies in front
// of the projection (hazard: a point behind a camera or spot light, w ≤ 0, has no place on
// it) and whether it is on the texture.
struct OnTexture {
    uv: vec2<f32>,
    // NDC depth (0 near .. 1 far), comparable with the projection's depth buffer
    depth: f32,
    in_front: bool,
    inside: bool,
};

fn on_texture(view_proj: mat4x4<f32>, p: vec3<f32>) -> OnTexture {
    let clip = view_proj * vec4<f32>(p, 1.0);
    var t: OnTexture;
    t.in_front = clip.w > 1e-6;
    t.uv = clip.xy / max(clip.w, 1e-6) * vec2<f32>(0.5, -0.5) + 0.5;
    t.depth = clip.z / max(clip.w, 1e-6);
    t.inside = t.in_front && all(t.uv >= vec2<f32>(0.0)) && all(t.uv < vec2<f32>(1.0));
    return t;
}

// World width of one texel at `p` of a map `size` texels across seen through `view_proj`
// (orthographic or perspective): the projection's x scale at the point's w (1 for an
// orthographic one). Its square is the area a texel covers across the view direction there.
fn texel_width(view_proj: mat4x4<f32>, p: vec3<f32>, size: f32) -> f32 {
    let w = (view_proj * vec4<f32>(p, 1.0)).w;
    let row0 = vec3<f32>(view_proj[0].x, view_proj[1].x, view_proj[2].x);
    return 2.0 * abs(w) / (size * max(length(row0), 1e-20));
}
