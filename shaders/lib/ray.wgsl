// Ray queries against the scene's acceleration structure (the `acceleration_structure`
// resource). Its instances are masked: opaque and alpha-masked meshes by `OPAQUE_MESHES`,
// blended ones by `BLENDED_MESHES`; the bundled passes trace both, as the reference does. The
// including file starts with `enable wgpu_ray_query;` and binds the structure as
// `scene_accel`. Sidedness: shadow and occlusion rays stop at every surface, from either side
// (docs/scenes.md), as the reference's do. Cut-outs: masked surfaces let light through where
// their alpha is below the cutoff, blended ones in proportion to 1 − alpha
// (lib/hit_maps.wgsl, whose standard bindings every tracing pass therefore binds; only the
// triangles of masked and blended meshes are ever looked up: the others are built opaque).
#include "lib/frame.wgsl"
#include "lib/hit_maps.wgsl"

const OPAQUE_MESHES: u32 = 1u;
const BLENDED_MESHES: u32 = 2u;

// How far a ray leaving a surface starts off it, and the nearest distance it counts: a
// fraction of the scene's size (as the reference's offset is), large enough to clear the
// rounding of a position rebuilt from the depth buffer.
fn ray_offset() -> f32 {
    return frame.scene_radius * 2e-4;
}

// How far a position rebuilt from the depth buffer may lie off its surface: the distance a
// few f32 steps of depth move it (large far from a tiny near plane: scenes/hard/deep_range).
fn depth_error(world: vec3<f32>) -> f32 {
    let c = frame.view_proj * vec4<f32>(world, 1.0);
    if c.w <= 0.0 {
        return 0.0;
    }
    let ndc = c.xyz / c.w;
    let step = max(abs(ndc.z), 1e-6) * 8.0 * 1.1920929e-7;
    let moved = frame.inv_view_proj * vec4<f32>(ndc.xy, ndc.z + step, 1.0);
    return distance(moved.xyz / moved.w, world);
}

// The offset of a ray leaving the surface seen at `world`.
fn surface_offset(world: vec3<f32>) -> f32 {
    return ray_offset() + depth_error(world);
}

// The share of light that passes along `dir` (unit) from `origin` between `t_min` and
// `t_max`: 0 where an opaque surface lies between, or a masked one where it is not cut out;
// else the product of (1 − alpha) over the blended surfaces between — the mean of the
// reference's coins (each lets the ray through with probability 1 − alpha), without their
// noise. Opaque triangles end the query at once; only masked and blended ones are offered
// as candidates, each once.
fn transmittance(origin: vec3<f32>, dir: vec3<f32>, t_min: f32, t_max: f32) -> f32 {
    if t_max <= t_min {
        return 1.0;
    }
    var rq: ray_query;
    rayQueryInitialize(&rq, scene_accel, RayDesc(RAY_FLAG_TERMINATE_ON_FIRST_HIT, 0xffu, t_min, t_max, origin, dir));
    var through = 1.0;
    while rayQueryProceed(&rq) {
        let c = rayQueryGetCandidateIntersection(&rq);
        if c.kind == RAY_QUERY_INTERSECTION_TRIANGLE {
            let cover = coverage(c.instance_custom_data + c.primitive_index, c.barycentrics);
            if cover >= 1.0 {
                rayQueryConfirmIntersection(&rq);
            } else {
                through *= 1.0 - cover;
            }
        }
    }
    return select(through, 0.0, rayQueryGetCommittedIntersection(&rq).kind != RAY_QUERY_INTERSECTION_NONE);
}

// How much of light `l` reaches `world` (normal `n`, facing the viewer) in direction `to_light`:
// one shadow ray, to the light's position (spot, point) or out of the scene (directional).
// A light that casts no shadows reaches everything, as with shadow maps.
fn light_visibility(l: Light, world: vec3<f32>, n: vec3<f32>, to_light: vec3<f32>) -> f32 {
    if l.casts_shadows == 0u {
        return 1.0;
    }
    return light_reaches(l, world, n, to_light, surface_offset(world));
}

// The shadow ray itself (its transmittance), from `eps` off the surface (every light, `shadows: false` or not:
// what the reference computes everywhere).
fn light_reaches(l: Light, world: vec3<f32>, n: vec3<f32>, to_light: vec3<f32>, eps: f32) -> f32 {
    // Off the side the light is on: a back-lit double-sided wall shadows itself.
    let side = select(-1.0, 1.0, dot(n, to_light) >= 0.0);
    let origin = world + n * side * eps;
    // Every surface lies within the scene's bounding sphere: 2 radii cover any chord.
    var t_max = 2.5 * frame.scene_radius;
    if l.kind != LIGHT_DIRECTIONAL {
        // A light nearer than the offset (on the surface) is not shadowed.
        t_max = distance(l.position.xyz, origin) - eps;
    }
    return transmittance(origin, to_light, eps, t_max);
}
