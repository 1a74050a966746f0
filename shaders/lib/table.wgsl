// Per-triangle tables: records of 16-byte texels in a `texture_2d_array<u32>`, row after row,
// layer after layer (the runtime's standard `triangles`, `hit_triangles`, `hit_emitters`,
// `hit_corners` and `hit_maps`). A texture holds tens of millions of triangles where a storage
// binding stops at the device's binding size (128 MiB on many).

// Texel `t` of `table`, whose width and rows per layer are powers of two: its place by shifts
// and masks (integer division costs most where shaders run in SIMD lanes on a CPU).
fn table_texel(table: texture_2d_array<u32>, t: u32) -> vec4<u32> {
    let size = textureDimensions(table);
    let row_bits = firstTrailingBit(size.x);
    let layer_bits = row_bits + firstTrailingBit(size.y);
    let at = vec2<u32>(t & (size.x - 1u), (t >> row_bits) & (size.y - 1u));
    return textureLoad(table, at, t >> layer_bits, 0);
}

// Corner `k` of triangle `i` of a table of world-space corners, 3 texels (`vec4`, w = 1) per
// triangle: the standard `triangles`, for vertex pulling.
fn table_corner(table: texture_2d_array<u32>, i: u32, k: u32) -> vec3<f32> {
    return bitcast<vec4<f32>>(table_texel(table, 3u * i + k)).xyz;
}
