// Direct light at a surface a ray found, for passes that trace rays: every light with a
// shadow ray, and the emissive surfaces by one point drawn on one emitter (next-event
// estimation, as the reference does) with a shadow ray. Includes lib/area_light.wgsl for the
// emitters (standard binding `area_lights`); the including file includes lib/ray.wgsl and
// lib/lighting.wgsl.
#include "lib/area_light.wgsl"

// The light of every emitter reflected at surface `s` (rays leave it `eps` off) towards
// `s.v`, estimated from one point: emitter `u.z` of them (uniform), uniform in its area at
// `u.xy`.
fn emitter_light(s: Surface, u: vec3<f32>, eps: f32) -> vec3<f32> {
    let count = arrayLength(&area_lights);
    let a = area_lights[min(u32(u.z * f32(count)), count - 1u)];
    if max(a.radiance.r, max(a.radiance.g, a.radiance.b)) <= 0.0 {
        return vec3<f32>(0.0);
    }
    let r = sqrt(u.x);
    let p = a.p0.xyz * (1.0 - r) + a.p1.xyz * (r * (1.0 - u.y)) + a.p2.xyz * (r * u.y);
    let e = cross(a.p1.xyz - a.p0.xyz, a.p2.xyz - a.p0.xyz);
    let area = 0.5 * length(e);
    let d = p - s.world;
    let dist2 = dot(d, d);
    if area <= 0.0 || dist2 <= eps * eps {
        return vec3<f32>(0.0);
    }
    let dist = sqrt(dist2);
    let l = d / dist;
    // Seen from its emitting side: the front (counter-clockwise) unless both sides emit.
    let cos_e = -dot(e, l) / (2.0 * area);
    if cos_e <= 0.0 && a.radiance.w == 0.0 {
        return vec3<f32>(0.0);
    }
    let f = blinn_phong(s.n, l, s.v, s.albedo, s.metallic, s.roughness);
    if max(f.r, max(f.g, f.b)) <= 0.0 {
        return vec3<f32>(0.0);
    }
    // The shadow ray stops short of the emitter's own triangle.
    let side = select(-1.0, 1.0, dot(s.n, l) >= 0.0);
    let vis = transmittance(s.world + s.n * side * eps, l, eps, dist - 2.0 * eps);
    return f * a.radiance.rgb * (abs(cos_e) * area * f32(count) / dist2) * vis;
}

// The direct light at surface `s` (every light and the emitters), reflected towards `s.v`;
// `u` draws the emitter's point. Every light is shadowed, `shadows: false` or not, as the
// reference's bounce light is.
fn direct_light(s: Surface, u: vec3<f32>) -> vec3<f32> {
    let eps = ray_offset();
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < frame.light_count; i++) {
        let l = lights[i];
        let ls = light_at(l, s.world);
        let f = blinn_phong(s.n, ls.to_light, s.v, s.albedo, s.metallic, s.roughness) * ls.radiance;
        if max(f.r, max(f.g, f.b)) > 0.0 {
            sum += f * light_reaches(l, s.world, s.n, ls.to_light, eps);
        }
    }
    return sum + emitter_light(s, u, eps);
}
