// Box blur (seed 000 §6.2.3): the mean of the (2 · size + 1)² texels around each one (edges
// clamp). Used for the occlusion buffer.
struct Params {
    size: u32,
};

@group(2) @binding(0) var input: texture_2d<f32>;
@group(2) @binding(1) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let n = i32(params.size);
    let last = vec2<i32>(textureDimensions(input, 0)) - 1;
    var sum = vec4<f32>(0.0);
    for (var y = -n; y <= n; y++) {
        for (var x = -n; x <= n; x++) {
            sum += textureLoad(input, clamp(vec2<i32>(pos.xy) + vec2<i32>(x, y), vec2<i32>(0), last), 0);
        }
    }
    return sum / f32((2 * n + 1) * (2 * n + 1));
}
