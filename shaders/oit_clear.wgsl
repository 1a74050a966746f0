// Fragment lists: empty every pixel's list and the pool before the blended surfaces are drawn.
#include "lib/frame.wgsl"
#include "lib/oit.wgsl"

@group(2) @binding(1) var<storage, read_write> oit_heads: array<u32>;
@group(2) @binding(3) var<storage, read_write> oit_counter: OitCounter;

@compute @workgroup_size(8, 8, 1)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    if all(id.xy == vec2<u32>(0u)) {
        atomicStore(&oit_counter.taken, 0u);
        atomicStore(&oit_counter.dropped, 0u);
    }
    if any(vec2<f32>(id.xy) >= frame.resolution.xy) {
        return;
    }
    let i = pixel_index(id.xy);
    if i < arrayLength(&oit_heads) {
        oit_heads[i] = NONE;
    }
}
