// Scene luminance as the tone mappers and the luminance reduction see it.

// Written by the luminance pass, read by the tone mappers.
struct Luminance {
    log_average: f32,
    white: f32,
    _pad0: f32,
    _pad1: f32,
};

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}
