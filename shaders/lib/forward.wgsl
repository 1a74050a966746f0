// Forward shading (seed 003 §2.4, §5.1): the surface under a mesh fragment, read from its
// material instead of a G-buffer. Needs lib/frame.wgsl included first.
#include "lib/material.wgsl"
#include "lib/surface.wgsl"
#include "lib/lighting.wgsl"

fn material_surface(in: VsOut, m: MaterialSample) -> Surface {
    var s: Surface;
    s.world = in.world_pos;
    s.n = m.n;
    // Hazard: a surface at the camera position.
    s.v = safe_normalize(frame.camera_pos.xyz - in.world_pos, m.n);
    s.albedo = m.base.rgb;
    s.metallic = m.metallic;
    s.roughness = m.roughness;
    s.covered = true;
    return s;
}

// Ambient light (`ambient`, linear RGB) and emission, as the deferred `ambient` pass adds them.
fn ambient_term(m: MaterialSample, ambient: vec3<f32>) -> vec3<f32> {
    return m.base.rgb * ambient * (1.0 - m.metallic) * m.occlusion + m.emissive;
}

// Every light of the storage buffer reflected at `s`, unshadowed (single-pass lighting).
fn all_lights(s: Surface) -> vec3<f32> {
    var c = vec3<f32>(0.0);
    for (var i = 0u; i < frame.light_count; i++) {
        let ls = light_at(lights[i], s.world);
        c += blinn_phong(s.n, ls.to_light, s.v, s.albedo, s.metallic, s.roughness) * ls.radiance;
    }
    return c;
}
