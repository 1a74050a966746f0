// The SSAO kernel shared by SSAO and multi-view AO (seed 000 §4.2.3; seed 003 §4.6.3): the
// hemisphere points (a data resource, growing outwards with their index) and the 4×4 tiled
// rotations (a data resource), at group 2 bindings 3 and 4 (after the G-buffer's 0..2, whose
// lib/gbuffer.wgsl is included first).
@group(2) @binding(3) var<storage, read> ssao_kernel: array<vec4<f32>>;
@group(2) @binding(4) var<storage, read> ssao_noise: array<vec2<f32>>;

// Tangent, bitangent and normal around `n`, turned by the rotation of texel `px`'s tile.
fn kernel_frame(n: vec3<f32>, px: vec2<i32>) -> mat3x3<f32> {
    let r = ssao_noise[u32(px.x % 4 + (px.y % 4) * 4)];
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(n.x) > 0.9);
    let t0 = normalize(cross(helper, n));
    let b0 = cross(n, t0);
    let t = t0 * r.x + b0 * r.y;
    return mat3x3<f32>(t, cross(n, t), n);
}

// How many kernel points `samples` asks for (at least 1, at most the kernel's size).
fn kernel_count(samples: u32) -> u32 {
    return clamp(samples, 1u, arrayLength(&ssao_kernel));
}

// Point `i` of `count`, in the frame, `radius` long at most. Evenly spread over the kernel,
// whose points grow outwards with their index: fewer samples still reach the whole radius.
fn kernel_point(frame_: mat3x3<f32>, i: u32, count: u32, radius: f32) -> vec3<f32> {
    return frame_ * ssao_kernel[i * arrayLength(&ssao_kernel) / count].xyz * radius;
}

// An occluder's weight: the range check smoothstep(0, 1, radius / d), d its distance from the
// sample, times 1 / (1 + d²) with `falloff` (seed 003 eq. 4.6).
fn occluder_weight(radius: f32, d: f32, falloff: bool) -> f32 {
    return smoothstep(0.0, 1.0, radius / max(d, 1e-6)) * select(1.0, 1.0 / (1.0 + d * d), falloff);
}

// What the camera's view says of kernel point `p`: the surface it sees there (`found`:
// false off screen or where nothing was drawn) and whether that surface is nearer than `p`
// by more than `bias`.
struct CameraSample {
    found: bool,
    seen: vec3<f32>,
    occluded: bool,
};

fn camera_sample(p: vec3<f32>, bias: f32) -> CameraSample {
    var out = CameraSample(false, p, false);
    let on = on_texture(frame.view_proj, p);
    if !on.inside {
        return out;
    }
    let q = vec2<i32>(on.uv * frame.resolution.xy);
    let d = textureLoad(gbuf_depth, q, 0).x;
    if d >= 1.0 {
        return out;
    }
    out.found = true;
    out.seen = world_from_depth(q, d);
    out.occluded = length(p - frame.camera_pos.xyz) - length(out.seen - frame.camera_pos.xyz) > bias;
    return out;
}
