// Fragment lists: each pixel's list sorted by depth (insertion sort of at most MAX_LAYERS
// fragments; past that the farthest are left out) and blended back to front over the opaque
// image (lib/composite.wgsl).
#include "lib/frame.wgsl"
#include "lib/oit.wgsl"
#include "lib/composite.wgsl"

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
    var acc = composite_start();
    for (var i = 0u; i < n; i++) {
        acc = composite_behind(acc, color[i]);
    }
    let out = composite_output(acc);
    if out.a <= 0.0 {
        discard;
    }
    return out;
}
