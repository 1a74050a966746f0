// Standard per-frame bindings the runtime provides to every pass (group 0).
// A shader binds only what it uses; unused declarations cost nothing.

const LIGHT_DIRECTIONAL: u32 = 0u;
const LIGHT_SPOT: u32 = 1u;
const LIGHT_POINT: u32 = 2u;
// An emissive mesh as one light (after the punctual ones, beyond `light_count`): only passes
// that run per `Area` light see it (an RSM of the light the emitter sends out).
const LIGHT_AREA: u32 = 3u;

struct Frame {
    view: mat4x4<f32>,
    // Jittered when the pipeline asks for `jitter` (then so are view_proj and its inverse).
    proj: mat4x4<f32>,
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    // The previous frame's view_proj and its inverse (jittered as that frame was); in the
    // first frame, this frame's. Reprojection: prev_view_proj * world position.
    prev_view_proj: mat4x4<f32>,
    prev_inv_view_proj: mat4x4<f32>,
    // xyz: camera position (world); w: unused
    camera_pos: vec4<f32>,
    // x, y: the output (viewport) size in pixels — the Plan's resolution; z, w: reciprocals.
    // A pass rendering at another size (e.g. `Viewport(0.5)`) finds its own in `instance.target_size`.
    resolution: vec4<f32>,
    // x, y: this frame's sub-pixel jitter in pixels (x right, y down; within ±0.5, Halton
    // 2, 3 over 16 frames); z, w: the previous frame's. All zero without `jitter`.
    jitter: vec4<f32>,
    // Seconds since the start (lights and cameras animate with it).
    time: f32,
    // Frames rendered before this one (0 in the first).
    frame_index: u32,
    light_count: u32,
    // The radius of the scene's bounding sphere: what scale-free lengths are fractions of.
    scene_radius: f32,
};

struct Light {
    // rgb: colour × intensity (linear); w: unused
    color: vec4<f32>,
    // xyz: position (spot, point); w: range (windowed attenuation, seed 003 eq. 3.5)
    position: vec4<f32>,
    // xyz: direction the light points (directional, spot; an area light's normal); w: an area
    // light's area
    direction: vec4<f32>,
    // x: cos(inner cone), y: cos(outer cone), z: shadow near plane, w: shadow far plane
    cone: vec4<f32>,
    kind: u32,
    casts_shadows: u32,
    _pad0: u32,
    _pad1: u32,
    // world -> shadow clip space (directional: orthographic, spot: perspective)
    view_proj: mat4x4<f32>,
    // point lights: world -> clip space of each cube face (+X, -X, +Y, -Y, +Z, -Z)
    face_view_proj: array<mat4x4<f32>, 6>,
};

// Which repetition of a per-light / per-face / per-mip pass is running.
struct Instance {
    light: u32,
    face: u32,
    view_count: u32,
    // The mip level this repetition of a `per_mip` pass renders (else 0).
    mip: u32,
    // x, y: this pass's target size in pixels (its first attachment, or the texture a compute
    // dispatch is sized from; else the output size); z, w: their reciprocals
    target_size: vec4<f32>,
    // Which run of a `repeat` pass this is, from 0 (else 0).
    repetition: u32,
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> instance: Instance;
@group(0) @binding(2) var<storage, read> lights: array<Light>;

// The unit of a pass's lengths (AO radii, SSR steps, ...): the scene's bounding radius, so
// that a scene looks the same at any scale; world units where `world` (parameter
// `lengths.world`) is set.
fn length_unit(world: u32) -> f32 {
    return select(frame.scene_radius, 1.0, world != 0u);
}
