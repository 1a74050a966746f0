// Reading the G-buffer in lighting passes (group 2, bindings 0..2). Positions come from
// depth and the inverse view-projection. Depth is read as an unfilterable float texture
// (texelFetch works on every backend; textureLoad on texture_depth_2d does not on GL).
#include "lib/math.wgsl"
#include "lib/surface.wgsl"

@group(2) @binding(0) var gbuf_depth: texture_2d<f32>;
@group(2) @binding(1) var gbuf_normal: texture_2d<f32>;
@group(2) @binding(2) var gbuf_albedo: texture_2d<f32>;

// World position of a pixel centre at the given depth (wgpu NDC: y up, depth 0..1).
fn world_from_depth(pixel: vec2<i32>, depth: f32) -> vec3<f32> {
    let uv = (vec2<f32>(pixel) + 0.5) * frame.resolution.zw;
    let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, depth, 1.0);
    let w = frame.inv_view_proj * ndc;
    return w.xyz / w.w;
}

fn load_surface(pixel: vec2<i32>) -> Surface {
    let depth = textureLoad(gbuf_depth, pixel, 0).x;
    let nr = textureLoad(gbuf_normal, pixel, 0);
    let albedo = textureLoad(gbuf_albedo, pixel, 0);
    var s: Surface;
    // The depth buffer is cleared to 1: nothing was drawn there.
    s.covered = depth < 1.0;
    s.world = world_from_depth(pixel, min(depth, 0.999999));
    s.n = select(vec3<f32>(0.0, 0.0, 1.0), normalize(nr.xyz), dot(nr.xyz, nr.xyz) > 1e-12);
    // Hazard (scenes/hard/camera_in_wall.ron): a surface at the camera position.
    s.v = safe_normalize(frame.camera_pos.xyz - s.world, s.n);
    s.albedo = albedo.rgb;
    s.metallic = albedo.a;
    s.roughness = nr.w;
    return s;
}

// The G-buffer pixel under texel `q` of a buffer of `dims` texels covering the screen (an
// occlusion buffer at w/2 × h/2 reads the surface at the centre of its 2×2 block).
fn gbuffer_pixel(q: vec2<i32>, dims: vec2<f32>) -> vec2<i32> {
    let p = vec2<i32>((vec2<f32>(q) + 0.5) * frame.resolution.xy / max(dims, vec2<f32>(1.0)));
    return clamp(p, vec2<i32>(0), vec2<i32>(frame.resolution.xy) - 1);
}

// The G-buffer pixel under fragment `frag` of this pass's target (which may be smaller than
// the screen).
fn target_gbuffer_pixel(frag: vec2<f32>) -> vec2<i32> {
    return gbuffer_pixel(vec2<i32>(frag), instance.target_size.xy);
}
