// Dual paraboloid shadow maps (seed 003 §4.4.1, after Brabec et al. 2002): a point light's
// surroundings in two hemispheres, each flattened by the paraboloid projection
// p = v.xy / (1 + v.z) of a unit direction v onto the unit disc. Layer 0 looks along the
// light's `direction` (side 1), layer 1 the other way (side -1). Depth is the distance from
// the light, linear between the shadow near and far planes.

// World -> hemisphere `side` coordinates: x, y across the map, z along the hemisphere's axis.
fn paraboloid_frame(l: Light, side: f32) -> mat3x3<f32> {
    let a = safe_normalize(l.direction.xyz, vec3<f32>(0.0, -1.0, 0.0));
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 0.0, 1.0), abs(a.x) > 0.9);
    let b1 = normalize(cross(a, helper));
    let b2 = cross(a, b1);
    // Rows: transpose of the columns b1, side · b2, side · a.
    return transpose(mat3x3<f32>(b1, b2 * side, a * side));
}

// A direction in hemisphere coordinates -> its point on the map ([-1, 1]², y up). Directions
// behind the hemisphere land far outside the disc.
fn paraboloid_project(v: vec3<f32>) -> vec2<f32> {
    return v.xy / max(1.0 + v.z, 1e-3);
}

// The inverse: the unit direction (hemisphere coordinates) seen at map point p.
fn paraboloid_direction(p: vec2<f32>) -> vec3<f32> {
    let q = dot(p, p);
    return vec3<f32>(2.0 * p, 1.0 - q) / (1.0 + q);
}

fn paraboloid_depth(dist: f32, l: Light) -> f32 {
    return (dist - l.cone.z) / max(l.cone.w - l.cone.z, 1e-6);
}

// World width of one paraboloid texel (`size` across the disc) at distance `dist`: the
// projection's widest, at the hemisphere's axis (the map spans 2 units over 90°).
fn paraboloid_texel(dist: f32, size: f32) -> f32 {
    return 4.0 * dist / size;
}

// Shadow of a point light from its two paraboloid maps (layer per hemisphere): `d` runs from
// the light to the receiver's lookup point; with `pcf`, 3×3 lookups one texel apart on the map.
fn paraboloid_shadow(maps: texture_depth_2d_array, cmp: sampler_comparison, l: Light, d: vec3<f32>, pcf: bool) -> f32 {
    if l.casts_shadows == 0u {
        return 1.0;
    }
    let dist = length(d);
    let front = paraboloid_frame(l, 1.0) * d;
    let side = select(-1.0, 1.0, front.z >= 0.0);
    let layer = select(1, 0, front.z >= 0.0);
    let p = paraboloid_project(paraboloid_frame(l, side) * d / max(dist, 1e-12));
    let uv = vec2<f32>(0.5 + 0.5 * p.x, 0.5 - 0.5 * p.y);
    let depth = paraboloid_depth(dist, l);
    let texel = 1.0 / vec2<f32>(textureDimensions(maps));
    let taps = select(0, 1, pcf);
    var lit = 0.0;
    for (var y = -taps; y <= taps; y++) {
        for (var x = -taps; x <= taps; x++) {
            lit += textureSampleCompareLevel(maps, cmp, uv + vec2<f32>(f32(x), f32(y)) * texel, layer, depth);
        }
    }
    return lit / f32((2 * taps + 1) * (2 * taps + 1));
}
