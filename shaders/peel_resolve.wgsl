// Depth peeling: the peeled layers (layer 0 the nearest) blended back to front over the opaque
// image (lib/composite.wgsl); only the `peel.layers` this frame peeled.
#include "lib/frame.wgsl"
#include "lib/composite.wgsl"

struct Params {
    layers: i32,
};

@group(2) @binding(0) var peel_color: texture_2d_array<f32>;
@group(2) @binding(1) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(pos.xy);
    var acc = composite_start();
    for (var i = 0; i < min(params.layers, i32(textureNumLayers(peel_color))); i++) {
        acc = composite_behind(acc, textureLoad(peel_color, px, i, 0));
    }
    let out = composite_output(acc);
    if out.a <= 0.0 {
        discard;
    }
    return out;
}
