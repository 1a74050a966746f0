// Reading a light's reflective shadow map (seed 000 §4.2.2): what the light sees along its view
// through a world position.

// The surface position the light's RSM holds where `p` projects (w: 0 where nothing was drawn,
// or where `p` is behind the light or off the map).
fn rsm_seen(rsm_position: texture_2d<f32>, l: Light, p: vec3<f32>) -> vec4<f32> {
    let on = on_texture(l.view_proj, p);
    if !on.inside {
        return vec4<f32>(0.0);
    }
    let dims = vec2<f32>(textureDimensions(rsm_position, 0));
    return textureLoad(rsm_position, vec2<i32>(on.uv * dims), 0);
}
