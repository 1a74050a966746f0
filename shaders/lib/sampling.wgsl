// Random numbers and direction sampling for passes that trace rays: numbers depend only on
// (pixel, frame, sample), so the same frame renders the same whatever the pacing.

const SAMPLING_PI: f32 = 3.14159265;

// PCG-style integer hash (Jarzynski and Olano 2020).
fn pcg_hash(x: u32) -> u32 {
    let s = x * 747796405u + 2891336453u;
    let w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (w >> 22u) ^ w;
}

// Two numbers in [0, 1) for sample `k` of pixel `px` in frame `frame_no`.
fn random_pair(px: vec2<u32>, frame_no: u32, k: u32) -> vec2<f32> {
    let a = pcg_hash(px.x ^ pcg_hash(px.y ^ pcg_hash(frame_no ^ pcg_hash(k))));
    let b = pcg_hash(a);
    return vec2<f32>(f32(a >> 8u), f32(b >> 8u)) * (1.0 / 16777216.0);
}

// A direction about unit `n`, drawn with density cos θ / π from `u` (Malley's method).
fn cosine_direction(n: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    // An orthonormal basis about n without a branch on its direction (Duff et al. 2017).
    let sgn = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sgn + n.z);
    let b = n.x * n.y * a;
    let t = vec3<f32>(1.0 + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
    let bt = vec3<f32>(b, sgn + n.y * n.y * a, -n.y);
    let r = sqrt(u.x);
    let phi = 2.0 * SAMPLING_PI * u.y;
    return normalize(t * (r * cos(phi)) + bt * (r * sin(phi)) + n * sqrt(max(1.0 - u.x, 0.0)));
}
