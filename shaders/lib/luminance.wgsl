// Scene luminance as the tone mappers and the luminance reduction see it.

// Written by the luminance pass, read by the tone mappers.
struct Luminance {
    // exp(mean(log(delta + L))) over the pixels something was drawn on
    log_average: f32,
    // the brightest such luminance (Reinhard's Lwhite before exposure)
    white: f32,
    // what HDR values are multiplied by before tone mapping: key / log_average when
    // automatic, 2^ev when manual
    exposure: f32,
    // pixels that took part (background excluded)
    covered: f32,
};

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}
