// The traced emissive triangles as lights, for passes that trace paths (standard binding
// `hit_emitters`, built with the hit data): one is chosen in proportion to its power (area ×
// brightest channel, as the reference weighs them) by searching a uniform number in their
// cumulative probabilities, then a point uniformly on it (next-event estimation);
// `emitter_pdf` gives the density of having drawn the point a bounce ray found, so that the
// two ways of reaching an emitter are weighed by multiple importance sampling. The including
// file includes lib/hit.wgsl and lib/hit_maps.wgsl (a point's emission) — and so
// lib/table.wgsl: `hit_emitters` is a table of texels, texel 0 holding the count, then 4
// texels per emitter (the words of a `HitEmitter`).

struct HitEmitter {
    // Corners (world), as the triangle's are (its front is `hit_triangles`' `ng`).
    p0: vec3<f32>,
    // Probability of being chosen (0 in the one entry that stands for none).
    prob: f32,
    p1: vec3<f32>,
    // Cumulative probability of this emitter and those before it (the last is 1).
    cdf: f32,
    p2: vec3<f32>,
    // Its triangle (an index into the `hit_triangles` table: its front, sidedness and material).
    triangle: u32,
    // Radiance with the emissive map's mean: what its power, and so its choice, is weighed by.
    radiance: vec3<f32>,
    area: f32,
};

@group(0) @binding(7) var hit_emitters: texture_2d_array<u32>;

fn emitter_count() -> u32 {
    return table_texel(hit_emitters, 0u).x;
}

fn emitter_at(index: u32) -> HitEmitter {
    let a = table_texel(hit_emitters, 4u * index + 1u);
    let b = table_texel(hit_emitters, 4u * index + 2u);
    let c = table_texel(hit_emitters, 4u * index + 3u);
    let d = bitcast<vec4<f32>>(table_texel(hit_emitters, 4u * index + 4u));
    return HitEmitter(bitcast<vec3<f32>>(a.xyz), bitcast<f32>(a.w), bitcast<vec3<f32>>(b.xyz), bitcast<f32>(b.w), bitcast<vec3<f32>>(c.xyz), c.w, d.xyz, d.w);
}

// Emitter `index`'s cumulative probability: the one word of its record the search reads.
fn emitter_cdf(index: u32) -> f32 {
    return bitcast<f32>(table_texel(hit_emitters, 4u * index + 2u).w);
}

// A point drawn on an emitter as seen from the point lit: the unit direction towards it,
// its distance, what it emits that way, and the density of having drawn it per unit solid
// angle (0: none drawn — nothing emits, or its back faces the point).
struct EmitterSample {
    l: vec3<f32>,
    dist: f32,
    radiance: vec3<f32>,
    pdf: f32,
};

// Whether anything emits (the last cumulative probability is 1, else the one entry is 0).
fn any_emitter() -> bool {
    return emitter_cdf(emitter_count() - 1u) > 0.0;
}

// The first emitter whose cumulative probability exceeds `u` (binary search).
fn emitter_pick(u: f32) -> u32 {
    var lo = 0u;
    var hi = emitter_count() - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if emitter_cdf(mid) > u {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    return lo;
}

// The cosine at emitter `e` towards a point in direction `-l` from it, if it emits that way
// (else 0): from its front, or from both sides when it is double-sided.
fn emitter_facing(e: HitEmitter, l: vec3<f32>) -> f32 {
    let tri = hit_sides_at(e.triangle);
    let c = -dot(tri.ng, l);
    let facing = select(c, abs(c), tri.double_sided != 0u);
    return select(0.0, facing, facing > 1e-7);
}

// A point on an emitter for the surface point `x`, from three uniform numbers.
fn emitter_sample(x: vec3<f32>, u: vec3<f32>) -> EmitterSample {
    var s: EmitterSample;
    let e = emitter_at(emitter_pick(u.x));
    if e.prob <= 0.0 {
        return s;
    }
    // Uniform on the triangle: the square root warp of two numbers to barycentrics.
    let r = sqrt(u.y);
    let p = e.p0 * (1.0 - r) + e.p1 * (r * (1.0 - u.z)) + e.p2 * (r * u.z);
    let d = p - x;
    s.dist = length(d);
    if !(s.dist > 0.0) {
        return s;
    }
    s.l = d / s.dist;
    let cos_e = emitter_facing(e, s.l);
    if cos_e > 0.0 {
        // Its emission there: the emissive map looked up (lib/hit_maps.wgsl).
        s.radiance = emission_at(e.triangle, vec2<f32>(r * (1.0 - u.z), r * u.z));
        s.pdf = e.prob / e.area * s.dist * s.dist / cos_e;
    }
    return s;
}

// The density per unit solid angle with which `emitter_sample` draws the point of emitter
// `index` that a ray along `dir` met at distance `dist` (0 where it emits nothing that way).
fn emitter_pdf(index: u32, dir: vec3<f32>, dist: f32) -> f32 {
    if index == NO_EMITTER {
        return 0.0;
    }
    let e = emitter_at(index);
    let cos_e = emitter_facing(e, dir);
    return select(0.0, e.prob / e.area * dist * dist / max(cos_e, 1e-30), cos_e > 0.0);
}
