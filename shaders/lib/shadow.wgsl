// Shadow-map lookups shared by the light passes.

// 3×3 percentage-closer filtering with a comparison sampler.
fn pcf_2d(map: texture_depth_2d, cmp: sampler_comparison, uv: vec2<f32>, depth: f32) -> f32 {
    let texel = 1.0 / vec2<f32>(textureDimensions(map));
    var lit = 0.0;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            lit += textureSampleCompareLevel(map, cmp, uv + vec2<f32>(f32(x), f32(y)) * texel, depth);
        }
    }
    return lit / 9.0;
}

// Depth a cube face's perspective projection gives a point at distance `d` along the face's
// axis (wgpu depth range 0..1, near n, far f): f/(f-n) * (1 - n/d).
fn cube_face_depth(major_axis_dist: f32, near: f32, far: f32) -> f32 {
    let d = max(major_axis_dist, near);
    return far / (far - near) * (1.0 - near / d);
}

// Index of the cube face a direction falls on: +X, -X, +Y, -Y, +Z, -Z.
fn cube_face(dir: vec3<f32>) -> u32 {
    let a = abs(dir);
    if a.x >= a.y && a.x >= a.z {
        return select(1u, 0u, dir.x >= 0.0);
    }
    if a.y >= a.z {
        return select(3u, 2u, dir.y >= 0.0);
    }
    return select(5u, 4u, dir.z >= 0.0);
}
