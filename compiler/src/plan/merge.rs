//! Stage `merge`: a pass that renders into exactly the attachments the pass before it
//! rendered into, and loads them, may be recorded inside that pass's render pass (the
//! pipeline switched, the attachments neither stored nor loaded again in between): ambient
//! then every light into `hdr` is one render pass. What holds for every scene is decided
//! here; an executor also compares the repetitions' subresources (a per-light instance, a
//! face), which depend on the scene's lights.

use super::{Plan, PlanPass, Work};

/// Mark each pass that may continue the previous pass's render pass (`PlanPass::continues`).
pub(super) fn mark(plan: &mut Plan) {
    for i in 1..plan.passes.len() {
        let ok = continues(&plan.passes[i - 1], &plan.passes[i]);
        plan.passes[i].continues = ok;
    }
}

/// Same attachments (resource, format, layer and level selection, in order; the same depth
/// attachment or none) and views, every one loaded by `next`; neither writes storage (no
/// barrier can separate draws inside a render pass), and `next` samples nothing `prev` renders.
fn continues(prev: &PlanPass, next: &PlanPass) -> bool {
    let (Some(a), Some(b)) = (prev.work.targets(), next.work.targets()) else {
        return false;
    };
    let same_color = a.color.len() == b.color.len()
        && a.color
            .iter()
            .zip(&b.color)
            .all(|(x, y)| (x.resource, x.format, x.layer, x.mip) == (y.resource, y.format, y.layer, y.mip) && y.load.is_load());
    let same_depth = match (&a.depth, &b.depth) {
        (None, None) => true,
        (Some(x), Some(y)) => (x.resource, x.format, x.layer, x.mip) == (y.resource, y.format, y.layer, y.mip) && y.load.is_load(),
        _ => false,
    };
    let written = prev.written();
    let renders = |w: &Work| !matches!(w, Work::Compute { .. });
    same_color
        && same_depth
        && renders(&prev.work)
        && renders(&next.work)
        && prev.work.multiview() == next.work.multiview()
        && prev.writes.is_empty()
        && next.writes.is_empty()
        && !next.reads.iter().any(|r| written.contains(&r.resource))
}
