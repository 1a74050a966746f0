// Shadow map of a directional (orthographic) or spot (perspective) light: depth only.
// The light's view-projection comes from the light array (built by the runtime with a
// safe up vector, so a light pointing straight down is well defined).
#include "lib/frame.wgsl"
#include "lib/mesh.wgsl"

@vertex
fn vs_main(v: VertexIn) -> @builtin(position) vec4<f32> {
    return lights[instance.light].view_proj * world_position(v);
}
