// Random numbers, sample patterns and direction sampling for passes that trace rays or gather:
// numbers depend only on (pixel, frame, sample), so the same frame renders the same whatever
// the pacing.

const SAMPLING_PI: f32 = 3.14159265;

// PCG-style integer hash (Jarzynski and Olano 2020).
fn pcg_hash(x: u32) -> u32 {
    let s = x * 747796405u + 2891336453u;
    let w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (w >> 22u) ^ w;
}

// 32 random bits for sample `k` of pixel `px` in frame `frame_no`.
fn random_bits(px: vec2<u32>, frame_no: u32, k: u32) -> u32 {
    return pcg_hash(px.x ^ pcg_hash(px.y ^ pcg_hash(frame_no ^ pcg_hash(k))));
}

// Two numbers in [0, 1) for sample `k` of pixel `px` in frame `frame_no`.
fn random_pair(px: vec2<u32>, frame_no: u32, k: u32) -> vec2<f32> {
    let a = random_bits(px, frame_no, k);
    let b = pcg_hash(a);
    return vec2<f32>(f32(a >> 8u), f32(b >> 8u)) * (1.0 / 16777216.0);
}

// Point i of n of a rank-1 (Fibonacci) lattice over the unit square: every point alone in its
// column of n and the points spread evenly in 2D, so a shifted lattice samples an area with
// far less variance than as many random points.
fn lattice(i: u32, n: u32) -> vec2<f32> {
    return vec2<f32>((f32(i) + 0.5) / f32(n), fract(f32(i) * 0.618034));
}

// A shift in [0, 1)² fixed per pixel (the same every frame), for a lattice (modulo 1).
fn pixel_shift(px: vec2<u32>) -> vec2<f32> {
    let h = pcg_hash(px.x ^ pcg_hash(px.y));
    return vec2<f32>(f32(h), f32(pcg_hash(h))) / 4294967296.0;
}

// The direction at polar angle (cos θ, sin θ) and azimuth φ about unit `n`, in an orthonormal
// basis built without a branch on n's direction (Duff et al. 2017).
fn about(n: vec3<f32>, cos_t: f32, sin_t: f32, phi: f32) -> vec3<f32> {
    let sgn = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sgn + n.z);
    let b = n.x * n.y * a;
    let t = vec3<f32>(1.0 + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
    let bt = vec3<f32>(b, sgn + n.y * n.y * a, -n.y);
    return normalize(t * (sin_t * cos(phi)) + bt * (sin_t * sin(phi)) + n * cos_t);
}

// A direction about unit `n`, drawn with density cos θ / π from `u` (Malley's method).
fn cosine_direction(n: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    return about(n, sqrt(max(1.0 - u.x, 0.0)), sqrt(u.x), 2.0 * SAMPLING_PI * u.y);
}

// A unit vector about unit `n` drawn with density (e + 1)/(2π) cosᵉ θ from `u`: the half
// vector of the Blinn-Phong lobe of exponent `e` (lib/lighting.wgsl's shininess).
fn power_lobe(n: vec3<f32>, e: f32, u: vec2<f32>) -> vec3<f32> {
    let cos_t = pow(max(u.x, 1e-30), 1.0 / (e + 1.0));
    let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    return about(n, cos_t, sin_t, 2.0 * SAMPLING_PI * u.y);
}
