// Shadow-map lookups shared by the light passes.

// Where a receiver at `world` (normal `n`, `to_light` towards the light) is looked up in a
// shadow map, against acne, in shadow-map texels (`texel`: one texel's width in world units
// at the receiver) so that it holds at any scale and under any projection: `bias` texels
// towards the light, and `normal_offset` texels along the normal in proportion to the sine of
// the incidence (nothing where the light falls straight on; the most at grazing light, where
// a texel's footprint spans the most depth).
fn shadow_lookup_point(world: vec3<f32>, n: vec3<f32>, to_light: vec3<f32>, bias: f32, normal_offset: f32, texel: f32) -> vec3<f32> {
    let c = clamp(dot(n, to_light), 0.0, 1.0);
    return world + to_light * (bias * texel) + n * (normal_offset * texel * sqrt(1.0 - c * c));
}

// World width of one texel of a 90° cube face (`size` texels across) at `dir` from the light.
fn cube_texel(dir: vec3<f32>, size: f32) -> f32 {
    let a = abs(dir);
    return 2.0 * max(a.x, max(a.y, a.z)) / size;
}

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

// Shadow of a point light from its cube map: the depth of the point `dir` from the light (the
// receiver's lookup point) on the face it falls on, compared in one lookup — or, with `pcf`,
// in 3×3 lookups one texel apart across that face.
fn cube_shadow(map: texture_depth_cube, cmp: sampler_comparison, l: Light, dir: vec3<f32>, pcf: bool) -> f32 {
    if l.casts_shadows == 0u {
        return 1.0;
    }
    let a = abs(dir);
    let major = max(a.x, max(a.y, a.z));
    let depth = cube_face_depth(major, l.cone.z, l.cone.w);
    if !pcf {
        return textureSampleCompareLevel(map, cmp, dir, depth);
    }
    // Two axes across the face the direction falls on, one texel (2 · major / size) long.
    let axis = select(select(vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0, 1.0, 0.0), a.y >= a.z && a.y >= a.x), vec3<f32>(1.0, 0.0, 0.0), a.x >= a.y && a.x >= a.z);
    let u = normalize(cross(axis, select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), axis.y > 0.5)));
    let v = cross(axis, u);
    let step = 2.0 * major / f32(textureDimensions(map).x);
    var lit = 0.0;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            lit += textureSampleCompareLevel(map, cmp, dir + (u * f32(x) + v * f32(y)) * step, depth);
        }
    }
    return lit / 9.0;
}

// Shadow of a point light whose cube faces were rendered into a 3×2 atlas (one instanced
// pass): project with the face's matrix, then look up inside that face's tile (with `pcf`,
// 3×3 lookups, each kept inside the tile).
fn atlas_shadow(atlas: texture_depth_2d, cmp: sampler_comparison, l: Light, world: vec3<f32>, to_light: vec3<f32>, pcf: bool) -> f32 {
    if l.casts_shadows == 0u {
        return 1.0;
    }
    let face = cube_face(-to_light);
    let c = l.face_view_proj[face] * vec4<f32>(world, 1.0);
    if c.w <= 1e-6 {
        return 1.0;
    }
    let ndc = c.xyz / c.w;
    let tile = vec2<f32>(f32(face % 3u), f32(face / 3u));
    // Stay half a texel inside the tile so filtering never reads the neighbour face.
    let half_texel = 0.5 / vec2<f32>(textureDimensions(atlas));
    let lo = half_texel * vec2<f32>(3.0, 2.0);
    let at = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    let taps = select(0, 1, pcf);
    var lit = 0.0;
    for (var y = -taps; y <= taps; y++) {
        for (var x = -taps; x <= taps; x++) {
            let in_tile = clamp(at + vec2<f32>(f32(x), f32(y)) * lo * 2.0, lo, 1.0 - lo);
            lit += textureSampleCompareLevel(atlas, cmp, (tile + in_tile) / vec2<f32>(3.0, 2.0), ndc.z);
        }
    }
    return lit / f32((2 * taps + 1) * (2 * taps + 1));
}

// Shadow of a directional (orthographic) or spot (perspective) light from its 2D map at the
// receiver's lookup point `world`.
fn map_shadow(map: texture_depth_2d, cmp: sampler_comparison, l: Light, world: vec3<f32>, pcf: bool) -> f32 {
    if l.casts_shadows == 0u {
        return 1.0;
    }
    let c = l.view_proj * vec4<f32>(world, 1.0);
    if c.w <= 1e-6 {
        return 1.0; // behind a spot light: lit by nothing, shadowed by nothing
    }
    let ndc = c.xyz / c.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0 {
        return 1.0;
    }
    let depth = ndc.z;
    if pcf {
        return pcf_2d(map, cmp, uv, depth);
    }
    return textureSampleCompareLevel(map, cmp, uv, depth);
}
