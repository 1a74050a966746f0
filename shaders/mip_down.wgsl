// Mip generation: each texel of a level is the mean of the 2×2 texels of the level above
// it. Use it in a pass that repeats over the levels and reads the one above:
//
//     fullscreen mips "mip_down.wgsl" {
//         per_mip 1..4
//         reads mip(chain, rep-1)
//         bind input = chain
//         color chain mip rep
//     }
//
// (Odd sizes drop the last row or column, as a 2×2 box filter does.)

@group(2) @binding(0) var input: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let q = vec2<i32>(pos.xy) * 2;
    let s = textureLoad(input, q, 0) + textureLoad(input, q + vec2<i32>(1, 0), 0)
        + textureLoad(input, q + vec2<i32>(0, 1), 0) + textureLoad(input, q + vec2<i32>(1, 1), 0);
    return s * 0.25;
}
