// Reading the G-buffer in lighting passes (group 2, bindings 0..2; the fat layout's 6..7).
// Two layouts (variant `gbuffer` of pipelines/deferred.ron, seed 003 §3.1, §5.2):
// - packed (`load_surface`): the normal in 2 × 16-bit fixed point (lib/normal_packing.wgsl),
//   positions reconstructed from depth and the inverse view-projection;
// - fat (`load_surface_fat`): the world-space normal as half floats and the world position
//   stored as 32-bit floats.
// Depth is read as an unfilterable float texture (texelFetch works on every backend;
// textureLoad on texture_depth_2d does not on GL).
#include "lib/math.wgsl"
#include "lib/surface.wgsl"
#include "lib/normal_packing.wgsl"

@group(2) @binding(0) var gbuf_depth: texture_2d<f32>;
@group(2) @binding(1) var gbuf_normal: texture_2d<u32>;
@group(2) @binding(2) var gbuf_albedo: texture_2d<f32>;
@group(2) @binding(6) var gbuf_position: texture_2d<f32>;
@group(2) @binding(7) var gbuf_fat_normal: texture_2d<f32>;

// World position of a pixel centre at the given depth (wgpu NDC: y up, depth 0..1).
fn world_from_depth(pixel: vec2<i32>, depth: f32) -> vec3<f32> {
    let uv = (vec2<f32>(pixel) + 0.5) * frame.resolution.zw;
    let ndc = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, depth, 1.0);
    let w = frame.inv_view_proj * ndc;
    return w.xyz / w.w;
}

// What both layouts store alike: albedo and metallic; and the direction to the camera.
fn surface_at(world: vec3<f32>, n: vec3<f32>, roughness: f32, covered: bool, pixel: vec2<i32>) -> Surface {
    let albedo = textureLoad(gbuf_albedo, pixel, 0);
    var s: Surface;
    s.covered = covered;
    s.world = world;
    s.n = n;
    // Hazard (scenes/hard/camera_in_wall.ron): a surface at the camera position.
    s.v = safe_normalize(frame.camera_pos.xyz - s.world, s.n);
    s.albedo = albedo.rgb;
    s.metallic = albedo.a;
    s.roughness = roughness;
    return s;
}

fn load_surface(pixel: vec2<i32>) -> Surface {
    let depth = textureLoad(gbuf_depth, pixel, 0).x;
    let nr = unpack_normal_roughness(textureLoad(gbuf_normal, pixel, 0));
    // The depth buffer is cleared to 1: nothing was drawn there.
    return surface_at(world_from_depth(pixel, min(depth, 0.999999)), nr.n, nr.roughness, depth < 1.0, pixel);
}

fn load_surface_fat(pixel: vec2<i32>) -> Surface {
    // w: 1 where something was drawn (the target is cleared to 0).
    let p = textureLoad(gbuf_position, pixel, 0);
    let nr = textureLoad(gbuf_fat_normal, pixel, 0);
    let n = select(vec3<f32>(0.0, 0.0, 1.0), normalize(nr.xyz), dot(nr.xyz, nr.xyz) > 1e-12);
    return surface_at(p.xyz, n, nr.w, p.w > 0.5, pixel);
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

// How far `pos` is behind the surface the camera sees in its direction (negative: in
// front); `miss` when it projects off screen, behind the camera or onto the background.
struct Probe {
    behind: f32,
    pixel: vec2<i32>,
    miss: bool,
};

fn probe(pos: vec3<f32>) -> Probe {
    var r: Probe;
    r.miss = true;
    let on = on_texture(frame.view_proj, pos);
    if !on.inside {
        return r; // off screen or behind the camera
    }
    r.pixel = vec2<i32>(on.uv * frame.resolution.xy);
    let d = textureLoad(gbuf_depth, r.pixel, 0).x;
    if d >= 1.0 {
        return r;
    }
    let seen = world_from_depth(r.pixel, d);
    r.behind = length(pos - frame.camera_pos.xyz) - length(seen - frame.camera_pos.xyz);
    r.miss = false;
    return r;
}

// Whether the segment from `a` to `b` (a receiver and a sender of indirect light) is clear in
// the depth buffer (after screen-space directional occlusion, Ritschel et al. 2009): `steps`
// points of it, shifted by `jitter` (0..1), are probed; one blocks where it lies behind the
// surface the camera sees there by more than `bias` (the two ends' own surfaces are not in the
// way) and less than `thickness` (every surface is taken to be that thick); points off screen
// or over the background block nothing.
fn segment_clear(a: vec3<f32>, b: vec3<f32>, steps: u32, thickness: f32, bias: f32, jitter: f32) -> bool {
    for (var k = 0u; k < steps; k++) {
        let q = probe(mix(a, b, (f32(k) + jitter) / f32(steps)));
        if !q.miss && q.behind > bias && q.behind < thickness {
            return false;
        }
    }
    return true;
}
