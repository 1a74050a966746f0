// Ray queries against the scene's acceleration structure (the `acceleration_structure`
// resource). Its instances are masked: opaque and alpha-masked meshes by `OPAQUE_MESHES`,
// blended ones by `BLENDED_MESHES` (which only the path tracer traces, as stochastic
// transparency). The including file starts with `enable wgpu_ray_query;` and binds the structure
// as `scene_accel`. Sidedness: shadow and occlusion rays stop at every surface, from either
// side (docs/scenes.md), as the reference's do.

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

// 1 when no surface lies along `dir` (unit) from `origin` between `t_min` and `t_max`, else 0.
fn unoccluded(origin: vec3<f32>, dir: vec3<f32>, t_min: f32, t_max: f32) -> f32 {
    if t_max <= t_min {
        return 1.0;
    }
    var rq: ray_query;
    rayQueryInitialize(&rq, scene_accel, RayDesc(RAY_FLAG_TERMINATE_ON_FIRST_HIT, OPAQUE_MESHES, t_min, t_max, origin, dir));
    rayQueryProceed(&rq);
    let hit = rayQueryGetCommittedIntersection(&rq);
    return select(1.0, 0.0, hit.kind != RAY_QUERY_INTERSECTION_NONE);
}

// Whether light `l` reaches `world` (normal `n`, facing the viewer) in direction `to_light`:
// one shadow ray, to the light's position (spot, point) or out of the scene (directional).
// A light that casts no shadows reaches everything, as with shadow maps.
fn light_visibility(l: Light, world: vec3<f32>, n: vec3<f32>, to_light: vec3<f32>) -> f32 {
    if l.casts_shadows == 0u {
        return 1.0;
    }
    return light_reaches(l, world, n, to_light, surface_offset(world));
}

// The shadow ray itself, from `eps` off the surface (every light, `shadows: false` or not:
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
    return unoccluded(origin, to_light, eps, t_max);
}
