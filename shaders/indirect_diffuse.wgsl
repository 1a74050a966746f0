// Indirect diffuse light from one light's reflective shadow map (seed 000 §4.3.3, §6.3.3,
// after Dachsbacher and Stamminger): the RSM texels around the receiver's projection act as
// small lights. Samples follow the seed's polar pattern, s = p + radius · e1 · (sin 2πe2,
// cos 2πe2), weighted by e1² (2·e1 with `gi.area_weights`, see `sample_weight`), and each adds
//     flux · max(n_p · d, 0) · max(n_s · -d, 0) / |d|⁴        (d: receiver to sender).
// Deviations (docs/effects.md): |d| is clamped below by `gi.min_distance` (the 1/|d|⁴ singularity of
// a sender next to the receiver); and each sample's flux is the light its texel reflects in
// all (`texel_power`) times the texels of the sampled disc it stands for, so the result does
// not depend on the RSM's size or the scene's scale.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"
#include "lib/sampling.wgsl"

struct Params {
    radius: f32,
    samples: u32,
    strength: f32,
    min_distance: f32,
    area_weights: u32,
    // min_distance in world units, else in the scene's (lib/frame.wgsl)
    world: u32,
    // The filtered variant's occlusion test (`segment_clear`, lib/gbuffer.wgsl): points
    // probed per sender, 0 for none; how thick a surface is taken to be.
    steps: u32,
    thickness: f32,
};

@group(2) @binding(3) var rsm_position: texture_2d<f32>;
@group(2) @binding(4) var rsm_normal: texture_2d<f32>;
@group(2) @binding(5) var rsm_flux: texture_2d<f32>;
@group(2) @binding(6) var<storage, read> gi_pattern: array<vec2<f32>>;
@group(2) @binding(7) var<uniform> params: Params;

const PI: f32 = 3.14159265;

// The light RSM texel t reflects in all (per π: radiance times area): the flux map holds
// radiosity per unit of the sender's own area, lit at incidence θ; the texel covers
// texel_width² across the map's axis at the sender's depth, 1/cos θ of that on the surface,
// and, in a perspective map, cos α of that off the axis (α the ray's angle to the axis: a
// texel's solid angle shrinks as cos³ α while its distance grows as 1/cos α; up to 4× at the
// edge of an emitter's 150° map). The product, light × albedo × texel_width² × cos α, does not
// depend on how the sender is turned (an area measured from neighbouring texels' positions
// would jump at every silhouette).
fn texel_power(l: Light, t: vec2<i32>, sp: vec3<f32>, sn: vec3<f32>, size: f32) -> vec3<f32> {
    let to_light = select(safe_normalize(l.position.xyz - sp, sn), -safe_normalize(l.direction.xyz, sn), l.kind == LIGHT_DIRECTIONAL);
    let cos_s = max(dot(sn, to_light), 1e-3);
    let w = texel_width(l.view_proj, sp, size);
    var cos_a = 1.0;
    if l.kind != LIGHT_DIRECTIONAL {
        let depth = abs((l.view_proj * vec4<f32>(sp, 1.0)).w);
        cos_a = clamp(depth / max(distance(l.position.xyz, sp), 1e-20), 0.0, 1.0);
    }
    return textureLoad(rsm_flux, t, 0).rgb / cos_s * w * w * cos_a;
}

// The seed's fixed pattern: every pixel, every frame, the same samples.
@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(gather(vec2<i32>(pos.xy), 0.0), 0.0);
}

// The filtered variant: two sampling strategies combined by the balance heuristic (Veach's
// multiple importance sampling), unbiased for everything the light reaches. Half the samples
// are uniform over the whole map (a disc around the receiver's projection misses the light of
// senders far away in the map, such as the floor for a wall a spot light grazes); half lie on
// a disc of radius `gi.filtered.radius` around that projection, uniform in radius, so dense
// where senders are near the receiver: there the 1/|d|² falloff makes the light of a few
// texels large, and uniform samples alone left whole surfaces ±30% off with 64 samples (the
// lamp-lit box's floor 0.90–1.30× the reference as the per-pixel shift changed). The pattern
// is shifted per pixel (the same every frame), which turns its structured error into noise
// that a cross-bilateral blur (bilateral_blur.wgsl) removes; each sender is tested for
// occlusion in the camera's depth buffer (`segment_clear`), since the whole map holds senders
// hidden from the receiver.
@fragment
fn fs_filtered(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(gather_mixed(vec2<i32>(pos.xy), pixel_shift(vec2<u32>(pos.xy))), 0.0);
}

// The temporal variant (after Lambru et al., seed 000 §4.3.3): fewer samples, the pattern
// rotated by an angle that differs per pixel and per frame; `temporal_accumulate.wgsl`
// averages the frames over a reprojected history.
@fragment
fn fs_rotated(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<u32>(pos.xy);
    let h = pcg_hash(p.x ^ pcg_hash(p.y ^ pcg_hash(frame.frame_index)));
    return vec4<f32>(gather(vec2<i32>(pos.xy), f32(h) / 4294967296.0), 0.0);
}

// The weight of a sample at e1 (its distance from the centre over the radius). Samples are
// uniform in e1, so their density on the disc falls as 1/e1: the disc area each stands for is
// 2·e1 times the mean (`area_weights`, unbiased). The seed's e1² averages 1/3 instead, so it
// gathers about a third of the light (`lightbench sweep sweeps/indirect_diffuse.ron` shows it
// against the path-traced reference).
fn sample_weight(e1: f32) -> f32 {
    return select(e1 * e1, 2.0 * e1, params.area_weights != 0u);
}

// What the receiver needs of the light of this repetition: its surface, the light, and where
// the receiver projects in the light's map (the disc's centre; a receiver behind a spot light
// — a ceiling above it — has no place in its map but is lit by what it lights all the same:
// its disc is centred on the map).
struct Receiver {
    s: Surface,
    l: Light,
    uv: vec2<f32>,
};

fn receiver(px: vec2<i32>) -> Receiver {
    let s = load_surface(px);
    let l = lights[instance.light];
    let on = on_texture(l.view_proj, s.world);
    return Receiver(s, l, select(vec2<f32>(0.5), on.uv, on.in_front));
}

// The light the RSM texel at `suv` sends the receiver, per unit of the map's area sampled:
// power · cos θ_p · cos θ_s / |d|² (|d| clamped below by `gi.min_distance`), 0 off the map,
// where nothing was drawn, for a sender turned away, or (`occluded`) one hidden in the
// camera's depth buffer.
fn sender(r: Receiver, suv: vec2<f32>, occluded: bool, jitter: f32) -> vec3<f32> {
    if any(suv < vec2<f32>(0.0)) || any(suv >= vec2<f32>(1.0)) {
        return vec3<f32>(0.0);
    }
    let size = vec2<i32>(textureDimensions(rsm_flux, 0));
    let t = min(vec2<i32>(suv * vec2<f32>(size)), size - 1);
    let sp = textureLoad(rsm_position, t, 0);
    if sp.w == 0.0 {
        return vec3<f32>(0.0); // nothing drawn there
    }
    let sn = textureLoad(rsm_normal, t, 0).xyz;
    let d = sp.xyz - r.s.world;
    let facing = max(dot(r.s.n, d), 0.0) * max(dot(sn, -d), 0.0);
    let unit = length_unit(params.world);
    if facing == 0.0 || (occluded && !segment_clear(r.s.world, sp.xyz, params.steps, params.thickness * unit, 0.01 * unit, jitter)) {
        return vec3<f32>(0.0); // turned away, or hidden from the receiver
    }
    let min_d = params.min_distance * unit;
    let d2 = max(dot(d, d), min_d * min_d);
    let texels = f32(size.x * size.y);
    return texel_power(r.l, t, sp.xyz, sn, f32(size.x)) * texels * facing / (d2 * d2);
}

// The sum over senders is ∫ B cos θ_p cos θ_s / |d|² dA = π E (B: the senders' radiosity, E:
// the receiver's irradiance); the term held is E / π (the receiver's Lambert 1/π, applied
// here, as indirect_compose.wgsl says).
fn irradiance_over_pi(sum: vec3<f32>) -> vec3<f32> {
    return sum * params.strength / (PI * PI);
}

// Irradiance / π at pixel `px` from the light of this repetition, by the seed's sampling: a
// disc around the receiver's projection, uniform in radius and weighted by `sample_weight`
// (each sample standing for the disc's area over the count), its pattern turned by `turn`.
fn gather(px: vec2<i32>, turn: f32) -> vec3<f32> {
    let r = receiver(px);
    if !r.s.covered {
        return vec3<f32>(0.0);
    }
    let n = min(params.samples, arrayLength(&gi_pattern));
    let per_sample = PI * params.radius * params.radius / f32(max(n, 1u));
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < n; i++) {
        let e = gi_pattern[i];
        let a = 2.0 * PI * (e.y + turn);
        let suv = r.uv + params.radius * e.x * vec2<f32>(sin(a), cos(a));
        sum += sample_weight(e.x) * per_sample * sender(r, suv, false, 0.0);
    }
    return irradiance_over_pi(sum);
}

// The share of the filtered variant's samples on the disc around the receiver's projection
// (the rest uniform over the map): 0.25, 0.5 and 0.75 measured alike on the three Cornell
// scenes of sweeps/indirect_diffuse.ron.
const NEAR_SHARE: f32 = 0.5;

// Irradiance / π at pixel `px` by the filtered variant's two strategies (see `fs_filtered`):
// a sample at map point x counts f(x) / (n_u + n_d · p_d(x)), p_d the disc's density (uniform
// in radius ρ: 1 / (2π R ρ) inside the disc), n_u and n_d the two strategies' sample counts —
// the balance heuristic, unbiased whichever strategy drew x.
fn gather_mixed(px: vec2<i32>, shift: vec2<f32>) -> vec3<f32> {
    let r = receiver(px);
    if !r.s.covered {
        return vec3<f32>(0.0);
    }
    let n = min(params.samples, arrayLength(&gi_pattern));
    let nd = u32(f32(n) * NEAR_SHARE);
    let nu = n - nd;
    let radius = params.radius;
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < n; i++) {
        var suv = fract(lattice(i, nu) + shift);
        if i >= nu {
            let e = gi_pattern[i - nu];
            let a = 2.0 * PI * (e.y + shift.x);
            suv = r.uv + radius * fract(e.x + shift.y) * vec2<f32>(sin(a), cos(a));
        }
        let rho = length(suv - r.uv);
        let p_disc = select(0.0, 1.0 / (2.0 * PI * radius * max(rho, 1e-9)), rho < radius);
        let jitter = fract(f32(i) * 0.7548777 + shift.y);
        sum += sender(r, suv, true, jitter) / (f32(nu) + f32(nd) * p_disc);
    }
    return irradiance_over_pi(sum);
}
