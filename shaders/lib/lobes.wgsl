// lib/lighting.wgsl's Blinn-Phong as a path tracer samples it (the reference's `Lobes`,
// reference/src/shading.rs): BRDF × cos, and a direction drawn from a one-sample mixture of
// the cosine lobe and the Phong-power lobe about the half vector, each in proportion to its
// share of the reflectance, with the mixture's density. The including file includes
// lib/sampling.wgsl.

struct Lobes {
    // diffuse reflectance / π
    diffuse: vec3<f32>,
    // specular colour × (s + 8) / 8π
    specular: vec3<f32>,
    exponent: f32,
    // (e + 1) / 2π: the power lobe's density constant
    density: f32,
    // probability of drawing from the specular lobe
    specular_share: f32,
};

fn lobes(albedo: vec3<f32>, metallic: f32, roughness: f32) -> Lobes {
    let diffuse = albedo * (1.0 - metallic);
    let spec_color = mix(vec3<f32>(0.04), albedo, metallic);
    let s = 2.0 / max(roughness * roughness * roughness * roughness, 1e-4) - 2.0;
    let e = max(s, 1.0);
    let d = max(diffuse.r, max(diffuse.g, diffuse.b));
    let sp = max(spec_color.r, max(spec_color.g, spec_color.b));
    return Lobes(diffuse / SAMPLING_PI, spec_color * ((s + 8.0) / 25.132741), e, (e + 1.0) / (2.0 * SAMPLING_PI), select(sp / (d + sp), 0.0, d + sp <= 0.0));
}

// BRDF × cos θ_l for light from `l` seen from `v` at shading normal `n`, and the density of
// `lobes_sample` drawing `l`.
struct LobeValue {
    f: vec3<f32>,
    pdf: f32,
};

fn lobes_eval(b: Lobes, n: vec3<f32>, l: vec3<f32>, v: vec3<f32>) -> LobeValue {
    let ndl = max(dot(n, l), 0.0);
    let cos_pdf = ndl / SAMPLING_PI;
    let half = safe_normalize(l + v, n);
    let lobe = pow(max(dot(n, half), 0.0), b.exponent);
    var out = LobeValue(vec3<f32>(0.0), cos_pdf);
    if ndl > 0.0 {
        out.f = (b.diffuse + b.specular * lobe) * ndl;
    }
    if b.specular_share > 0.0 {
        let spec = b.density * lobe / (4.0 * max(abs(dot(v, half)), 1e-6));
        out.pdf = (1.0 - b.specular_share) * cos_pdf + b.specular_share * spec;
    }
    return out;
}

// A direction to continue a path in, its weight BRDF × cos / pdf (0 below the geometric
// surface `ng`) and its density.
struct LobeSample {
    l: vec3<f32>,
    weight: vec3<f32>,
    pdf: f32,
};

fn lobes_sample(b: Lobes, n: vec3<f32>, ng: vec3<f32>, v: vec3<f32>, u: vec2<f32>, choose: f32) -> LobeSample {
    var l: vec3<f32>;
    if choose < b.specular_share {
        let half = power_lobe(n, b.exponent, u);
        l = safe_normalize(2.0 * dot(v, half) * half - v, vec3<f32>(0.0));
    } else {
        l = cosine_direction(n, u);
    }
    let e = lobes_eval(b, n, l, v);
    if dot(ng, l) <= 0.0 || e.pdf <= 0.0 {
        return LobeSample(l, vec3<f32>(0.0), e.pdf);
    }
    return LobeSample(l, e.f / e.pdf, e.pdf);
}
