// Log-average luminance, step 1 of 2 (seed 003 §4.2, §5.4; Table 6.2 measures its cost): one
// invocation per tile of `lum.tiles` reduces its part of the HDR image to (sum of log
// luminance, brightest luminance, pixels counted). The tiles partition the image exactly,
// whatever the tile texture's rounded size: tile t covers pixels [t·size/tiles, (t+1)·size/tiles).
// Step 2 (`luminance_reduce.wgsl`) reduces the tiles in one workgroup, so the work of each
// invocation is (pixels / tiles) + (tiles / 256) instead of pixels / 256.
// Which pixels count, and how a pixel's luminance is read, is the single-workgroup
// `luminance.wgsl`'s rule: drawn pixels only (depth < 1), the tone value of lib/luminance.wgsl,
// non-finite values as 0.
#include "lib/luminance.wgsl"

struct Params {
    by_luminance: u32,
};

@group(2) @binding(0) var hdr: texture_2d<f32>;
@group(2) @binding(1) var gbuf_depth: texture_2d<f32>;
@group(2) @binding(2) var lum_tiles: texture_storage_2d<rgba32float, write>;
@group(2) @binding(3) var<uniform> params: Params;

const DELTA: f32 = 1e-4;

@compute @workgroup_size(8, 8, 1)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let tiles = textureDimensions(lum_tiles);
    if id.x >= tiles.x || id.y >= tiles.y {
        return;
    }
    let size = textureDimensions(hdr);
    let lo = id.xy * size / tiles;
    let hi = (id.xy + 1u) * size / tiles;
    var s = 0.0;
    var m = 0.0;
    var n = 0u;
    for (var y = lo.y; y < hi.y; y++) {
        for (var x = lo.x; x < hi.x; x++) {
            let pixel = vec2<u32>(x, y);
            if textureLoad(gbuf_depth, pixel, 0).x >= 1.0 {
                continue; // background: nothing drawn here
            }
            var l = tone_value(textureLoad(hdr, pixel, 0).rgb, params.by_luminance != 0u);
            l = select(0.0, l, l >= 0.0 && l < 65504.0);
            s += log(DELTA + l);
            m = max(m, l);
            n += 1u;
        }
    }
    textureStore(lum_tiles, id.xy, vec4<f32>(s, m, f32(n), 0.0));
}
