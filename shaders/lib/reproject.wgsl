// Temporal reuse (temporal_accumulate.wgsl): where this frame's surface lay in the previous
// frame's buffers, and whether it is the same surface there. Include after lib/frame.wgsl and
// lib/gbuffer.wgsl.

// World position of G-buffer pixel `p` of the previous frame at depth `d`.
fn prev_world(p: vec2<i32>, d: f32) -> vec3<f32> {
    let uv = (vec2<f32>(p) + 0.5) * frame.resolution.zw;
    let w = frame.prev_inv_view_proj * vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, d, 1.0);
    return w.xyz / w.w;
}

// The texel of a buffer of `size` texels that held surface point `world` last frame, or -1
// where none did: the first frame, off the previous view or behind the previous camera, or a
// different surface there (disocclusion: the previous depth at that texel, `prev_depth`,
// reconstructs farther from `world` than `reject` of its distance to the camera).
fn reproject(world: vec3<f32>, size: vec2<f32>, prev_depth: texture_2d<f32>, reject: f32) -> vec2<i32> {
    let none = vec2<i32>(-1);
    if frame.frame_index == 0u {
        return none;
    }
    let on = on_texture(frame.prev_view_proj, world);
    if !on.inside {
        return none;
    }
    let q = clamp(vec2<i32>(on.uv * size), vec2<i32>(0), vec2<i32>(size) - 1);
    let d = textureLoad(prev_depth, q, 0).x;
    let seen = length(world - frame.camera_pos.xyz);
    if d >= 1.0 || length(prev_world(gbuffer_pixel(q, size), d) - world) > reject * seen {
        return none;
    }
    return q;
}
