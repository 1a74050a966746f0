// The occlusion buffer brought to the screen's size, depth-aware (seed 003 §4.6.4,
// cross-bilateral upsampling): the 4 nearest texels weigh bilinearly times 1 / (δ + relative
// difference in distance) times normal agreement, so occlusion does not bleed across depth
// edges. At full size the weights pick the pixel's own texel. Output: 1 open … 0 occluded.
#include "lib/frame.wgsl"
#include "lib/gbuffer.wgsl"

@group(2) @binding(3) var input: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(pos.xy);
    let here = load_surface(px);
    if !here.covered {
        return vec4<f32>(1.0);
    }
    let dims = vec2<f32>(textureDimensions(input, 0));
    let dist = length(here.world - frame.camera_pos.xyz);
    let f = (pos.xy) * dims / frame.resolution.xy - 0.5;
    let base = vec2<i32>(floor(f));
    let t = f - floor(f);
    let last = vec2<i32>(dims) - 1;
    var sum = 0.0;
    var total = 0.0;
    for (var i = 0; i < 4; i++) {
        let o = vec2<i32>(i & 1, i >> 1u);
        let q = clamp(base + o, vec2<i32>(0), last);
        let s = load_surface(gbuffer_pixel(q, dims));
        if !s.covered {
            continue;
        }
        let bilinear = select(1.0 - t.x, t.x, o.x == 1) * select(1.0 - t.y, t.y, o.y == 1);
        let rel = abs(length(s.world - frame.camera_pos.xyz) - dist) / max(dist, 1e-6);
        let w = bilinear / (0.01 + rel) * pow(max(dot(s.n, here.n), 0.0), 8.0);
        sum += textureLoad(input, q, 0).r * w;
        total += w;
    }
    // No neighbour on this surface (a thin edge): the nearest texel.
    let nearest = textureLoad(input, clamp(vec2<i32>(round(f)), vec2<i32>(0), last), 0).r;
    return vec4<f32>(select(nearest, sum / total, total > 1e-6));
}
