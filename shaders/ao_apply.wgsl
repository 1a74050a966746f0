// Ambient occlusion applied to the HDR image right after the ambient pass cleared it (so the
// light passes that follow are not occluded): the target's `blend: Multiply` scales the
// ambient term by the occlusion. (Emission, which the ambient pass also writes, is scaled too:
// a deviation from "AO multiplies the ambient term" that only glowing surfaces show.)
@group(2) @binding(0) var ao_full: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let a = textureLoad(ao_full, vec2<i32>(pos.xy), 0).r;
    return vec4<f32>(a, a, a, 1.0);
}
