// Per-triangle tables: records of 16-byte texels in a `texture_2d_array<u32>`, row after row,
// layer after layer (the runtime's standard `triangles`, `hit_triangles` and `hit_corners`).
// A texture holds tens of millions of triangles where a storage binding stops at the device's
// binding size (128 MiB on many).

// Texel `t` of `table`.
fn table_texel(table: texture_2d_array<u32>, t: u32) -> vec4<u32> {
    let size = textureDimensions(table);
    let per_layer = size.x * size.y;
    let at = t % per_layer;
    return textureLoad(table, vec2<u32>(at % size.x, at / size.x), t / per_layer, 0);
}
