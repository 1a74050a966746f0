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
    // 1: metered and tone mapped by luminance (seed 003); 0: by the largest channel
    by_luminance: f32,
    // the log-average the exposure follows: `log_average`, or with eye adaptation
    // (`luminance_adapt.wgsl`) its value moving towards it over time
    adapted: f32,
    // `frame.time` of the frame that last adapted (eye adaptation only)
    adapted_at: f32,
};

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// What exposure meters and tone mapping compresses: by default a pixel's largest channel, so
// that a colour scaled by (mapped / value) keeps its hue and saturation and no channel leaves
// [0, 1] (a pure red's luminance is a fifth of its red: mapped by luminance, it clips, and the
// faces of a red box become one red); with `by_luminance`, luminance, as seed 003 does. The two
// agree on greys.
fn tone_value(c: vec3<f32>, by_luminance: bool) -> f32 {
    return select(max(c.r, max(c.g, c.b)), luminance(c), by_luminance);
}
