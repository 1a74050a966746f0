// Area lights from emissive surfaces, shaded with linearly transformed cosines (Heitz et al.
// 2016): the scene's emissive triangles (standard binding `area_lights`, filled by the
// runtime) and the integral of a clamped cosine over a polygon, in closed form. The diffuse
// lobe is that cosine; the specular lobe of lib/lighting.wgsl's Blinn-Phong is a cosine carried
// by the inverse transform of pipelines/ltc_blinn_phong.json (fitted by
// `cargo run --release -p lightbench-reference --example ltc_fit`; docs/reference.md), plus
// what that fit leaves out, by quadrature (`Residual`).

struct AreaLight {
    // Corners in world space (w unused), counter-clockwise seen from the emitting side.
    p0: vec4<f32>,
    p1: vec4<f32>,
    p2: vec4<f32>,
    // Emitted radiance (rgb); w: 1 when both sides emit, 0 the front only.
    radiance: vec4<f32>,
};

@group(0) @binding(3) var<storage, read> area_lights: array<AreaLight>;
// The LTC table (a `data` buffer of the pipeline).
@group(2) @binding(3) var<storage, read> ltc: array<vec4<f32>>;

// The table's size and layout (reference/src/ltc.rs): SIZE × SIZE cells of two vec4 —
// M⁻¹'s entries (a, b, c, d) of [a 0 b; 0 c 0; d 0 1], then (magnitude, fit error, 0, 0).
const LTC_SIZE: f32 = 32.0;
const LTC_MIN_ROUGHNESS: f32 = 0.1;

// One edge's share of the integral of cos/π over a polygon on the unit sphere: the arc's
// angle along the edge plane's normal (exact, with atan2 for a well-conditioned angle).
fn ltc_edge(a: vec3<f32>, b: vec3<f32>) -> f32 {
    let c = cross(a, b);
    let s = length(c);
    let theta = atan2(s, dot(a, b));
    return c.z * theta / max(s, 1e-9);
}

// A triangle clipped to the upper hemisphere (z > 0; Sutherland-Hodgman): at most four corners.
struct Clipped {
    p: array<vec3<f32>, 4>,
    n: u32,
};

fn ltc_clip(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> Clipped {
    var p: array<vec3<f32>, 3> = array<vec3<f32>, 3>(a, b, c);
    var out: Clipped;
    out.n = 0u;
    for (var i = 0u; i < 3u; i = i + 1u) {
        let cur = p[i];
        let next = p[(i + 1u) % 3u];
        if cur.z > 0.0 {
            out.p[out.n] = cur;
            out.n = out.n + 1u;
        }
        if (cur.z > 0.0) != (next.z > 0.0) {
            let t = cur.z / (cur.z - next.z);
            out.p[out.n] = mix(cur, next, t);
            out.n = out.n + 1u;
        }
    }
    return out;
}

// The integral of the clamped cosine / π over a clipped triangle on the unit sphere. Signed:
// positive when the triangle is seen clockwise (its front, emitting side, faces the point for
// counter-clockwise corners).
fn ltc_integral(q: Clipped) -> f32 {
    if q.n < 3u {
        return 0.0;
    }
    var p = q.p;
    var sum = 0.0;
    for (var i = 0u; i < q.n; i = i + 1u) {
        sum = sum + ltc_edge(normalize(p[i]), normalize(p[(i + 1u) % q.n]));
    }
    return -sum / 6.2831853;
}

// The integral over triangle (a, b, c) — points relative to the shading point, in a frame
// whose cosine lobe points +z — of the clamped cosine / π, clipped to the upper hemisphere.
fn ltc_triangle(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> f32 {
    return ltc_integral(ltc_clip(a, b, c));
}

// The fitted lobe's residual. A cosine-power lobe is not a transformed cosine (the fit is too
// low at the peak, too high in the tails: docs/reference.md), so the specular integral is the
// fitted lobe's, in closed form, plus the integral of (true lobe − fitted lobe) over the
// polygon by Gauss-Legendre quadrature. The quadrature runs in M⁻¹'s space, where the fitted
// lobe is a plain cosine and the polygon as wide as the lobe is sharp: a few points resolve
// the difference down to roughness ~0.2 (at 0.1, 4 points are short: docs/effects.md).
// `order` points per side per triangle; 0: none.
struct Residual {
    // M (the fitted transform; M⁻¹ carries the polygon to the cosine's space), |det M|.
    m: mat3x3<f32>,
    det_m: f32,
    magnitude: f32,
    // The view direction, in the surface's frame (normal +z), and the surface's roughness.
    v: vec3<f32>,
    roughness: f32,
    order: u32,
};

// Gauss-Legendre rules on [0, 1]: (node, weight) pairs, row n − 1 for n points (n ≤ 5).
const GAUSS_LEGENDRE = array<array<vec2<f32>, 5>, 5>(
    array<vec2<f32>, 5>(vec2(0.5, 1.0), vec2(0.0), vec2(0.0), vec2(0.0), vec2(0.0)),
    array<vec2<f32>, 5>(vec2(0.21132487, 0.5), vec2(0.78867513, 0.5), vec2(0.0), vec2(0.0), vec2(0.0)),
    array<vec2<f32>, 5>(vec2(0.11270167, 0.27777778), vec2(0.5, 0.44444444), vec2(0.88729833, 0.27777778), vec2(0.0), vec2(0.0)),
    array<vec2<f32>, 5>(vec2(0.06943184, 0.17392742), vec2(0.33000948, 0.32607258), vec2(0.66999052, 0.32607258), vec2(0.93056816, 0.17392742), vec2(0.0)),
    array<vec2<f32>, 5>(vec2(0.04691008, 0.11846344), vec2(0.23076534, 0.23931434), vec2(0.5, 0.28444444), vec2(0.76923466, 0.23931434), vec2(0.95308992, 0.11846344)),
);

// The specular lobe × cos θ for a specular colour of 1, normal +z: `blinn_phong()` of a white
// metal (no diffuse lobe, specular colour 1).
fn lobe(l: vec3<f32>, r: Residual) -> f32 {
    return blinn_phong(vec3<f32>(0.0, 0.0, 1.0), l, r.v, vec3<f32>(1.0), 1.0, r.roughness).x;
}

// The angle at corner `a` of the spherical triangle (a, b, c).
fn corner_angle(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> f32 {
    return acos(clamp(dot(normalize(cross(a, b)), normalize(cross(a, c))), -1.0, 1.0));
}

// ∫ (lobe − magnitude · fitted lobe) over the spherical triangle (a, b, c) of the cosine's
// space: points from Arvo's area-preserving map of the unit square (1995), the lobe carried
// back by M with its Jacobian |det M| / |M ω|³.
fn residual_triangle(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, r: Residual) -> f32 {
    // Corners that (nearly) coincide: a sliver of no area (and no well-defined angles).
    if min(min(length(cross(a, b)), length(cross(b, c))), length(cross(c, a))) < 1e-6 {
        return 0.0;
    }
    let alpha = corner_angle(a, b, c);
    let area = alpha + corner_angle(b, c, a) + corner_angle(c, a, b) - 3.14159265;
    if area <= 1e-7 {
        return 0.0;
    }
    let c_perp = safe_normalize(c - dot(c, a) * a, b);
    let cos_a = cos(alpha);
    let sin_a = sin(alpha);
    let cos_ab = dot(a, b);
    var rule = GAUSS_LEGENDRE[r.order - 1u];
    var sum = 0.0;
    for (var i = 0u; i < r.order; i = i + 1u) {
        // The sub-triangle (a, b, ĉ) of area u₁ · area, then a point along b → ĉ by u₂.
        let part = rule[i].x * area - alpha;
        let s = sin(part);
        let t = cos(part);
        let u = t - cos_a;
        let w = s + sin_a * cos_ab;
        let q = clamp(((w * t - u * s) * cos_a - w) / max((w * s + u * t) * sin_a, 1e-12), -1.0, 1.0);
        let c_hat = q * a + sqrt(max(1.0 - q * q, 0.0)) * c_perp;
        let b_perp = safe_normalize(c_hat - dot(c_hat, b) * b, c_hat);
        for (var j = 0u; j < r.order; j = j + 1u) {
            let z = 1.0 - rule[j].x * (1.0 - dot(c_hat, b));
            let o = z * b + sqrt(max(1.0 - z * z, 0.0)) * b_perp;
            let carried = r.m * o;
            let len = length(carried);
            let jacobian = r.det_m / max(len * len * len, 1e-12);
            let f = lobe(carried / len, r) * jacobian - r.magnitude * max(o.z, 0.0) / 3.14159265;
            sum = sum + rule[i].y * rule[j].y * f;
        }
    }
    return sum * area;
}

// The residual over a clipped triangle of the cosine's space (a fan of at most two).
fn ltc_residual(q: Clipped, r: Residual) -> f32 {
    if r.order == 0u || q.n < 3u {
        return 0.0;
    }
    var p = q.p;
    var sum = 0.0;
    for (var k = 1u; k + 1u < q.n; k = k + 1u) {
        sum = sum + residual_triangle(normalize(p[0]), normalize(p[k]), normalize(p[k + 1u]), r);
    }
    return sum;
}

fn ltc_cell(part: u32, i: u32, j: u32) -> vec4<f32> {
    return ltc[(i * u32(LTC_SIZE) + j) * 2u + part];
}

// The table's `part` (0: M⁻¹'s entries, 1: magnitude) at (roughness, cos θ_v), interpolated
// bilinearly.
fn ltc_lookup(part: u32, roughness: f32, cos_v: f32) -> vec4<f32> {
    let last = LTC_SIZE - 1.0;
    let x = clamp((roughness - LTC_MIN_ROUGHNESS) / (1.0 - LTC_MIN_ROUGHNESS), 0.0, 1.0) * last;
    let y = sqrt(clamp(1.0 - cos_v, 0.0, 1.0)) * last;
    let i0 = u32(floor(x));
    let j0 = u32(floor(y));
    let i1 = min(i0 + 1u, u32(last));
    let j1 = min(j0 + 1u, u32(last));
    let f = vec2<f32>(x - f32(i0), y - f32(j0));
    let top = mix(ltc_cell(part, i0, j0), ltc_cell(part, i0, j1), f.y);
    let bottom = mix(ltc_cell(part, i1, j0), ltc_cell(part, i1, j1), f.y);
    return mix(top, bottom, f.x);
}

// Screen-space shadows for area lights: how many of the segments from the surface to points
// on a triangle pass through a surface the camera sees. `on` false: unshadowed (1 for every
// triangle).
struct ScreenShadows {
    on: bool,
    // Steps along each segment.
    steps: u32,
};

// Whether the segment from `a` to `b`, marched in `steps` steps, passes through a surface in
// the depth buffer: from one step on a side of what the camera sees to the next on the other,
// by no more than twice the step (and the tolerance's width) — a larger jump is the segment
// passing behind a silhouette, not through a surface — or from in front of what the camera
// sees to at most three steps behind what it sees at the next: into an object through a face
// seen edge-on (the tall box's side, from the wall beside it), which the depth buffer shows
// as a jump too. A step within 1.5 pixels' width of the surface seen there is on neither
// side: the depth buffer holds one depth per pixel, and a grazing surface's changes fast
// across one. What the camera does not see (off screen, hidden) blocks nothing.
fn crosses_depth_buffer(a: vec3<f32>, b: vec3<f32>, steps: u32) -> bool {
    // Twice the step.
    let reach = 2.0 * distance(a, b) / f32(steps);
    // The side (−1 in front, +1 behind, 0 not known) and depth of the last step off the surface.
    var side = 0.0;
    var behind = 0.0;
    for (var i = 0u; i <= steps; i = i + 1u) {
        let x = mix(a, b, f32(i) / f32(steps));
        let p = probe(x);
        let pixel = distance(x, frame.camera_pos.xyz) * 2.0 / (frame.proj[1][1] * frame.resolution.y);
        if p.miss {
            side = 0.0;
        } else if abs(p.behind) > 1.5 * pixel {
            let through = abs(p.behind - behind) <= reach + 5.0 * pixel;
            let into = side < 0.0 && p.behind < 1.5 * reach;
            if sign(p.behind) * side < 0.0 && (through || into) {
                return true;
            }
            side = sign(p.behind);
            behind = p.behind;
        }
    }
    return false;
}

// The share of triangle `l` that `s` sees: segments to its centre and to three points halfway
// from it to the corners, from just off the surface to just short of the triangle.
fn area_visibility(s: Surface, l: AreaLight, shadows: ScreenShadows) -> f32 {
    if !shadows.on {
        return 1.0;
    }
    let centre = (l.p0.xyz + l.p1.xyz + l.p2.xyz) / 3.0;
    let points = array<vec3<f32>, 4>(centre, mix(centre, l.p0.xyz, 0.5), mix(centre, l.p1.xyz, 0.5), mix(centre, l.p2.xyz, 0.5));
    let steps = max(shadows.steps, 1u);
    var seen = 0.0;
    for (var k = 0u; k < 4u; k = k + 1u) {
        // 1% of the way off both ends: neither the surface nor the light blocks the segment.
        let a = s.world + s.n * 0.01 * distance(s.world, points[k]);
        let b = mix(a, points[k], 0.99);
        seen = seen + select(1.0, 0.0, crosses_depth_buffer(a, b, steps));
    }
    return seen / 4.0;
}

// What the scene's area lights add at surface `s`: per triangle, the clamped cosine's integral
// in the surface's frame (the diffuse lobe) and in the frame M⁻¹ carries the specular lobe to
// (plus the fit's residual by `residual_order` points per side), times its radiance and, with
// `shadows.on`, the share of it `s` sees in screen space.
fn area_lighting(s: Surface, shadows: ScreenShadows, residual_order: u32) -> vec3<f32> {
    let n = s.n;
    let cos_v = clamp(dot(n, s.v), 0.02, 1.0);
    // The surface's frame: x towards the view in the tangent plane, z the normal.
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(n.x) > 0.9);
    let t1 = safe_normalize(s.v - n * dot(s.v, n), normalize(cross(n, helper)));
    let t2 = cross(n, t1);
    let to_local = transpose(mat3x3<f32>(t1, t2, n));
    let m = ltc_lookup(0u, s.roughness, cos_v);
    let inv = mat3x3<f32>(vec3<f32>(m.x, 0.0, m.w), vec3<f32>(0.0, m.z, 0.0), vec3<f32>(m.y, 0.0, 1.0));
    let magnitude = ltc_lookup(1u, s.roughness, cos_v).x;
    // M from M⁻¹ = [a 0 b; 0 c 0; d 0 1]: its x-z block inverted, 1/c on y.
    let k = m.x - m.y * m.w;
    let residual = Residual(
        mat3x3<f32>(vec3<f32>(1.0, 0.0, -m.w) / k, vec3<f32>(0.0, 1.0 / m.z, 0.0), vec3<f32>(-m.y, 0.0, m.x) / k),
        1.0 / abs(k * m.z),
        magnitude,
        to_local * s.v,
        s.roughness,
        min(residual_order, 5u),
    );
    let spec_color = mix(vec3<f32>(0.04), s.albedo, s.metallic);
    let diffuse = s.albedo * (1.0 - s.metallic);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < arrayLength(&area_lights); i = i + 1u) {
        let l = area_lights[i];
        let a = to_local * (l.p0.xyz - s.world);
        let b = to_local * (l.p1.xyz - s.world);
        let c = to_local * (l.p2.xyz - s.world);
        var d = ltc_triangle(a, b, c);
        let carried = ltc_clip(inv * a, inv * b, inv * c);
        var sp = ltc_integral(carried);
        if l.radiance.w > 0.5 {
            d = abs(d);
            sp = abs(sp);
        }
        // The residual where the fitted lobe lights the point: the front of a one-sided light.
        var specular = 0.0;
        if sp > 0.0 {
            specular = max(magnitude * sp + ltc_residual(carried, residual), 0.0);
        }
        let light = l.radiance.rgb * (diffuse * max(d, 0.0) + spec_color * specular);
        if any(light > vec3<f32>(0.0)) {
            sum = sum + light * area_visibility(s, l, shadows);
        }
    }
    return sum;
}
