// Log-average luminance, step 1 of 2 (seed 003 §4.2, §5.4; Table 6.2 measures its cost): one
// invocation per tile of `lum.tiles` reduces its part of the HDR image to (sum of log
// luminance, brightest luminance, pixels counted). The tiles partition the image exactly,
// whatever the tile texture's rounded size: tile t covers pixels [t·size/tiles, (t+1)·size/tiles).
// Step 2 (`luminance_reduce.wgsl`) reduces the tiles in one workgroup, so the work of each
// invocation is (pixels / tiles) + (tiles / 256) instead of pixels / 256.
// Which pixels count, and how, is lib/log_average.wgsl's `metered`.
#include "lib/log_average.wgsl"

struct Params {
    by_luminance: u32,
};

@group(2) @binding(0) var hdr: texture_2d<f32>;
@group(2) @binding(1) var gbuf_depth: texture_2d<f32>;
@group(2) @binding(2) var lum_tiles: texture_storage_2d<rgba32float, write>;
@group(2) @binding(3) var<uniform> params: Params;

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
    var n = 0.0;
    for (var y = lo.y; y < hi.y; y++) {
        for (var x = lo.x; x < hi.x; x++) {
            let p = metered(hdr, gbuf_depth, vec2<u32>(x, y), params.by_luminance != 0u);
            s += p.x;
            m = max(m, p.y);
            n += p.z;
        }
    }
    textureStore(lum_tiles, id.xy, vec4<f32>(s, m, n, 0.0));
}
