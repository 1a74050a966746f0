enable wgpu_ray_query;
// The reference's integrator on the GPU (docs/reference.md; reference/src/integrate.rs): a
// camera ray through the pixel's centre, then per term
// - `fs_full`: path tracing — every light (a shadow ray each) and one point drawn on an
//   emitter chosen by power (next-event estimation) at every vertex, the path continued in a
//   direction drawn from the BRDF's one-sample mixture of lobes, emitters it meets weighed
//   against next-event estimation by the power heuristic, Russian roulette after 3 bounces;
// - `fs_direct`: emission + the lights + the emitters by both strategies, once;
// - `fs_ao`: 1 − the cosine-weighted share of directions meeting a surface within the radius.
// Materials are looked up where rays meet them (lib/hit_maps.wgsl: base colour,
// metallic-roughness, normal and emissive maps; masked surfaces cut out and blended ones
// stochastically transparent, for camera and bounce rays; shadow rays take the coins' mean,
// lib/ray.wgsl's `transmittance`).
// Each frame adds `samples` paths per pixel to a running mean and sum of squared deviations
// (Welford; in `pt.mean`, `pt.m2`, history resources, so the image refines frame by frame);
// the count restarts in the first frame, when the camera moves, and with fresh history.
// Random numbers depend only on (seed, pixel, sample), and each sample is added in turn, so a
// seed gives the same image however the samples are spread over frames.
#include "lib/frame.wgsl"
#include "lib/math.wgsl"
#include "lib/lighting.wgsl"
#include "lib/surface.wgsl"
#include "lib/ray.wgsl"
#include "lib/hit.wgsl"
#include "lib/sampling.wgsl"
#include "lib/hit_maps.wgsl"
#include "lib/hit_emitters.wgsl"
#include "lib/lobes.wgsl"

struct Params {
    samples: u32,
    seed: u32,
    ao_radius: f32,
    ao_falloff: u32,
    emitter_sampling: u32,
    max_samples: u32,
};

@group(2) @binding(0) var pt_mean_prev: texture_2d<f32>;
@group(2) @binding(1) var pt_m2_prev: texture_2d<f32>;
@group(2) @binding(8) var<uniform> params: Params;
@group(2) @binding(9) var scene_accel: acceleration_structure;

// Bounces after which Russian roulette may end a path, and the hard cap (the reference's).
const ROULETTE_FROM: u32 = 3u;
const MAX_BOUNCES: u32 = 256u;
const FAR: f32 = 3.0e38;

// A stream of uniform numbers in [0, 1) for one (seed, pixel, sample).
struct Rng {
    state: u32,
};

fn rng_new(pixel: u32, sample: u32) -> Rng {
    return Rng(pcg_hash(params.seed ^ pcg_hash(pixel ^ pcg_hash(sample))));
}

fn rand(r: ptr<function, Rng>) -> f32 {
    (*r).state = pcg_hash((*r).state);
    return f32((*r).state >> 8u) * (1.0 / 16777216.0);
}

// A fresh coin source for the rays about to leave (blended surfaces, lib/hit_maps.wgsl).
fn toss(r: ptr<function, Rng>) {
    (*r).state = pcg_hash((*r).state);
    ray_coin = (*r).state;
}

// How far rays leaving a surface start off it: 1e-5 of the scene's diagonal, the reference's.
fn path_eps() -> f32 {
    return frame.scene_radius * 2e-5;
}

fn origin_of(h: RayHit) -> vec3<f32> {
    return h.world + h.ng * path_eps();
}

// The camera ray through pixel centre `px`, clipped to the near and far planes (read off the
// projection: a perspective one, x and y scaled, depth 0..1).
struct CameraRay {
    origin: vec3<f32>,
    dir: vec3<f32>,
    t_min: f32,
    t_max: f32,
};

fn camera_ray(px: vec2<f32>) -> CameraRay {
    let ndc = vec2<f32>(px.x * frame.resolution.z * 2.0 - 1.0, 1.0 - px.y * frame.resolution.w * 2.0);
    let at_one = vec3<f32>(ndc.x / frame.proj[0].x, ndc.y / frame.proj[1].y, -1.0);
    // The view is rigid: its inverse rotation is its transpose.
    let rot = transpose(mat3x3<f32>(frame.view[0].xyz, frame.view[1].xyz, frame.view[2].xyz));
    let len = length(at_one);
    let near = frame.proj[3].z / frame.proj[2].z;
    let far = frame.proj[3].z / (frame.proj[2].z + 1.0);
    let t_max = select(FAR, far * len, far > near && far * len < FAR);
    return CameraRay(frame.camera_pos.xyz, normalize(rot * at_one), near * len, t_max);
}

// The share of light passing from `to` to `start` (a shadow ray from the offset origin
// towards `to`, stopping short of it).
fn seen_through(start: vec3<f32>, to: vec3<f32>) -> f32 {
    let d = to - start;
    let dist = length(d);
    let eps = path_eps();
    if dist - eps <= eps {
        return 1.0;
    }
    return transmittance(start, d / dist, eps, dist - eps);
}

// The lights' light at `h` reflected towards `v`, each with a shadow ray.
fn lights_at(h: RayHit, b: Lobes, v: vec3<f32>) -> vec3<f32> {
    let eps = path_eps();
    let origin = origin_of(h);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < frame.light_count; i++) {
        let l = lights[i];
        let ls = light_at(l, h.world);
        if max(ls.radiance.r, max(ls.radiance.g, ls.radiance.b)) <= 0.0 {
            continue;
        }
        let f = lobes_eval(b, h.n, ls.to_light, v).f;
        if max(f.r, max(f.g, f.b)) <= 0.0 {
            continue;
        }
        let t_max = select(ls.dist - eps, FAR, l.kind == LIGHT_DIRECTIONAL);
        if t_max <= 0.0 {
            sum += f * ls.radiance;
        } else {
            sum += f * ls.radiance * transmittance(origin, ls.to_light, eps, t_max);
        }
    }
    return sum;
}

fn power_heuristic(p: f32, other: f32) -> f32 {
    let r = other / p;
    return select(0.0, 1.0 / (1.0 + r * r), r * r < FAR);
}

fn emits() -> bool {
    return params.emitter_sampling != 0u && any_emitter();
}

// One point drawn on an emitter, its light reflected at `h` towards `v` (next-event
// estimation), weighed against BRDF sampling when `mis`.
fn emitted_light(h: RayHit, b: Lobes, v: vec3<f32>, r: ptr<function, Rng>, mis: bool) -> vec3<f32> {
    if !emits() {
        return vec3<f32>(0.0);
    }
    let u = vec3<f32>(rand(r), rand(r), rand(r));
    let s = emitter_sample(h.world, u);
    if s.pdf <= 0.0 || dot(h.ng, s.l) <= 0.0 || max(s.radiance.r, max(s.radiance.g, s.radiance.b)) <= 0.0 {
        return vec3<f32>(0.0);
    }
    let e = lobes_eval(b, h.n, s.l, v);
    if max(e.f.r, max(e.f.g, e.f.b)) <= 0.0 {
        return vec3<f32>(0.0);
    }
    let w = select(1.0, power_heuristic(s.pdf, e.pdf), mis);
    return e.f * s.radiance * (w / s.pdf) * seen_through(origin_of(h), h.world + s.l * s.dist);
}

// What a surface `y` that a BRDF-drawn ray (direction `l`, density `pdf`) met emits towards
// it, weighed against next-event estimation; nothing where the ray passed a back first.
fn emission_found(y: RayHit, l: vec3<f32>, pdf: f32) -> vec3<f32> {
    if y.shadowed || max(y.emissive.r, max(y.emissive.g, y.emissive.b)) <= 0.0 {
        return vec3<f32>(0.0);
    }
    if !emits() {
        return y.emissive;
    }
    return y.emissive * power_heuristic(pdf, emitter_pdf(y.emitter, l, y.t));
}

fn lobes_at(h: RayHit) -> Lobes {
    return lobes(h.albedo, clamp(h.metallic, 0.0, 1.0), clamp(h.roughness, 0.03, 1.0));
}

// `full`: every bounce.
fn full(first: RayHit, v0: vec3<f32>, r: ptr<function, Rng>) -> vec3<f32> {
    var h = first;
    var v = v0;
    var sum = h.emissive;
    var throughput = vec3<f32>(1.0);
    for (var bounce = 1u; bounce <= MAX_BOUNCES; bounce++) {
        toss(r);
        let b = lobes_at(h);
        sum += throughput * (lights_at(h, b, v) + emitted_light(h, b, v, r, true));
        let u = vec2<f32>(rand(r), rand(r));
        let s = lobes_sample(b, h.n, h.ng, v, u, rand(r));
        throughput *= s.weight;
        if max(throughput.r, max(throughput.g, throughput.b)) <= 0.0 {
            break;
        }
        if bounce > ROULETTE_FROM {
            let survive = min(max(throughput.r, max(throughput.g, throughput.b)), 0.95);
            if rand(r) >= survive {
                break;
            }
            throughput /= survive;
        }
        let y = trace_seen_mapped(origin_of(h), s.l, path_eps(), FAR);
        if !y.found {
            break;
        }
        sum += throughput * emission_found(y, s.l, s.pdf);
        h = y;
        v = -s.l;
    }
    return sum;
}

// `direct`: emission, the lights, and the emitters by a point drawn on one and by a
// direction drawn from the BRDF.
fn direct(h: RayHit, v: vec3<f32>, r: ptr<function, Rng>) -> vec3<f32> {
    toss(r);
    let b = lobes_at(h);
    var sum = h.emissive + lights_at(h, b, v);
    if !any_emitter() {
        return sum;
    }
    let u = vec2<f32>(rand(r), rand(r));
    let s = lobes_sample(b, h.n, h.ng, v, u, rand(r));
    if max(s.weight.r, max(s.weight.g, s.weight.b)) > 0.0 {
        let y = trace_seen_mapped(origin_of(h), s.l, path_eps(), FAR);
        if y.found {
            sum += s.weight * emission_found(y, s.l, s.pdf);
        }
    }
    return sum + emitted_light(h, b, v, r, true);
}

// `ao`: a cosine-weighted direction, occluded by any surface within the radius.
fn ao(h: RayHit, r: ptr<function, Rng>) -> f32 {
    toss(r);
    let d = cosine_direction(h.n, vec2<f32>(rand(r), rand(r)));
    if dot(h.ng, d) <= 0.0 {
        return 0.0;
    }
    let t = nearest_occluder(origin_of(h), d, path_eps(), params.ao_radius);
    if t < 0.0 {
        return 1.0;
    }
    return select(0.0, 1.0 - 1.0 / (1.0 + t * t), params.ao_falloff != 0u);
}

const TERM_FULL: u32 = 0u;
const TERM_DIRECT: u32 = 1u;
const TERM_AO: u32 = 2u;

// One sample of `term` at the surface the camera ray met (or the background).
fn estimate(term: u32, first: RayHit, v: vec3<f32>, r: ptr<function, Rng>) -> vec3<f32> {
    if !first.found {
        return select(vec3<f32>(0.0), vec3<f32>(1.0), term == TERM_AO);
    }
    if term == TERM_AO {
        return vec3<f32>(ao(first, r));
    }
    if term == TERM_DIRECT {
        return direct(first, v, r);
    }
    return full(first, v, r);
}

struct Out {
    // rgb: the running mean; a: the samples behind it
    @location(0) mean: vec4<f32>,
    // rgb: the sum of squared deviations from the mean (variance × (n − 1))
    @location(1) m2: vec4<f32>,
    // Where the camera ray met a surface (1 where it met none), for metering.
    @builtin(frag_depth) depth: f32,
};

fn accumulate(frag: vec4<f32>, term: u32) -> Out {
    let px = vec2<i32>(frag.xy);
    let moved = any(frame.view_proj[0] != frame.prev_view_proj[0]) || any(frame.view_proj[1] != frame.prev_view_proj[1])
        || any(frame.view_proj[2] != frame.prev_view_proj[2]) || any(frame.view_proj[3] != frame.prev_view_proj[3]);
    let restart = frame.frame_index == 0u || moved;
    var mean = select(textureLoad(pt_mean_prev, px, 0), vec4<f32>(0.0), restart);
    var m2 = select(textureLoad(pt_m2_prev, px, 0).rgb, vec3<f32>(0.0), restart);
    let ray = camera_ray(frag.xy);
    let pixel = u32(px.y) * u32(frame.resolution.x) + u32(px.x);
    let todo = min(params.samples, params.max_samples - min(u32(mean.a), params.max_samples));
    var first: RayHit;
    // The camera ray is traced with each sample (it meets the same surface every time; traced
    // once before the loop, lavapipe's ray query crashes), and once when no sample is due.
    for (var k = 0u; k < max(todo, 1u); k++) {
        var r = rng_new(pixel, u32(mean.a));
        toss(&r);
        first = trace_seen_mapped(ray.origin, ray.dir, ray.t_min, ray.t_max);
        if k < todo {
            let x = estimate(term, first, -ray.dir, &r);
            mean.a += 1.0;
            let delta = x - mean.rgb;
            mean = vec4<f32>(mean.rgb + delta / mean.a, mean.a);
            m2 += delta * (x - mean.rgb);
        }
    }
    var out: Out;
    out.mean = mean;
    out.m2 = vec4<f32>(m2, 0.0);
    out.depth = 1.0;
    if first.found {
        let c = frame.view_proj * vec4<f32>(first.world, 1.0);
        out.depth = clamp(c.z / c.w, 0.0, 1.0);
    }
    return out;
}

@fragment
fn fs_full(@builtin(position) frag: vec4<f32>) -> Out {
    return accumulate(frag, TERM_FULL);
}

@fragment
fn fs_direct(@builtin(position) frag: vec4<f32>) -> Out {
    return accumulate(frag, TERM_DIRECT);
}

@fragment
fn fs_ao(@builtin(position) frag: vec4<f32>) -> Out {
    return accumulate(frag, TERM_AO);
}
