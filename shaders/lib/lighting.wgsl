// Lighting helpers shared by the light passes (seed 003 §2.3, §3.2).
#include "lib/math.wgsl"

// Windowed inverse-square attenuation after seed 003 eq. 3.5, (1 - (d/r)^20) / (1 + d^2),
// with one deviation: the seed's 1 (one world unit squared, which keeps d = 0 finite) is
// (r/6)^2 here, so that the falloff is the same at every scene scale: a scene modelled in
// millimetres, with ranges and intensities scaled alike, lights like one in metres. For a
// light of range 6 (the Cornell box's) it is exactly the seed's function. Reaches 0 at r.
const ATTENUATION_SOFTNESS: f32 = 6.0;

fn attenuation(d: f32, range: f32) -> f32 {
    let r = max(range, 1e-30);
    let x = clamp(d / r, 0.0, 1.0);
    let x2 = x * x;
    let x4 = x2 * x2;
    let x20 = x4 * x4 * x4 * x4 * x4;
    let soft = r / ATTENUATION_SOFTNESS;
    return (1.0 - x20) / (soft * soft + d * d);
}

struct LightSample {
    // light arriving at the point, before shadowing
    radiance: vec3<f32>,
    // unit vector from the point to the light
    to_light: vec3<f32>,
    // distance to the light (0 for directional lights)
    dist: f32,
};

// Directional: constant radiance from -direction. Spot and point: windowed inverse-square
// attenuation; spot lights also fade over their cone. Area (an emissive mesh, colour = its
// radiance × area A): a flat Lambertian emitter seen as a point, L·A·cos θ / (d² + A/π) — the
// A/π is a disc's own term, exact on a disc's axis, so a receiver close to the emitter gets
// its finite irradiance, not a point's.
fn light_at(l: Light, world: vec3<f32>) -> LightSample {
    var ls: LightSample;
    ls.radiance = l.color.rgb;
    ls.to_light = -normalize(l.direction.xyz);
    ls.dist = 0.0;
    if l.kind != LIGHT_DIRECTIONAL {
        let d = l.position.xyz - world;
        ls.dist = length(d);
        ls.to_light = d / max(ls.dist, 1e-6);
        if l.kind == LIGHT_AREA {
            let cos_e = max(-dot(ls.to_light, normalize(l.direction.xyz)), 0.0);
            ls.radiance *= cos_e / (ls.dist * ls.dist + l.direction.w / 3.14159265);
            return ls;
        }
        ls.radiance *= attenuation(ls.dist, l.position.w);
        if l.kind == LIGHT_SPOT {
            ls.radiance *= spot_factor(l, -d);
        }
    }
    return ls;
}

// Smooth spot cone falloff between the outer and inner cone angles (cosines).
fn spot_factor(l: Light, to_surface: vec3<f32>) -> f32 {
    // Hazard (scenes/hard/point_on_surface.ron): a surface point at the light itself.
    let c = dot(safe_normalize(to_surface, l.direction.xyz), normalize(l.direction.xyz));
    return smoothstep(l.cone.y, max(l.cone.x, l.cone.y + 1e-4), c);
}

// Blinn-Phong (seed 003 §2.3.2): diffuse + specular with the half vector.
// Roughness maps to a Phong exponent; metals tint the specular with the albedo.
fn blinn_phong(n: vec3<f32>, l: vec3<f32>, v: vec3<f32>, albedo: vec3<f32>, metallic: f32, roughness: f32) -> vec3<f32> {
    let ndl = max(dot(n, l), 0.0);
    if ndl <= 0.0 {
        return vec3<f32>(0.0);
    }
    // Hazard: light and view exactly opposite (l + v = 0).
    let h = safe_normalize(l + v, n);
    let shininess = 2.0 / max(roughness * roughness * roughness * roughness, 1e-4) - 2.0;
    let spec_color = mix(vec3<f32>(0.04), albedo, metallic);
    let spec = pow(max(dot(n, h), 0.0), max(shininess, 1.0)) * (shininess + 8.0) / 25.132741;
    let diffuse = albedo * (1.0 - metallic);
    return (diffuse / 3.14159265 + spec_color * spec) * ndl;
}
