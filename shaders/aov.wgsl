// Ambient occlusion volumes (seed 003 §4.6.4, §5.7; McGuire 2010) without a geometry shader:
// a `draw: Triangles(24)` pass pulls scene triangle `instance_index` from the standard
// `triangles` table (lib/table.wgsl) and emits its volume, a prism of 8 triangles: the triangle grown by
// `radius` within its plane (base) and pushed `radius` along its normal (top). The volume
// covers every point the triangle can occlude within `radius`. When the camera is inside
// (or within the near plane of) a volume, the volume becomes a full-screen triangle instead,
// since every visible point may be occluded. Each fragment reads the G-buffer surface under
// it and the triangle's occlusion there: the form factor of the triangle clipped to the
// surface's hemisphere (Lambert's polygon formula) times the falloff (1 - d / radius)², d the
// distance to the triangle, times `strength` (1: the form factor itself).
// Volumes combine by `blend: Multiply` into an accessibility buffer cleared to 1 (each
// triangle leaves 1 - occlusion), which needs no blur: there is no sampling noise.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/table.wgsl"

const PI: f32 = 3.14159265;

struct Params {
    radius: f32,
    strength: f32,
    // the radius in world units, else in the scene's (lib/frame.wgsl)
    world: u32,
};

// How far a triangle occludes, in world units.
fn radius() -> f32 {
    return params.radius * length_unit(params.world);
}

@group(2) @binding(3) var triangles: texture_2d_array<u32>;
@group(2) @binding(4) var<uniform> params: Params;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) tri: u32,
};

struct Tri {
    a: vec3<f32>,
    b: vec3<f32>,
    c: vec3<f32>,
    n: vec3<f32>,
    // false for a degenerate triangle (no area), which occludes nothing
    ok: bool,
};

fn load_tri(i: u32) -> Tri {
    var t: Tri;
    t.a = table_corner(triangles, i, 0u);
    t.b = table_corner(triangles, i, 1u);
    t.c = table_corner(triangles, i, 2u);
    let cr = cross(t.b - t.a, t.c - t.a);
    t.ok = dot(cr, cr) > 1e-20;
    t.n = safe_normalize(cr, vec3<f32>(0.0, 1.0, 0.0));
    return t;
}

// The outward normal, in the triangle's plane, of its edge from `a` to `b` (counter-clockwise
// seen from the front).
fn edge_out(a: vec3<f32>, b: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return safe_normalize(cross(b - a, n), n);
}

// Corner `k` of the grown triangle: the exact offset of both edges meeting there by `r`
// (capped for slivers, whose corners would fly off).
fn grown(t: Tri, k: u32, r: f32) -> vec3<f32> {
    let v = array<vec3<f32>, 3>(t.a, t.b, t.c);
    let p = v[k];
    let e_in = edge_out(v[(k + 2u) % 3u], p, t.n);
    let e_out = edge_out(p, v[(k + 1u) % 3u], t.n);
    return p + (e_in + e_out) * r / max(1.0 + dot(e_in, e_out), 0.1);
}

// Whether `q` lies in the prism grown by `margin` (the near plane's reach).
fn in_prism(t: Tri, base: array<vec3<f32>, 3>, q: vec3<f32>, margin: f32) -> bool {
    let h = dot(q - t.a, t.n);
    var inside = h > -margin && h < radius() + margin;
    for (var k = 0u; k < 3u; k++) {
        inside = inside && dot(q - base[k], edge_out(base[k], base[(k + 1u) % 3u], t.n)) < margin;
    }
    return inside;
}

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, @builtin(instance_index) ti: u32) -> VsOut {
    var out: VsOut;
    out.tri = ti;
    let t = load_tri(ti);
    let r = radius();
    let base = array<vec3<f32>, 3>(grown(t, 0u, r), grown(t, 1u, r), grown(t, 2u, r));
    // The near plane's distance, from the projection (perspective: proj[3][2] / proj[2][2]).
    let near = abs(frame.proj[3][2] / min(frame.proj[2][2], -1e-6));
    if !t.ok {
        out.clip = vec4<f32>(0.0, 0.0, 2.0, 1.0); // degenerate: outside the depth range
        return out;
    }
    if in_prism(t, base, frame.camera_pos.xyz, 2.0 * near + 1e-4) {
        // One triangle covering clip space (counter-clockwise), the rest degenerate.
        let corners = array<vec2<f32>, 3>(vec2<f32>(-1.0, -1.0), vec2<f32>(3.0, -1.0), vec2<f32>(-1.0, 3.0));
        out.clip = select(vec4<f32>(0.0, 0.0, 2.0, 1.0), vec4<f32>(corners[min(vi, 2u)], 0.5, 1.0), vi < 3u);
        return out;
    }
    // Corners 0..2 the base, 3..5 the top; 8 outward-facing triangles.
    let index = array<u32, 24>(
        3u, 4u, 5u, 0u, 2u, 1u,
        0u, 1u, 4u, 0u, 4u, 3u,
        1u, 2u, 5u, 1u, 5u, 4u,
        2u, 0u, 3u, 2u, 3u, 5u,
    );
    let k = index[min(vi, 23u)];
    let p = base[k % 3u] + t.n * r * f32(k / 3u);
    out.clip = frame.view_proj * vec4<f32>(p, 1.0);
    return out;
}

// Lambert's form factor of polygon `poly` from a point at the origin with normal `n`; the
// polygon lies in the hemisphere above n.
fn form_factor(poly: Poly, n: vec3<f32>) -> f32 {
    var sum = 0.0;
    for (var i = 0u; i < poly.count; i++) {
        let r0 = safe_normalize(poly.v[i], n);
        let r1 = safe_normalize(poly.v[(i + 1u) % poly.count], n);
        let g = cross(r0, r1);
        let len = length(g);
        if len > 1e-7 {
            sum += atan2(len, dot(r0, r1)) * dot(n, g / len);
        }
    }
    return abs(sum) / (2.0 * PI);
}

// A convex polygon of at most 4 corners.
struct Poly {
    v: array<vec3<f32>, 4>,
    count: u32,
};

// The triangle's corners relative to `p`, clipped to the hemisphere above `n` (one
// Sutherland-Hodgman step: 3 corners stay 3, or become 4, 3 or none).
fn clipped(t: Tri, p: vec3<f32>, n: vec3<f32>) -> Poly {
    let v = array<vec3<f32>, 3>(t.a - p, t.b - p, t.c - p);
    var out: Poly;
    out.count = 0u;
    for (var i = 0u; i < 3u; i++) {
        let a = v[i];
        let b = v[(i + 1u) % 3u];
        let da = dot(a, n);
        let db = dot(b, n);
        if da >= 0.0 && out.count < 4u {
            out.v[out.count] = a;
            out.count++;
        }
        if (da >= 0.0) != (db >= 0.0) && out.count < 4u {
            out.v[out.count] = a + (b - a) * (da / (da - db));
            out.count++;
        }
    }
    return out;
}

// Distance from `p` to the triangle, with its height `h` above the plane: the lateral part
// is how far p lies outside the edges.
fn distance_to(t: Tri, p: vec3<f32>, h: f32) -> f32 {
    let v = array<vec3<f32>, 3>(t.a, t.b, t.c);
    var out2 = 0.0;
    for (var k = 0u; k < 3u; k++) {
        let e = edge_out(v[k], v[(k + 1u) % 3u], t.n);
        out2 += pow(max(dot(p - v[k], e), 0.0), 2.0);
    }
    return sqrt(h * h + out2);
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let s = load_surface(target_gbuffer_pixel(in.clip.xy));
    let t = load_tri(in.tri);
    let h = dot(s.world - t.a, t.n);
    // Points in front of the triangle and within reach. `eps` absorbs depth reconstruction
    // error: a point at a wall's foot may land just behind the wall's plane and must still
    // see it (no bright seam in the corner), while a triangle the surface lies in occludes
    // nothing (from just below, it would cover the whole hemisphere).
    let eps = 1e-3 * max(frame.scene_radius, length(s.world - frame.camera_pos.xyz));
    let coplanar = abs(h) < eps && dot(t.n, s.n) > 0.9;
    if !s.covered || !t.ok || coplanar || h <= -eps || h >= radius() {
        return vec4<f32>(1.0);
    }
    let d = distance_to(t, s.world, max(h, 0.0));
    let falloff = pow(clamp(1.0 - d / radius(), 0.0, 1.0), 2.0);
    let poly = clipped(t, s.world, s.n);
    if poly.count < 3u || falloff <= 0.0 {
        return vec4<f32>(1.0);
    }
    let occlusion = clamp(form_factor(poly, s.n) * falloff * params.strength, 0.0, 1.0);
    return vec4<f32>(1.0 - occlusion);
}
