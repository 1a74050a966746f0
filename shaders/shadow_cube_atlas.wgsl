// Point-light cube shadow in a single pass by instancing (seed 004 §4.4.5): each mesh is
// drawn 6 times, instance i goes to tile (i % 3, i / 3) of a 3×2 atlas, and clip
// distances cut every copy to its face's frustum so nothing spills into a neighbour tile.
enable clip_distances;
#include "lib/frame.wgsl"
#include "lib/mesh.wgsl"

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @builtin(clip_distances) clip_distances: array<f32, 4>,
};

@vertex
fn vs_main(v: VertexIn, @builtin(instance_index) face: u32) -> VsOut {
    let c = lights[instance.light].face_view_proj[face] * world_position(v);
    var out: VsOut;
    // Inside the face frustum: -w <= x <= w and -w <= y <= w.
    out.clip_distances[0] = c.w + c.x;
    out.clip_distances[1] = c.w - c.x;
    out.clip_distances[2] = c.w + c.y;
    out.clip_distances[3] = c.w - c.y;
    // Squeeze NDC [-1, 1] into the tile: x into a third, y into a half of the atlas.
    let tile = vec2<f32>(f32(face % 3u), f32(face / 3u));
    let ndc_scale = vec2<f32>(1.0 / 3.0, 1.0 / 2.0);
    let offset = vec2<f32>(-1.0 + (2.0 * tile.x + 1.0) / 3.0, 1.0 - (2.0 * tile.y + 1.0) / 2.0);
    out.clip = vec4<f32>(c.xy * ndc_scale + offset * c.w, c.z, c.w);
    return out;
}
