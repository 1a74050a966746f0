// Reading the G-buffer in lighting passes (group 2, bindings 0..2).

@group(2) @binding(0) var gbuf_position: texture_2d<f32>;
@group(2) @binding(1) var gbuf_normal: texture_2d<f32>;
@group(2) @binding(2) var gbuf_albedo: texture_2d<f32>;

struct Surface {
    world: vec3<f32>,
    n: vec3<f32>,
    // direction to the camera
    v: vec3<f32>,
    albedo: vec3<f32>,
    metallic: f32,
    roughness: f32,
    // false for background pixels (nothing was drawn there)
    covered: bool,
};

fn load_surface(pixel: vec2<i32>) -> Surface {
    let position = textureLoad(gbuf_position, pixel, 0);
    let nr = textureLoad(gbuf_normal, pixel, 0);
    let albedo = textureLoad(gbuf_albedo, pixel, 0);
    var s: Surface;
    s.covered = position.w != 0.0;
    s.world = position.xyz;
    s.n = select(vec3<f32>(0.0, 0.0, 1.0), normalize(nr.xyz), dot(nr.xyz, nr.xyz) > 1e-12);
    s.v = normalize(frame.camera_pos.xyz - position.xyz);
    s.albedo = albedo.rgb;
    s.metallic = albedo.a;
    s.roughness = nr.w;
    return s;
}

// A point light's unshadowed contribution; `to_light` and `dist` are returned for the shadow test.
fn point_light_radiance(l: Light, s: Surface, to_light: ptr<function, vec3<f32>>, dist: ptr<function, f32>) -> vec3<f32> {
    let d = l.position.xyz - s.world;
    *dist = length(d);
    *to_light = d / max(*dist, 1e-6);
    return blinn_phong(s.n, *to_light, s.v, s.albedo, s.metallic, s.roughness) * l.color.rgb * attenuation(*dist, l.position.w);
}
