// Separable box blur: the mean of `taps` texels on each side along `dir` (in texels; edges
// clamp). One shader for both directions: each pass fixes the fields with per-pass values,
//
//     fullscreen blur_h "blur.wgsl" { reads src  bind input = src  set dir = (1, 0), taps = 3  color tmp }
//     fullscreen blur_v "blur.wgsl" { reads tmp  bind input = tmp  set dir = (0, 1), taps = 3  color out }

struct Params {
    dir: vec2<f32>,
    taps: u32,
};

@group(2) @binding(0) var input: texture_2d<f32>;
@group(2) @binding(1) var<uniform> params: Params;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let d = vec2<i32>(params.dir);
    let n = i32(params.taps);
    let last = vec2<i32>(textureDimensions(input, 0)) - 1;
    var sum = vec4<f32>(0.0);
    for (var i = -n; i <= n; i++) {
        sum += textureLoad(input, clamp(vec2<i32>(pos.xy) + d * i, vec2<i32>(0), last), 0);
    }
    return sum / f32(2 * n + 1);
}
