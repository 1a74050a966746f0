//! Stage `diff`: how two Plans differ in structure — variants, parameter values, passes kept
//! (added, removed, changed fact by fact), culling and its reasons, resources and memory.
//! What `lightbench diff` reports before (or without) rendering anything.

use super::explain::{pass_facts, resource_fact};
use super::Plan;
use serde::Serialize;
use std::collections::BTreeMap;

/// One named thing with a value on each side (`None`: absent there).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Change {
    pub name: String,
    pub a: Option<String>,
    pub b: Option<String>,
}

/// A pass both Plans keep, with the facts only one side has (shader, bindings, attachments,
/// repetitions, blocks: see `pass_facts`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PassChange {
    pub name: String,
    pub only_a: Vec<String>,
    pub only_b: Vec<String>,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PlanDiff {
    pub variants: Vec<Change>,
    /// Parameters whose value (default, preset or override) differs.
    pub params: Vec<Change>,
    /// Kept by B only (with its facts), by A only.
    pub passes_added: Vec<Change>,
    pub passes_removed: Vec<Change>,
    pub passes_changed: Vec<PassChange>,
    /// Both keep the same passes but run them in another order.
    pub order_changed: bool,
    /// Passes culled on one side only, with the reason (a: A's).
    pub culled: Vec<Change>,
    pub resources: Vec<Change>,
    pub memory: (u64, u64),
}

impl PlanDiff {
    /// Nothing in the structure differs (memory follows from the rest).
    pub fn is_empty(&self) -> bool {
        self.variants.is_empty()
            && self.params.is_empty()
            && self.passes_added.is_empty()
            && self.passes_removed.is_empty()
            && self.passes_changed.is_empty()
            && !self.order_changed
            && self.culled.is_empty()
            && self.resources.is_empty()
    }
}

/// Pairs of `name -> value` maps as changes, in name order, leaving out what is equal.
fn changes(a: BTreeMap<String, String>, mut b: BTreeMap<String, String>) -> Vec<Change> {
    let mut out: Vec<Change> = vec![];
    for (name, va) in a {
        let vb = b.remove(&name);
        if vb.as_ref() != Some(&va) {
            out.push(Change { name, a: Some(va), b: vb });
        }
    }
    out.extend(b.into_iter().map(|(name, vb)| Change {
        name,
        a: None,
        b: Some(vb),
    }));
    out.sort_by(|x, y| x.name.cmp(&y.name));
    out
}

fn passes(plan: &Plan) -> BTreeMap<String, Vec<String>> {
    plan.passes.iter().map(|p| (p.name.clone(), pass_facts(plan, p))).collect()
}

/// A pass in brief: what it does, reads and writes, and its shaders (the facts before its
/// reuse and binding lines).
fn summary(facts: &[String]) -> String {
    let brief: Vec<&str> = facts
        .iter()
        .map(String::as_str)
        .take_while(|l| !l.starts_with("runs when"))
        .collect();
    brief.join("\n")
}

fn pass_changes(a: &Plan, b: &Plan, d: &mut PlanDiff) {
    let (pa, mut pb) = (passes(a), passes(b));
    for (name, fa) in pa {
        match pb.remove(&name) {
            None => d.passes_removed.push(Change {
                name,
                a: Some(summary(&fa)),
                b: None,
            }),
            Some(fb) if fb != fa => d.passes_changed.push(PassChange {
                name,
                only_a: fa.iter().filter(|l| !fb.contains(l)).cloned().collect(),
                only_b: fb.iter().filter(|l| !fa.contains(l)).cloned().collect(),
            }),
            Some(_) => {}
        }
    }
    d.passes_added = pb
        .into_iter()
        .map(|(name, fb)| Change {
            name,
            a: None,
            b: Some(summary(&fb)),
        })
        .collect();
    let common = |x: &Plan, y: &Plan| -> Vec<String> {
        x.passes
            .iter()
            .filter(|p| y.pass(&p.name).is_some())
            .map(|p| p.name.clone())
            .collect()
    };
    d.order_changed = common(a, b) != common(b, a);
}

/// How two Plans of the same or different pipelines differ in structure.
pub fn diff(a: &Plan, b: &Plan) -> PlanDiff {
    let mut d = PlanDiff {
        memory: (a.memory_bytes, b.memory_bytes),
        ..Default::default()
    };
    let variants = |p: &Plan| p.variants.iter().map(|v| (v.variant.clone(), v.option.clone())).collect();
    d.variants = changes(variants(a), variants(b));
    let params = |p: &Plan| p.params.iter().map(|v| (v.name.clone(), v.default.describe())).collect();
    d.params = changes(params(a), params(b));
    pass_changes(a, b, &mut d);
    let culled = |p: &Plan| p.culled.iter().map(|c| (c.name.clone(), c.reason.clone())).collect();
    // Culled on both sides (for reasons worded after each side's choices) is no difference.
    d.culled = changes(culled(a), culled(b))
        .into_iter()
        .filter(|c| c.a.is_none() || c.b.is_none())
        .collect();
    let resources = |p: &Plan| p.resources.iter().map(|r| (r.name.clone(), resource_fact(r))).collect();
    d.resources = changes(resources(a), resources(b));
    d
}
