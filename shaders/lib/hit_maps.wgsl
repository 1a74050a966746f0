// A material's maps looked up where a ray met it, as the reference looks them up (level 0,
// bilinear, the material's wrap modes, sRGB colour decoded per texel): standard bindings
// `hit_corners` (per traced triangle its corners' texture coordinates) and `hit_maps` (the
// scene's maps: the count, an entry per map, then RGBA8 texels), both tables of
// lib/table.wgsl. Alpha-masked surfaces are cut out where their alpha is below
// the cutoff, blended ones where it is below a coin tossed per ray and triangle (stochastic
// transparency, as the reference's), for camera, bounce and shadow rays alike; normal maps
// bend the shading normal. The including file sets `ray_coin` before each ray that may meet
// blended surfaces and is to see them stochastically (shadow rays take their mean instead:
// lib/ray.wgsl's `transmittance`).
#include "lib/hit.wgsl"
#include "lib/sampling.wgsl"
#include "lib/map_slots.wgsl"

struct HitCorners {
    // Per corner: (u, v) of TEXCOORD_0, then of TEXCOORD_1.
    uv: array<vec4<f32>, 3>,
    // Per corner: the tangent (world), w the bitangent's sign.
    tangent: array<vec4<f32>, 3>,
};

// What the coins of the next ray's blended surfaces are drawn from.
var<private> ray_coin: u32;

@group(0) @binding(8) var hit_corners: texture_2d_array<u32>;
@group(0) @binding(9) var hit_maps: texture_2d_array<u32>;

const NO_MAP: u32 = 0xffffffffu;

// Traced triangle `index`'s corners.
fn hit_corners_at(index: u32) -> HitCorners {
    var c: HitCorners;
    for (var k = 0u; k < 3u; k++) {
        c.uv[k] = bitcast<vec4<f32>>(table_texel(hit_corners, 6u * index + k));
        c.tangent[k] = bitcast<vec4<f32>>(table_texel(hit_corners, 6u * index + 3u + k));
    }
    return c;
}

// Map `map`'s entry in the `hit_maps` table: its first texel's word, width, height and row
// pitch in words (| 1 << 31 where it is sRGB colour). Texel 0 holds the count of maps.
fn map_entry(map: u32) -> vec4<u32> {
    return table_texel(hit_maps, 1u + map);
}

// Word `i` of the `hit_maps` table: one RGBA8 texel of a map.
fn map_word(i: u32) -> u32 {
    return table_texel(hit_maps, i / 4u)[i % 4u];
}

fn srgb_decode(c: f32) -> f32 {
    return select(pow((c + 0.055) / 1.055, 2.4), c / 12.92, c <= 0.04045);
}

// Texel index `i` of `n` along an axis by wrap mode `mode` (0 repeat, 1 clamp, 2 mirror).
fn wrap_texel(i: i32, n: i32, mode: u32) -> i32 {
    if mode == 1u {
        return clamp(i, 0, n - 1);
    }
    if mode == 2u {
        let m = ((i % (2 * n)) + 2 * n) % (2 * n);
        return select(2 * n - 1 - m, m, m < n);
    }
    return ((i % n) + n) % n;
}

// Map `map`'s texel (x, y), wrapped, decoded to linear where it is sRGB colour.
fn map_texel(map: u32, x: i32, y: i32, wrap: u32) -> vec4<f32> {
    let entry = map_entry(map);
    let first = entry.x;
    let size = vec2<i32>(entry.yz);
    let pitch = entry.w & 0x7fffffffu;
    let srgb = (entry.w >> 31u) != 0u;
    let xi = u32(wrap_texel(x, size.x, wrap & 3u));
    let yi = u32(wrap_texel(y, size.y, (wrap >> 2u) & 3u));
    let v = unpack4x8unorm(map_word(first + yi * pitch + xi));
    if srgb {
        return vec4<f32>(srgb_decode(v.r), srgb_decode(v.g), srgb_decode(v.b), v.a);
    }
    return v;
}

// Bilinear lookup of map `map` at `uv` (1 where there is no map).
fn sample_map(map: u32, uv: vec2<f32>, wrap: u32) -> vec4<f32> {
    if map == NO_MAP || map >= table_texel(hit_maps, 0u).x {
        return vec4<f32>(1.0);
    }
    let size = vec2<f32>(map_entry(map).yz);
    let p = uv * size - 0.5;
    let p0 = floor(p);
    let f = p - p0;
    let i = vec2<i32>(p0);
    let top = mix(map_texel(map, i.x, i.y, wrap), map_texel(map, i.x + 1, i.y, wrap), f.x);
    let bottom = mix(map_texel(map, i.x, i.y + 1, wrap), map_texel(map, i.x + 1, i.y + 1, wrap), f.x);
    return mix(top, bottom, f.y);
}

// Map `k` of material `m`'s texture coordinates at barycentrics `b` of triangle `index`,
// through the material's UV transform.
fn map_uv(m: HitMaterial, index: u32, b: vec2<f32>, k: u32) -> vec2<f32> {
    let c = hit_corners_at(index);
    let w = vec3<f32>(1.0 - b.x - b.y, b.x, b.y);
    let second = ((m.uv_sets >> k) & 1u) != 0u;
    let uv4 = c.uv[0] * w.x + c.uv[1] * w.y + c.uv[2] * w.z;
    let uv = select(uv4.xy, uv4.zw, second);
    return vec2<f32>(dot(m.uv_row0.xyz, vec3<f32>(uv, 1.0)), dot(m.uv_row1.xyz, vec3<f32>(uv, 1.0)));
}

fn material_map(m: HitMaterial, index: u32, b: vec2<f32>, k: u32) -> vec4<f32> {
    if m.maps[k] == NO_MAP {
        return vec4<f32>(1.0);
    }
    return sample_map(m.maps[k], map_uv(m, index, b, k), m.wrap);
}

// The tangent-space normal map's texel applied to unit normal `n` (the reference's
// `normal_mapped`): tangent made orthogonal to n, bitangent n × t times the tangent's sign.
fn normal_mapped(n: vec3<f32>, tangent: vec4<f32>, texel: vec3<f32>, scale: f32) -> vec3<f32> {
    if length(tangent.xyz) <= 1e-6 {
        return n;
    }
    let t = safe_normalize(tangent.xyz - n * dot(n, tangent.xyz), vec3<f32>(0.0));
    let b = cross(n, t) * tangent.w;
    let k = texel * 2.0 - 1.0;
    return safe_normalize(t * k.x * scale + b * k.y * scale + n * k.z, n);
}

// The shading normal at a hit along `dir` with the material's normal map applied, turned as
// lib/hit.wgsl's `ray_hit` turns it.
fn mapped_normal(h: RayHit, m: HitMaterial, dir: vec3<f32>) -> vec3<f32> {
    let tri = hit_triangle_at(h.triangle);
    let w = vec3<f32>(1.0 - h.bary.x - h.bary.y, h.bary.x, h.bary.y);
    let c = hit_corners_at(h.triangle);
    let tangent = c.tangent[0] * w.x + c.tangent[1] * w.y + c.tangent[2] * w.z;
    let texel = material_map(m, h.triangle, h.bary, MAP_NORMAL).xyz;
    let n = normal_mapped(safe_normalize(tri.n0 * w.x + tri.n1 * w.y + tri.n2 * w.z, tri.ng), tangent, texel, m.normal_scale);
    return select(select(n, -n, dot(n, dir) > 0.0), select(n, -n, dot(n, tri.ng) < 0.0), h.front);
}

// The hit's material where a ray along `dir` met it: albedo, metallic, roughness and emission
// from the factors times the maps (lib/material.wgsl's definitions) in place of the maps'
// means, and the normal map applied.
fn look_up_maps(h: ptr<function, RayHit>, dir: vec3<f32>) {
    let m = hit_material_at((*h).triangle);
    if m.maps[MAP_NORMAL] != NO_MAP {
        (*h).n = mapped_normal(*h, m, dir);
    }
    let base = m.base_factor * material_map(m, (*h).triangle, (*h).bary, MAP_BASE_COLOR);
    let mr = material_map(m, (*h).triangle, (*h).bary, MAP_METALLIC_ROUGHNESS);
    (*h).albedo = base.rgb;
    (*h).metallic = clamp(m.metallic_factor * mr.z, 0.0, 1.0);
    (*h).roughness = clamp(m.roughness_factor * mr.y, 0.03, 1.0);
    let emits = (*h).front || hit_sides_at((*h).triangle).double_sided != 0u;
    let e = m.emissive_factor * material_map(m, (*h).triangle, (*h).bary, MAP_EMISSIVE).rgb;
    (*h).emissive = select(vec3<f32>(0.0), e, emits);
}

// What emitter triangle `index` emits at barycentrics `b` (its map looked up).
fn emission_at(index: u32, b: vec2<f32>) -> vec3<f32> {
    let m = hit_material_at(index);
    return m.emissive_factor * material_map(m, index, b, MAP_EMISSIVE).rgb;
}

// How much of the light triangle `index` stops at barycentrics `b`: 1 where it is opaque, 0
// or 1 where it is masked (its alpha against the cutoff), its alpha where it is blended.
fn coverage(index: u32, b: vec2<f32>) -> f32 {
    let m = hit_material_at(index);
    if m.cutoff == 0.0 {
        return 1.0;
    }
    let alpha = m.base_factor.a * material_map(m, index, b, MAP_BASE_COLOR).a;
    if m.cutoff < 0.0 {
        return clamp(alpha, 0.0, 1.0);
    }
    return select(0.0, 1.0, alpha >= m.cutoff);
}

// Whether the ray passes triangle `index`, met at distance `t` and barycentrics `b`: a masked
// one where its alpha is below the cutoff, a blended one where its alpha is below a coin of
// this ray's and this triangle's (stochastic transparency: seen with probability alpha).
fn ray_passes(index: u32, b: vec2<f32>, t: f32) -> bool {
    let cover = coverage(index, b);
    if cover >= 1.0 || cover <= 0.0 {
        return cover <= 0.0;
    }
    let coin = f32(pcg_hash(ray_coin ^ pcg_hash(index ^ bitcast<u32>(t))) >> 8u) * (1.0 / 16777216.0);
    return cover < coin;
}

// The nearest surface a camera or bounce ray sees along `dir` between `t_min` and `t_max`,
// masked surfaces cut out, its maps looked up.
fn trace_seen_mapped(origin: vec3<f32>, dir: vec3<f32>, t_min: f32, t_max: f32) -> RayHit {
    var rq: ray_query;
    rayQueryInitialize(&rq, scene_accel, RayDesc(RAY_FLAG_FORCE_NO_OPAQUE, 0xffu, t_min, t_max, origin, dir));
    // The nearest back passed (every candidate nearer than the final hit is offered).
    var back = t_max;
    while rayQueryProceed(&rq) {
        let c = rayQueryGetCandidateIntersection(&rq);
        if c.kind == RAY_QUERY_INTERSECTION_TRIANGLE {
            let index = c.instance_custom_data + c.primitive_index;
            if !ray_passes(index, c.barycentrics, c.t) {
                if seen_along(hit_sides_at(index), dir) {
                    rayQueryConfirmIntersection(&rq);
                } else {
                    back = min(back, c.t);
                }
            }
        }
    }
    var h = ray_hit(rayQueryGetCommittedIntersection(&rq), origin, dir);
    h.shadowed = h.found && back < h.t;
    if h.found {
        look_up_maps(&h, dir);
    }
    return h;
}

// The distance to the nearest surface (cut-outs passed, either side) along `dir` between
// `t_min` and `t_max`, or −1 where there is none. Opaque triangles commit themselves.
fn nearest_occluder(origin: vec3<f32>, dir: vec3<f32>, t_min: f32, t_max: f32) -> f32 {
    var rq: ray_query;
    rayQueryInitialize(&rq, scene_accel, RayDesc(RAY_FLAG_NONE, 0xffu, t_min, t_max, origin, dir));
    while rayQueryProceed(&rq) {
        let c = rayQueryGetCandidateIntersection(&rq);
        if c.kind == RAY_QUERY_INTERSECTION_TRIANGLE && !ray_passes(c.instance_custom_data + c.primitive_index, c.barycentrics, c.t) {
            rayQueryConfirmIntersection(&rq);
        }
    }
    let hit = rayQueryGetCommittedIntersection(&rq);
    return select(-1.0, hit.t, hit.kind != RAY_QUERY_INTERSECTION_NONE);
}
