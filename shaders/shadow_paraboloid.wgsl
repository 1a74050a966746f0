// Point-light shadow, dual paraboloid (seed 003 §4.4.1): one pass per hemisphere, 2 per light.
//
// The tessellation caveat: the paraboloid projection bends straight lines, but the rasterizer
// joins projected corners with straight edges, so a large triangle's interpolated depth is
// wrong inside it and its true (bent) outline is not what gets rasterized. Here each triangle
// is pulled whole from the standard `triangles` buffer (`draw: Triangles(3)`) and drawn grown
// around its centre on the map, the more the larger it is there; each fragment computes its
// depth exactly — the ray from the light through its map point meets the triangle's plane —
// and fragments whose ray misses the triangle are discarded. What remains of the caveat: a
// triangle bending beyond its growth (a huge one across the hemispheres' seam) leaves thin
// slivers uncovered, where light leaks; and the growth costs fragment work.
#include "lib/frame.wgsl"
#include "lib/math.wgsl"
#include "lib/paraboloid.wgsl"

struct Params {
    // 1: the front hemisphere (along the light's direction), -1: the back
    side: f32,
};

@group(2) @binding(0) var<uniform> params: Params;
@group(2) @binding(1) var<storage, read> triangles: array<vec4<f32>>;

struct VsOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) @interpolate(flat) a: vec3<f32>,
    @location(1) @interpolate(flat) b: vec3<f32>,
    @location(2) @interpolate(flat) c: vec3<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) v: u32, @builtin(instance_index) t: u32) -> VsOut {
    let l = lights[instance.light];
    var out: VsOut;
    out.a = triangles[3u * t].xyz;
    out.b = triangles[3u * t + 1u].xyz;
    out.c = triangles[3u * t + 2u].xyz;
    let f = paraboloid_frame(l, params.side);
    var corners: array<vec2<f32>, 3>;
    for (var k = 0u; k < 3u; k++) {
        let d = f * (triangles[3u * t + k].xyz - l.position.xyz);
        corners[k] = paraboloid_project(d / max(length(d), 1e-12));
    }
    // Grown around its centre so that the bent outline of the true triangle stays inside (the
    // fragment stage discards what the triangle does not cover): the larger the triangle on
    // the map, the more its edges bend, the more it grows.
    let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
    let extent = max(distance(corners[0], corners[1]), max(distance(corners[1], corners[2]), distance(corners[2], corners[0])));
    let growth = 1.1 + 4.0 * min(extent, 2.0);
    out.pos = vec4<f32>(centre + (corners[v % 3u] - centre) * growth, 0.5, 1.0);
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
