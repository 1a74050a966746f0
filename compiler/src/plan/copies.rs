//! Plan stage `copies`: which copy (instance) of each per-light resource a repetition binds
//! or renders into. A per-light resource has one copy per light of its kinds (per casting
//! light for a map only shadow passes write); a light's copy is its rank among those lights.
//! A light with none (it casts no shadow) binds copy 0, which its shader does not read.

use super::{Plan, PlanCopy, PlanResource};
use crate::ir::LightKind;

/// Fill every repetition's `copies` for the scene's lights in light-array order, each with
/// whether it casts shadows.
pub fn assign(plan: &mut Plan, lights: &[(LightKind, bool)]) {
    let resources = &plan.resources;
    for pass in &mut plan.passes {
        let used: Vec<_> = pass
            .used()
            .into_iter()
            .filter(|r| !resources[r.0 as usize].per_light.is_empty())
            .collect();
        for rep in &mut pass.reps {
            let Some(light) = rep.light else { continue };
            rep.copies = used
                .iter()
                .map(|&resource| PlanCopy {
                    resource,
                    instance: copy_of(&resources[resource.0 as usize], lights, light),
                })
                .collect();
        }
    }
}

/// Light `light`'s copy of `r`: its rank among the lights `r` has copies for, else 0.
fn copy_of(r: &PlanResource, lights: &[(LightKind, bool)], light: u32) -> u32 {
    lights
        .iter()
        .enumerate()
        .filter(|(_, (kind, casts))| r.per_light.contains(kind) && (*casts || !r.casters_only))
        .position(|(i, _)| i as u32 == light)
        .unwrap_or(0) as u32
}
