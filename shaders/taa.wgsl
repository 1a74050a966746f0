// TAA, temporal anti-aliasing (the modern baseline beside FXAA; after Karis, "High quality
// temporal supersampling", 2014, and Pedersen, "Temporal reprojection anti-aliasing in
// INSIDE", 2016): the camera moves by a sub-pixel Halton offset each frame (the option's
// `jitter`), so each pixel sees a different point of its area every frame; the pixel blends
// this frame's sample into a history of earlier ones, found where the surface was in the
// previous frame (reprojection from depth through `frame.prev_view_proj`, without either
// frame's jitter, so that a still camera reads the history at the pixel itself). A history
// colour the pixel's 3×3 neighbourhood does not hold now — the scene moved, or the surface
// was hidden — is clipped to the neighbourhood's range in YCoCg (towards its centre, which
// keeps the hue) before the blend: no ghost trails. The history keeps weight
// `taa.history_weight`; 0.9 averages about the last 10 frames. Blending is in linear light
// of the tone-mapped image, so the bright side of an edge cannot swamp it.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"

struct Params {
    history_weight: f32,
};

@group(2) @binding(3) var ldr_aliased: texture_2d<f32>;
@group(2) @binding(4) var taa_history_prev: texture_2d<f32>;
@group(2) @binding(5) var taa_linear: sampler;
@group(2) @binding(8) var<uniform> params: Params;

struct Out {
    // The displayed image.
    @location(0) color: vec4<f32>,
    // The same, kept unquantised for the next frame.
    @location(1) history: vec4<f32>,
};

fn ycocg(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(c, vec3<f32>(0.25, 0.5, 0.25)), dot(c, vec3<f32>(0.5, 0.0, -0.5)), dot(c, vec3<f32>(-0.25, 0.5, -0.25)));
}

fn rgb(c: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z);
}

// `h` moved along the line to the box's centre until it lies in the box [lo, hi].
fn clip_to_box(h: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> vec3<f32> {
    let centre = 0.5 * (lo + hi);
    let d = h - centre;
    let reach = abs(d) / max(0.5 * (hi - lo), vec3<f32>(1e-6));
    let m = max(reach.x, max(reach.y, reach.z));
    return select(h, centre + d / m, m > 1.0);
}

// Where this pixel's surface was in the previous frame's history, in texture coordinates;
// outside [0, 1) when it was off screen. History pixels hold un-jittered pixel centres:
// undo the previous frame's jitter and add this frame's (a pixel samples its centre plus
// `frame.jitter.xy`).
fn history_uv(px: vec2<i32>) -> vec2<f32> {
    let depth = textureLoad(gbuf_depth, px, 0).x;
    let on = on_texture(frame.prev_view_proj, world_from_depth(px, depth));
    if !on.in_front {
        return vec2<f32>(-1.0);
    }
    let at = on.uv * frame.resolution.xy - frame.jitter.zw + frame.jitter.xy;
    return at * frame.resolution.zw;
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> Out {
    let size = vec2<i32>(textureDimensions(ldr_aliased));
    let px = vec2<i32>(pos.xy);
    let current = textureLoad(ldr_aliased, px, 0).rgb;
    var lo = ycocg(current);
    var hi = lo;
    for (var i = 0; i < 9; i++) {
        let q = clamp(px + vec2<i32>(i % 3 - 1, i / 3 - 1), vec2<i32>(0), size - 1);
        let c = ycocg(textureLoad(ldr_aliased, q, 0).rgb);
        lo = min(lo, c);
        hi = max(hi, c);
    }
    var out: Out;
    out.color = vec4<f32>(current, 1.0);
    out.history = out.color;
    let uv = history_uv(px);
    if frame.frame_index == 0u || any(uv < vec2<f32>(0.0)) || any(uv >= vec2<f32>(1.0)) {
        return out; // no history here yet: this frame's sample alone
    }
    let history = textureSampleLevel(taa_history_prev, taa_linear, uv, 0.0).rgb;
    let kept = rgb(clip_to_box(ycocg(history), lo, hi));
    // Clamped: the clip is to a box in YCoCg, whose corners lie a little outside [0, 1] in RGB.
    let blended = clamp(mix(current, kept, clamp(params.history_weight, 0.0, 1.0)), vec3<f32>(0.0), vec3<f32>(1.0));
    out.color = vec4<f32>(blended, 1.0);
    out.history = out.color;
    return out;
}
