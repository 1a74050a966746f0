// Point-light cube shadow in a single pass with multiview (seed 004 §4.4.4): the
// attachment is the 6-layer cube seen as a 2D array, view i renders face i.
#include "lib/frame.wgsl"
#include "lib/mesh.wgsl"

@vertex
fn vs_main(v: VertexIn, @builtin(view_index) view: u32) -> @builtin(position) vec4<f32> {
    return lights[instance.light].face_view_proj[view] * world_position(v);
}
