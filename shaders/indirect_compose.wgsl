// Indirect diffuse light added to the HDR image: the irradiance gathered from the RSMs times
// the surface's diffuse albedo (Lambert: albedo / π, the 1/π applied when gathering).
@group(2) @binding(0) var gbuf_albedo: texture_2d<f32>;
@group(2) @binding(1) var gi_indirect: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pos.xy);
    let a = textureLoad(gbuf_albedo, p, 0);
    return vec4<f32>(textureLoad(gi_indirect, p, 0).rgb * a.rgb * (1.0 - a.a), 0.0);
}
