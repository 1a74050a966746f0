// Log-average luminance, step 2 of 2, shared by `luminance_reduce.wgsl` and
// `luminance_adapt.wgsl`: one workgroup of 256 invocations sums the tiles step 1
// (`luminance_tiles.wgsl`) wrote, striding over them, then in a tree.

const TILE_GROUP: u32 = 256u;
var<workgroup> tile_sum: array<f32, TILE_GROUP>;
var<workgroup> tile_max: array<f32, TILE_GROUP>;
var<workgroup> tile_count: array<f32, TILE_GROUP>;

// (sum of log luminance, brightest luminance, pixels counted) over every tile, in every
// invocation `idx` of the workgroup.
fn reduce_tiles(tiles: texture_2d<f32>, idx: u32) -> vec3<f32> {
    let size = textureDimensions(tiles);
    let count = size.x * size.y;
    var acc = vec3<f32>(0.0);
    for (var i = idx; i < count; i += TILE_GROUP) {
        let t = textureLoad(tiles, vec2<u32>(i % size.x, i / size.x), 0);
        acc = vec3<f32>(acc.x + t.x, max(acc.y, t.y), acc.z + t.z);
    }
    tile_sum[idx] = acc.x;
    tile_max[idx] = acc.y;
    tile_count[idx] = acc.z;
    workgroupBarrier();
    for (var stride = TILE_GROUP / 2u; stride > 0u; stride /= 2u) {
        if idx < stride {
            tile_sum[idx] += tile_sum[idx + stride];
            tile_max[idx] = max(tile_max[idx], tile_max[idx + stride]);
            tile_count[idx] += tile_count[idx + stride];
        }
        workgroupBarrier();
    }
    return vec3<f32>(tile_sum[0], tile_max[0], tile_count[0]);
}

// exp(mean(log(delta + L))) of a reduction, `delta` where nothing was counted.
fn log_average_of(r: vec3<f32>, delta: f32) -> f32 {
    return select(delta, exp(r.x / max(r.z, 1.0)), r.z > 0.0);
}
