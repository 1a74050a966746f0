// Forward shading (seed 003 §2.4, §5.1): the surface under a mesh fragment, read from its
// material instead of a G-buffer. Needs lib/frame.wgsl included first.
#include "lib/material.wgsl"
#include "lib/surface.wgsl"

// Cut-outs (alphaMode MASK) are discarded where the G-buffer pass discards them.
fn cut_out(m: MaterialSample) -> bool {
    return m.base.a < material.alpha_cutoff;
}

fn material_surface(in: VsOut, m: MaterialSample) -> Surface {
    var s: Surface;
    s.world = in.world_pos;
    s.n = m.n;
    // Hazard: a surface at the camera position.
    s.v = safe_normalize(frame.camera_pos.xyz - in.world_pos, m.n);
    s.albedo = m.base.rgb;
    s.metallic = m.metallic;
    s.roughness = m.roughness;
    s.covered = true;
    return s;
}
