// Blending layers of blended surfaces sorted front to back (fragment lists, depth peeling):
// the radiance that reaches the eye and the transmittance left behind them. What a resolve
// pass writes, blended "over" the opaque image (src·α + dst·(1 − α)), is the layers' colour and
// their combined opacity 1 − Π(1 − αᵢ): the back-to-front composite.

struct Composite {
    radiance: vec3<f32>,
    through: f32,
};

fn composite_start() -> Composite {
    return Composite(vec3<f32>(0.0), 1.0);
}

// `c` (linear colour, opacity) behind what `acc` holds.
fn composite_behind(acc: Composite, c: vec4<f32>) -> Composite {
    return Composite(acc.radiance + acc.through * c.a * c.rgb, acc.through * (1.0 - c.a));
}

// The colour and opacity to blend over the image behind; opacity 0 where no layer covers.
fn composite_output(acc: Composite) -> vec4<f32> {
    let alpha = 1.0 - acc.through;
    return vec4<f32>(acc.radiance / max(alpha, 1e-20), alpha);
}
