// Ground-truth-based ambient occlusion (GTAO; Jimenez et al., "Practical realtime strategies
// for accurate indirect occlusion", 2016; Intel's XeGTAO shows the same integral): the modern
// baseline beside the seeds' SSAO. Per pixel, `slices` planes through the view direction, each
// turned by a per-pixel offset (interleaved gradient noise; the blur after it averages the
// offsets). In each slice, `steps` depth samples each way along the screen direction, within
// the radius's projection, find the highest horizon on either side; the visible arc between
// the two horizons, clamped to the hemisphere of the normal projected into the slice, is
// integrated against the cosine in closed form, weighted by the projected normal's length. The result is the cosine-weighted share of directions that meet no surface
// within the radius — what the reference's `ao` term measures — under a heightfield
// assumption: what hides a direction is taken to extend behind it, unless `thickness` lets a
// horizon sink back when the samples behind an occluder fall away. Occluders fade out over the
// last `falloff` of the radius (a hard edge would flicker with the sample positions).
// Worked in world space: positions from depth, the slice direction from the camera's axes.
// Output: 1 unoccluded … 0 fully occluded.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"

struct Params {
    radius: f32,
    slices: u32,
    steps: u32,
    thickness: f32,
    falloff: f32,
    // the radius in world units, else in the scene's (lib/frame.wgsl)
    world: u32,
};

@group(2) @binding(5) var<uniform> params: Params;

const PI: f32 = 3.14159265;
const HALF_PI: f32 = 1.57079633;

// Interleaved gradient noise (Jimenez 2014): a different offset for each pixel of a 4×4-ish
// pattern that a small blur averages well.
fn noise(p: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(p, vec2<f32>(0.06711056, 0.00583715))));
}

// World position of the surface the camera sees at screen point `q` (pixels), if any. Off
// screen, the nearest edge pixel's surface stands in (as XeGTAO's clamping sampler does): a
// wall leaving the image still occludes with its last visible point, where skipping the
// samples left the step's occlusion +0.078 above the reference, twice what clamping leaves.
struct Seen {
    found: bool,
    world: vec3<f32>,
};

fn seen_at(q: vec2<f32>) -> Seen {
    let px = clamp(vec2<i32>(floor(q)), vec2<i32>(0), vec2<i32>(frame.resolution.xy) - 1);
    let d = textureLoad(gbuf_depth, px, 0).x;
    return Seen(d < 1.0, world_from_depth(px, d));
}

// Where a slice starts: the surface point and pixel, the direction to the camera, the radius
// in world units and in pixels.
struct Origin {
    p: vec3<f32>,
    at: vec2<f32>,
    v: vec3<f32>,
    radius: f32,
    reach: f32,
};

// The cosine of the highest horizon along screen direction `dir` (pixels) from `o`, starting
// at `lowest` (the hemisphere's edge on that side); `offset` shifts the sample positions.
fn horizon(o: Origin, dir: vec2<f32>, lowest: f32, offset: f32) -> f32 {
    var best = lowest;
    let steps = max(params.steps, 1u);
    for (var j = 0u; j < steps; j++) {
        // Sample spacing grows quadratically: more samples near the pixel, where it matters.
        let t = (f32(j) + offset) / f32(steps);
        let s = seen_at(o.at + dir * max(t * t * o.reach, 1.0 + f32(j)));
        if !s.found {
            continue;
        }
        let delta = s.world - o.p;
        let dist = length(delta);
        let cos_h = dot(delta / max(dist, 1e-20), o.v);
        let fade = clamp((o.radius - dist) / max(params.falloff * o.radius, 1e-6), 0.0, 1.0);
        let candidate = mix(lowest, cos_h, fade);
        // Thickness: a horizon may sink back towards a lower sample (the occluder ended).
        best = select(mix(best, candidate, params.thickness), candidate, candidate > best);
    }
    return best;
}

// The cosine-weighted visible arc from horizon angle `h` to the normal's angle `n` in a slice.
fn arc(h: f32, n: f32) -> f32 {
    return 0.25 * (-cos(2.0 * h - n) + cos(n) + 2.0 * h * sin(n));
}

// The slices' offsets stay put (the blur averages the pattern's neighbours).
@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return occlusion(frag, noise(frag.xy));
}

// `ao = gtao_temporal`: the offsets turn by the golden ratio each frame, so that
// temporal_accumulate.wgsl's average over frames covers the slice angles and step positions evenly.
@fragment
fn fs_temporal(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return occlusion(frag, fract(noise(frag.xy) + 0.618034 * f32(frame.frame_index % 4096u)));
}

fn occlusion(frag: vec4<f32>, offset: f32) -> vec4<f32> {
    let px = target_gbuffer_pixel(frag.xy);
    let s = load_surface(px);
    if !s.covered {
        return vec4<f32>(1.0);
    }
    let at = vec2<f32>(px) + 0.5;
    let radius = params.radius * length_unit(params.world);
    let v = safe_normalize(frame.camera_pos.xyz - s.world, s.n);
    // The radius's length in pixels at this depth (the projection's y scale).
    let w = (frame.view_proj * vec4<f32>(s.world, 1.0)).w;
    let reach = radius * frame.proj[1][1] * 0.5 * frame.resolution.y / max(w, 1e-6);
    let right = vec3<f32>(frame.view[0].x, frame.view[1].x, frame.view[2].x);
    let up = vec3<f32>(frame.view[0].y, frame.view[1].y, frame.view[2].y);
    let o = Origin(s.world, at, v, radius, reach);
    let slices = max(params.slices, 1u);
    var visibility = 0.0;
    for (var i = 0u; i < slices; i++) {
        let phi = (f32(i) + offset) * PI / f32(slices);
        let dir = vec2<f32>(cos(phi), sin(phi));
        // The slice's direction in the world (screen y runs down), and the slice plane's axis.
        let along = right * dir.x - up * dir.y;
        let ortho = along - dot(along, v) * v;
        let axis = safe_normalize(cross(ortho, v), s.n);
        let projected = s.n - axis * dot(s.n, axis);
        let len = length(projected);
        if len < 1e-6 {
            continue;
        }
        let cos_n = clamp(dot(projected, v) / len, -1.0, 1.0);
        let n = select(-1.0, 1.0, dot(ortho, projected) >= 0.0) * acos(cos_n);
        // Angles from the view direction, positive towards `dir`; unoccluded, each side's
        // horizon is the hemisphere's edge, n ± π/2.
        let h_plus = acos(clamp(horizon(o, dir, cos(n + HALF_PI), fract(offset + 0.5)), -1.0, 1.0));
        let h_minus = -acos(clamp(horizon(o, -dir, cos(n - HALF_PI), fract(offset + 0.25)), -1.0, 1.0));
        let h1 = n + clamp(h_plus - n, -HALF_PI, HALF_PI);
        let h0 = n + clamp(h_minus - n, -HALF_PI, HALF_PI);
        // Weighted by the projected normal's length: the slices together integrate the
        // cosine over the hemisphere (1 where nothing occludes).
        visibility += len * (arc(h0, n) + arc(h1, n));
    }
    return vec4<f32>(clamp(visibility / f32(slices), 0.0, 1.0));
}
