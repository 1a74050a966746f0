// lib/lighting.wgsl's Blinn-Phong as a path tracer samples it (the reference's `Lobes`,
// reference/src/shading.rs): a direction drawn from a one-sample mixture of the cosine lobe
// and the Phong-power lobe about the half vector, each in proportion to its share of the
// reflectance, with the mixture's density, and the BRDF × cos there (`blinn_phong` itself).
// The including file includes lib/lighting.wgsl and lib/sampling.wgsl.

struct Lobes {
    // The surface, as lib/lighting.wgsl's `blinn_phong` takes it.
    albedo: vec3<f32>,
    metallic: f32,
    roughness: f32,
    // The specular lobe's exponent and its density constant (e + 1) / 2π.
    exponent: f32,
    density: f32,
    // probability of drawing from the specular lobe
    specular_share: f32,
};

fn lobes(albedo: vec3<f32>, metallic: f32, roughness: f32) -> Lobes {
    let diffuse = albedo * (1.0 - metallic);
    let spec_color = mix(vec3<f32>(0.04), albedo, metallic);
    let e = max(2.0 / max(roughness * roughness * roughness * roughness, 1e-4) - 2.0, 1.0);
    let d = max(diffuse.r, max(diffuse.g, diffuse.b));
    let sp = max(spec_color.r, max(spec_color.g, spec_color.b));
    return Lobes(albedo, metallic, roughness, e, (e + 1.0) / (2.0 * SAMPLING_PI), select(sp / (d + sp), 0.0, d + sp <= 0.0));
}

// BRDF × cos θ_l for light from `l` seen from `v` at shading normal `n` (lib/lighting.wgsl's
// definition), and the density of `lobes_sample` drawing `l`. Nothing is reflected towards a
// `v` below the shading normal's hemisphere (a smooth-normal surface seen at a grazing angle):
// the reference's convention (`reflects` in reference/src/shading.rs), which the raster
// passes' `blinn_phong` does not apply.
struct LobeValue {
    f: vec3<f32>,
    pdf: f32,
};

fn lobes_eval(b: Lobes, n: vec3<f32>, l: vec3<f32>, v: vec3<f32>) -> LobeValue {
    let cos_pdf = max(dot(n, l), 0.0) / SAMPLING_PI;
    let f = select(vec3<f32>(0.0), blinn_phong(n, l, v, b.albedo, b.metallic, b.roughness), dot(n, v) > 0.0);
    var out = LobeValue(f, cos_pdf);
    if b.specular_share > 0.0 {
        let half = safe_normalize(l + v, n);
        let lobe = pow(max(dot(n, half), 0.0), b.exponent);
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
