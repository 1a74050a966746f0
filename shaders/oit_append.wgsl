// Fragment lists: each blended fragment in front of the opaque scene (depth tested, not
// written) is shaded and linked into its pixel's list. Past the pool's end a fragment is
// dropped and counted (`oit.counter.dropped`); nothing is written out of bounds.
#include "lib/blended.wgsl"
#include "lib/oit.wgsl"

@group(2) @binding(1) var<storage, read_write> oit_heads: array<atomic<u32>>;
@group(2) @binding(2) var<storage, read_write> oit_nodes: array<OitNode>;
@group(2) @binding(3) var<storage, read_write> oit_counter: OitCounter;

@fragment
fn fs_append(in: VsOut, @builtin(front_facing) facing: bool) {
    let b = shade_blended(in, facing);
    let pixel = pixel_index(vec2<u32>(in.clip.xy));
    if b.hidden || pixel >= arrayLength(&oit_heads) {
        return;
    }
    let node = atomicAdd(&oit_counter.taken, 1u);
    if node >= arrayLength(&oit_nodes) {
        atomicAdd(&oit_counter.dropped, 1u);
        return;
    }
    oit_nodes[node].color = pack_color(b.color);
    oit_nodes[node].depth = bitcast<u32>(in.clip.z);
    oit_nodes[node].next = atomicExchange(&oit_heads[pixel], node);
}
