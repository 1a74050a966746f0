// The packed G-buffer normal (seed 003 §3.1, eq. 3.1–3.3, after Kircher and Lawrance): the
// view-space unit normal n as the x and y of n' = (n + (0,0,1)) / |n + (0,0,1)|, each in 16-bit
// fixed point (snorm16: uniform precision over [-1, 1], where half floats would not be).
// Needs lib/frame.wgsl included first.

// World-space unit normal -> n'.xy.
fn encode_normal(n_world: vec3<f32>) -> vec2<f32> {
    let n = normalize((frame.view * vec4<f32>(n_world, 0.0)).xyz);
    let s = n + vec3<f32>(0.0, 0.0, 1.0);
    // n = (0, 0, -1) faces straight away from the camera, where eq. 3.1 divides by zero: (1, 0)
    // decodes to it exactly.
    if dot(s, s) < 1e-12 {
        return vec2<f32>(1.0, 0.0);
    }
    return normalize(s).xy;
}

// n'.xy -> world-space unit normal (eq. 3.2–3.3); finite and unit length for any input.
fn decode_normal(e: vec2<f32>) -> vec3<f32> {
    let z = sqrt(max(1.0 - dot(e, e), 0.0));
    let n = vec3<f32>(2.0 * z * e, 2.0 * z * z - 1.0);
    // The view matrix is a rotation and a translation: its transpose rotates back.
    let r = mat3x3<f32>(frame.view[0].xyz, frame.view[1].xyz, frame.view[2].xyz);
    return normalize(transpose(r) * n);
}

// The G-buffer texel (Rgba16Uint): n'.x, n'.y as snorm16, roughness as unorm16.
fn pack_normal_roughness(n_world: vec3<f32>, roughness: f32) -> vec4<u32> {
    let e = pack2x16snorm(encode_normal(n_world));
    let r = pack2x16unorm(vec2<f32>(roughness, 0.0));
    return vec4<u32>(e & 0xffffu, e >> 16u, r & 0xffffu, 0u);
}

struct NormalRoughness {
    n: vec3<f32>,
    roughness: f32,
};

fn unpack_normal_roughness(t: vec4<u32>) -> NormalRoughness {
    var out: NormalRoughness;
    out.n = decode_normal(unpack2x16snorm((t.x & 0xffffu) | (t.y << 16u)));
    out.roughness = unpack2x16unorm(t.z & 0xffffu).x;
    return out;
}
