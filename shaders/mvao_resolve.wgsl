// Multi-view AO, last step: the weighted accessibilities of the views divided by their total
// weight (seed 000 §4.3.2). No view with weight (a surface facing away from all): open.
@group(2) @binding(0) var ao_views: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let v = textureLoad(ao_views, vec2<i32>(pos.xy), 0);
    return vec4<f32>(select(1.0, clamp(v.x / v.y, 0.0, 1.0), v.y > 1e-4));
}
