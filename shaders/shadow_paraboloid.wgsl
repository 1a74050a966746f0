// Point-light shadow, dual paraboloid (seed 003 §4.4.1): one pass per hemisphere, 2 per light.
//
// The tessellation caveat: the paraboloid projection bends straight lines, but the rasterizer
// joins projected corners with straight edges, so a large triangle's interpolated depth is
// wrong inside it and its true (bent) outline is not what gets rasterized. Here each scene
// triangle is pulled whole from the standard `triangles` table (`draw: Triangles(6)`),
// clipped to the hemisphere (a fan of up to two triangles) and drawn grown around its centre
// by how far its edges bow on the map; each fragment computes its depth exactly — the ray
// from the light through its map point meets the triangle's plane — and fragments whose ray
// misses the triangle are discarded. What remains of the caveat: the bow is estimated (at the
// edge's middle direction, × 1.5), so a huge triangle may still leave slivers where light
// leaks; the growth and the exact depth (no early depth test) cost fragment work.
#include "lib/frame.wgsl"
#include "lib/math.wgsl"
#include "lib/table.wgsl"
#include "lib/paraboloid.wgsl"

struct Params {
    // 1: the front hemisphere (along the light's direction), -1: the back
    side: f32,
};

@group(2) @binding(0) var<uniform> params: Params;
@group(2) @binding(1) var triangles: texture_2d_array<u32>;

struct VsOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) @interpolate(flat) a: vec3<f32>,
    @location(1) @interpolate(flat) b: vec3<f32>,
    @location(2) @interpolate(flat) c: vec3<f32>,
};

// The paraboloid projection is the stereographic one, which maps the great circle an edge
// lies on to a circle: an edge projects to an arc. How far it bows out of its chord is
// estimated at the projected middle direction of the edge.
fn bow(di: vec3<f32>, dj: vec3<f32>, ci: vec2<f32>, cj: vec2<f32>) -> f32 {
    let mid = paraboloid_project(safe_normalize(di + dj, di));
    let chord = cj - ci;
    let len = length(chord);
    return select(0.0, abs(chord.x * (mid.y - ci.y) - chord.y * (mid.x - ci.x)) / len, len > 1e-9);
}

// Distance from `p` to the line through `ci` and `cj`.
fn line_distance(p: vec2<f32>, ci: vec2<f32>, cj: vec2<f32>) -> f32 {
    let chord = cj - ci;
    return abs(chord.x * (p.y - ci.y) - chord.y * (p.x - ci.x)) / max(length(chord), 1e-12);
}

// How much the projected triangle must grow around its centre so that every edge moves out
// past its arc (1.5 × the estimated bow); a triangle whose edges do not bend is drawn as is.
fn growth(dirs: array<vec3<f32>, 3>, corners: array<vec2<f32>, 3>, centre: vec2<f32>) -> f32 {
    var g = 1.0;
    for (var k = 0u; k < 3u; k++) {
        let j = (k + 1u) % 3u;
        let h = line_distance(centre, corners[k], corners[j]);
        g = max(g, 1.0 + 1.5 * bow(dirs[k], dirs[j], corners[k], corners[j]) / max(h, 1e-6));
    }
    return min(g, MAX_GROWTH);
}

// The cap on any growth (a triangle seen almost edge-on has a tiny height on the map).
const MAX_GROWTH: f32 = 16.0;

// The part of a triangle (corners relative to the light, hemisphere coordinates) on the
// hemisphere's side of the plane through the light (z ≥ 0): 0, 3 or 4 corners.
struct Clipped {
    p: array<vec3<f32>, 4>,
    n: u32,
};

fn clip_to_hemisphere(d: array<vec3<f32>, 3>) -> Clipped {
    var c: Clipped;
    c.n = 0u;
    for (var i = 0u; i < 3u; i++) {
        let j = (i + 1u) % 3u;
        let a = d[i];
        let b = d[j];
        if a.z >= 0.0 {
            c.p[c.n] = a;
            c.n += 1u;
        }
        if (a.z >= 0.0) != (b.z >= 0.0) {
            c.p[c.n] = mix(a, b, a.z / (a.z - b.z));
            c.n += 1u;
        }
    }
    return c;
}

// Six vertices per scene triangle: its part on this hemisphere as a fan of up to two
// triangles (the second collapses to a point when the part is a triangle).
@vertex
fn vs_main(@builtin(vertex_index) v: u32, @builtin(instance_index) t: u32) -> VsOut {
    let l = lights[instance.light];
    var out: VsOut;
    out.a = table_corner(triangles, t, 0u);
    out.b = table_corner(triangles, t, 1u);
    out.c = table_corner(triangles, t, 2u);
    let f = paraboloid_frame(l, params.side);
    let part = clip_to_hemisphere(array<vec3<f32>, 3>(f * (out.a - l.position.xyz), f * (out.b - l.position.xyz), f * (out.c - l.position.xyz)));
    let fan = v / 3u;
    if part.n < 3u + fan {
        out.pos = vec4<f32>(2.0, 2.0, 0.5, 1.0);
        return out;
    }
    let ids = array<u32, 3>(0u, 1u + fan, 2u + fan);
    var dirs: array<vec3<f32>, 3>;
    var corners: array<vec2<f32>, 3>;
    for (var k = 0u; k < 3u; k++) {
        dirs[k] = safe_normalize(part.p[ids[k]], vec3<f32>(0.0, 0.0, 1.0));
        corners[k] = paraboloid_project(dirs[k]);
    }
    // Grown around its centre so that the bent outline of the true triangle stays inside (the
    // fragment stage discards what the triangle does not cover).
    let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
    out.pos = vec4<f32>(centre + (corners[v % 3u] - centre) * growth(dirs, corners, centre), 0.5, 1.0);
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @builtin(frag_depth) f32 {
    let l = lights[instance.light];
    let frag = in.pos;
    let p = vec2<f32>(frag.x * instance.target_size.z * 2.0 - 1.0, 1.0 - frag.y * instance.target_size.w * 2.0);
    // Rows of the frame are its axes: its transpose takes map directions back to the world.
    let dir = transpose(paraboloid_frame(l, params.side)) * paraboloid_direction(p);
    let n = cross(in.b - in.a, in.c - in.a);
    let nn = dot(n, n);
    let denom = dot(dir, n);
    // Hazard (scenes/hard): degenerate triangles have no plane.
    if nn < 1e-24 || abs(denom) < 1e-9 * sqrt(nn) {
        discard;
    }
    let t = dot(in.a - l.position.xyz, n) / denom;
    let hit = l.position.xyz + t * dir;
    // Barycentric coordinates (times |n|²), with a little slack so shared edges leave no crack.
    let slack = -1e-3 * nn;
    let inside = dot(cross(in.b - in.a, hit - in.a), n) >= slack && dot(cross(in.c - in.b, hit - in.b), n) >= slack
        && dot(cross(in.a - in.c, hit - in.c), n) >= slack;
    if t <= 0.0 || !inside {
        discard;
    }
    return clamp(paraboloid_depth(t, l), 0.0, 1.0);
}
