// A texture added to the target as it is (the pass blends with `Add`): a separately computed,
// separately denoised term joining the HDR image.
@group(2) @binding(0) var input: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(textureLoad(input, vec2<i32>(pos.xy), 0).rgb, 0.0);
}
