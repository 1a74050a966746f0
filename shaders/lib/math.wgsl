// Numerically safe helpers: each guards a hazard `lightbench verify` finds in the hard-case
// scenes (scenes/hard/).

// normalize(v), or `fallback` where v has (nearly) no length: zero-length glTF normals, a
// light exactly on the lit surface, a camera touching a wall. normalize(0) is NaN.
fn safe_normalize(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len2 = dot(v, v);
    return select(fallback, v * inverseSqrt(len2), len2 > 1e-30);
}
