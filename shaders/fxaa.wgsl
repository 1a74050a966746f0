// FXAA (seed 003 §3.3; Lottes' FXAA 3.11 "quality" algorithm): anti-aliasing as a post pass
// over the tone-mapped image, for deferred shading where hardware MSAA is costly. Per pixel:
// skip where the local luma contrast is below `fxaa.edge_threshold` (relative) or
// `fxaa.edge_threshold_min` (absolute) — flat regions are left exactly as they are; else find
// the edge's orientation, walk along it both ways (12 steps of growing length) to its ends,
// and shift the lookup across the edge by how far the pixel is from the nearer end; blend in
// a sub-pixel term for single-pixel features, scaled by `fxaa.subpixel`. The shift is read with
// a bilinear lookup, which mixes the two sides of the edge.

struct Params {
    edge_threshold: f32,
    edge_threshold_min: f32,
    subpixel: f32,
};

@group(2) @binding(0) var ldr_aliased: texture_2d<f32>;
@group(2) @binding(1) var fxaa_linear: sampler;
@group(2) @binding(2) var<uniform> params: Params;

// Perceptual luma of a linear colour (the image is stored sRGB; sampling decodes it).
fn luma(c: vec3<f32>) -> f32 {
    return sqrt(dot(c, vec3<f32>(0.299, 0.587, 0.114)));
}

fn luma_at(uv: vec2<f32>) -> f32 {
    return luma(textureSampleLevel(ldr_aliased, fxaa_linear, uv, 0.0).rgb);
}

fn luma_of(p: vec2<i32>, size: vec2<i32>) -> f32 {
    return luma(textureLoad(ldr_aliased, clamp(p, vec2<i32>(0), size - 1), 0).rgb);
}

const STEPS: array<f32, 12> = array<f32, 12>(1.0, 1.0, 1.0, 1.0, 1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0);

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<i32>(textureDimensions(ldr_aliased));
    let p = vec2<i32>(pos.xy);
    let texel = 1.0 / vec2<f32>(size);
    let uv = (vec2<f32>(p) + 0.5) * texel;
    let center = textureLoad(ldr_aliased, p, 0);
    let m = luma(center.rgb);
    let n = luma_of(p + vec2<i32>(0, -1), size);
    let s = luma_of(p + vec2<i32>(0, 1), size);
    let e = luma_of(p + vec2<i32>(1, 0), size);
    let w = luma_of(p + vec2<i32>(-1, 0), size);
    let lo = min(m, min(min(n, s), min(e, w)));
    let hi = max(m, max(max(n, s), max(e, w)));
    let range = hi - lo;
    if range < max(params.edge_threshold_min, hi * params.edge_threshold) {
        return center; // flat: unchanged
    }
    let nw = luma_of(p + vec2<i32>(-1, -1), size);
    let ne = luma_of(p + vec2<i32>(1, -1), size);
    let sw = luma_of(p + vec2<i32>(-1, 1), size);
    let se = luma_of(p + vec2<i32>(1, 1), size);
    // Orientation: the larger second difference across rows (a horizontal edge) or columns.
    let across_rows = abs(n + s - 2.0 * m) * 2.0 + abs(ne + se - 2.0 * e) + abs(nw + sw - 2.0 * w);
    let across_cols = abs(e + w - 2.0 * m) * 2.0 + abs(ne + nw - 2.0 * n) + abs(se + sw - 2.0 * s);
    let horizontal = across_rows >= across_cols;
    // The side of the edge with the steeper gradient; a step of one texel towards it.
    let l1 = select(w, n, horizontal);
    let l2 = select(e, s, horizontal);
    let g1 = l1 - m;
    let g2 = l2 - m;
    let first = abs(g1) >= abs(g2);
    let gradient = 0.25 * max(abs(g1), abs(g2));
    var step = select(texel.x, texel.y, horizontal);
    var local_average = 0.5 * (l2 + m);
    if first {
        step = -step;
        local_average = 0.5 * (l1 + m);
    }
    // On the edge: half a texel towards the chosen side; walk along it both ways.
    var on_edge = uv;
    if horizontal {
        on_edge.y += 0.5 * step;
    } else {
        on_edge.x += 0.5 * step;
    }
    let along = select(vec2<f32>(0.0, texel.y), vec2<f32>(texel.x, 0.0), horizontal);
    var uv1 = on_edge - along;
    var uv2 = on_edge + along;
    var end1 = luma_at(uv1) - local_average;
    var end2 = luma_at(uv2) - local_average;
    var done1 = abs(end1) >= gradient;
    var done2 = abs(end2) >= gradient;
    for (var i = 1; i < 12; i++) {
        if done1 && done2 {
            break;
        }
        if !done1 {
            uv1 -= along * STEPS[i];
            end1 = luma_at(uv1) - local_average;
            done1 = abs(end1) >= gradient;
        }
        if !done2 {
            uv2 += along * STEPS[i];
            end2 = luma_at(uv2) - local_average;
            done2 = abs(end2) >= gradient;
        }
    }
    let d1 = select(uv.y - uv1.y, uv.x - uv1.x, horizontal);
    let d2 = select(uv2.y - uv.y, uv2.x - uv.x, horizontal);
    let nearer1 = d1 < d2;
    let thickness = d1 + d2;
    let pixel_offset = -min(d1, d2) / max(thickness, 1e-6) + 0.5;
    // Only shift if the luma at the nearer end varies the way the centre does.
    let centre_smaller = m < local_average;
    let right_way = (select(end2, end1, nearer1) < 0.0) != centre_smaller;
    var offset = select(0.0, pixel_offset, right_way);
    // Sub-pixel aliasing: how far the centre is from its 3×3 average, smoothed.
    let average = (2.0 * (n + s + e + w) + nw + ne + sw + se) / 12.0;
    let sub1 = clamp(abs(average - m) / range, 0.0, 1.0);
    let sub2 = (-2.0 * sub1 + 3.0) * sub1 * sub1;
    offset = max(offset, sub2 * sub2 * params.subpixel);
    var final_uv = uv;
    if horizontal {
        final_uv.y += offset * step;
    } else {
        final_uv.x += offset * step;
    }
    return vec4<f32>(textureSampleLevel(ldr_aliased, fxaa_linear, final_uv, 0.0).rgb, center.a);
}
