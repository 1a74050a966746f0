//! Stage `alias`: transient resources whose lifetimes within a frame do not overlap share
//! memory. wgpu has no placed resources, so sharing means one texture or buffer of the same
//! shape serving several resources in turn (what Granite and Frostbite call aliasing, by
//! whole objects). A resource is transient when nothing needs its content outside the frame's
//! passes that use it: not history, not external, no `data`, not an output (saved, shown), not
//! a shadow map that may go unwritten (read as cleared). Its lifetime is the span of passes, in
//! execution order, from the first that touches it to the last; one resource takes over
//! another's memory only after the other's last pass (never within one pass).
//!
//! The Plan only says who may share (`PlanResource::shares`); an executor opts in, since then
//! a skipped pass (reuse of unchanged work) or a read-back of a resource after the frame would
//! see another resource's content.

use super::{Plan, PlanPass, PlanResource, ResourceId};
use crate::layout::BindSource;

/// The passes (indices in execution order) using each resource: first and last.
fn lifetimes(plan: &Plan) -> Vec<Option<(usize, usize)>> {
    let mut life: Vec<Option<(usize, usize)>> = vec![None; plan.resources.len()];
    for (i, pass) in plan.passes.iter().enumerate() {
        for r in touched(pass) {
            if let Some(l) = life.get_mut(r.0 as usize) {
                *l = Some(l.map_or((i, i), |(a, _)| (a, i)));
            }
        }
    }
    life
}

/// Every resource a pass reads, writes, renders into or binds.
fn touched(pass: &PlanPass) -> Vec<ResourceId> {
    let mut out: Vec<ResourceId> = pass.reads.iter().map(|r| r.resource).collect();
    out.extend(pass.written());
    for e in pass.bind_groups.iter().flat_map(|g| &g.entries) {
        if let BindSource::Resource(r) | BindSource::Prev(r) = e.source {
            out.push(r);
        }
    }
    out
}

/// Why the resource's content is needed outside the frame's passes that use it (it keeps
/// its own memory); `None` for a transient one.
fn kept(plan: &Plan, id: usize, r: &PlanResource) -> Option<&'static str> {
    let id = Some(ResourceId(id as u32));
    if id == Some(plan.output) || id == plan.hdr_output {
        Some("an output")
    } else if r.history {
        Some("history")
    } else if r.external {
        Some("external")
    } else if r.data {
        Some("data")
    } else if r.casters_only {
        Some("may go unwritten")
    } else {
        None
    }
}

/// The first and last pass using a resource (indices in execution order; `None`: unused), and
/// why it keeps its own memory if it does for a reason other than its lifetime.
pub type Use = (Option<(usize, usize)>, Option<&'static str>);

/// `Use` of each resource (`plan --memory`).
pub fn report(plan: &Plan) -> Vec<Use> {
    let life = lifetimes(plan);
    plan.resources
        .iter()
        .enumerate()
        .map(|(i, r)| (life[i], kept(plan, i, r)))
        .collect()
}

/// Can `b` live in `a`'s memory: the same shape (format, extent, layers, mips; or bytes) and
/// instances.
fn same_shape(a: &PlanResource, b: &PlanResource) -> bool {
    a.shape == b.shape && a.instances == b.instances
}

/// Assign shared memory: in order of first use, each transient resource takes the memory of
/// the first earlier one of its shape whose users have all run (greedy interval colouring,
/// optimal for one shape). Sets `shares` and `physical_bytes`.
pub(super) fn assign(plan: &mut Plan) {
    let life = lifetimes(plan);
    let mut order: Vec<usize> = (0..plan.resources.len())
        .filter(|&i| life[i].is_some() && kept(plan, i, &plan.resources[i]).is_none())
        .collect();
    order.sort_by_key(|&i| life[i].map(|l| l.0));
    // Each slot: the resource that owns the memory, and the last pass using it so far.
    let mut slots: Vec<(usize, usize)> = vec![];
    let mut shares: Vec<Option<ResourceId>> = vec![None; plan.resources.len()];
    for i in order {
        let Some((first, last)) = life[i] else { continue };
        let free = slots
            .iter_mut()
            .find(|(owner, end)| *end < first && same_shape(&plan.resources[*owner], &plan.resources[i]));
        match free {
            Some(slot) => {
                shares[i] = Some(ResourceId(slot.0 as u32));
                slot.1 = last;
            }
            None => slots.push((i, last)),
        }
    }
    for (r, s) in plan.resources.iter_mut().zip(shares) {
        r.shares = s;
    }
    plan.physical_bytes = plan.resources.iter().filter(|r| r.shares.is_none()).map(|r| r.bytes).sum();
}
