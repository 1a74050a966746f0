// Writes zero: a pass that only clears its targets (e.g. before per-light passes add to them).
@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return vec4<f32>(0.0);
}
