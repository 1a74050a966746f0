// Fragment lists: each pixel's list sorted by depth (insertion sort of at most MAX_LAYERS
// fragments; past that the farthest are left out) and blended back to front over the opaque
// image. Output, blended "over" the HDR image: the layers' colour and their combined opacity
// 1 − Π(1 − αᵢ), so that src·α + dst·(1 − α) is the back-to-front composite.
#include "lib/frame.wgsl"
#include "lib/oit.wgsl"

const MAX_LAYERS: u32 = 16u;

@group(2) @binding(1) var<storage, read> oit_heads: array<u32>;
@group(2) @binding(2) var<storage, read> oit_nodes: array<OitNode>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    var depth: array<f32, MAX_LAYERS>;
    var color: array<vec4<f32>, MAX_LAYERS>;
    var n = 0u;
    let pixel = pixel_index(vec2<u32>(pos.xy));
    var node = select(NONE, oit_heads[pixel], pixel < arrayLength(&oit_heads));
    // Bounded: a list is never longer than the pool.
    for (var walked = 0u; node < arrayLength(&oit_nodes) && walked < arrayLength(&oit_nodes); walked++) {
        let f = oit_nodes[node];
        let c = unpack_color(f.color);
        let d = bitcast<f32>(f.depth);
        // Insertion, nearest first; a full list keeps the MAX_LAYERS nearest.
        var i = min(n, MAX_LAYERS - 1u);
        if n < MAX_LAYERS || d < depth[i] {
            while i > 0u && depth[i - 1u] > d {
                depth[i] = depth[i - 1u];
                color[i] = color[i - 1u];
                i--;
            }
            depth[i] = d;
            color[i] = c;
            n = min(n + 1u, MAX_LAYERS);
        }
        node = f.next;
    }
    // Front to back: radiance reaching the eye and the transmittance left.
    var radiance = vec3<f32>(0.0);
    var through = 1.0;
    for (var i = 0u; i < n; i++) {
        radiance += through * color[i].a * color[i].rgb;
        through *= 1.0 - color[i].a;
    }
    let alpha = 1.0 - through;
    if alpha <= 0.0 {
        discard;
    }
    return vec4<f32>(radiance / alpha, alpha);
}
