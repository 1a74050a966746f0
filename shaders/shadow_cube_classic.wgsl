// Point-light cube shadow, classic: one pass per face (seed 004 §3.5.2), 6 passes per light.
#include "lib/frame.wgsl"
#include "lib/mesh.wgsl"

@vertex
fn vs_main(v: VertexIn) -> @builtin(position) vec4<f32> {
    return lights[instance.light].face_view_proj[instance.face] * world_position(v);
}
