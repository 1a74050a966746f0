//! The reuse rule of a Plan: which repetitions of which passes run in a frame. A pass runs
//! when something it depends on (the Plan's `Depends`: camera, time, frame index, lights,
//! scene; its parameter block; the light it repeats over) changed since it last ran, or a
//! resource it reads is rewritten this frame. Then, so that every resource holds what a
//! full frame would leave in it, the earlier writers its inputs need run too (a `load`
//! chain is rebuilt from its start), and so do later writers of whatever it overwrites.
//! It depends only on the Plan: an executor supplies what changed (`FrameKeys`, the
//! parameter blocks' bytes) and gets back what to run. What never changes while a Plan runs
//! (who feeds whom) is worked out once (`Graph::of`).

use super::{Plan, PlanPass, ResourceId};
use crate::ir::{LayerSel, Load};
use std::hash::{Hash, Hasher};

/// What changed between frames, hashed per kind of dependency.
#[derive(Clone, Debug, Default)]
pub struct FrameKeys {
    pub camera: u64,
    pub time: u64,
    pub frame_index: u64,
    pub lights: u64,
    /// Per active light.
    pub light: Vec<u64>,
}

pub fn hash_bytes(b: &[u8]) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    b.hash(&mut h);
    h.finish()
}

/// What one pass of the frame needs for the decision.
pub struct PassInputs<'a> {
    pub plan: &'a PlanPass,
    /// Hash of its parameter blocks' bytes.
    pub params: u64,
    /// The light of each repetition (per-light passes).
    pub rep_lights: Vec<Option<u32>>,
}

/// The Plan's passes as the rule sees them, by index in execution order.
#[derive(Clone, Debug, PartialEq)]
pub struct Graph {
    /// The earlier passes whose output each pass reads: if one runs, so does it.
    fed_by: Vec<Vec<usize>>,
    /// The earlier writers a running pass needs to run again: their result is not the last
    /// one of its resource, so it is no longer in place.
    needs: Vec<Vec<usize>>,
    /// The later writers of what a pass writes: they run after it.
    later: Vec<Vec<usize>>,
    /// Whether a pass's repetitions may run alone (each writes its own part).
    separable: Vec<bool>,
    /// Whether a pass runs every frame whatever changed.
    always: Vec<bool>,
}

impl Graph {
    pub fn of(plan: &Plan) -> Graph {
        let n = plan.passes.len();
        let writes: Vec<Vec<ResourceId>> = plan.passes.iter().map(writes_of).collect();
        let reads: Vec<Vec<ResourceId>> = plan.passes.iter().map(reads_of).collect();
        let writer_before = |r: ResourceId, p: usize| (0..p).rev().find(|&w| writes[w].contains(&r));
        let last_writer = |r: ResourceId| (0..n).rev().find(|&w| writes[w].contains(&r));
        let mut g = Graph {
            fed_by: vec![vec![]; n],
            needs: vec![vec![]; n],
            later: vec![vec![]; n],
            separable: plan.passes.iter().map(|p| separable(plan, p)).collect(),
            always: plan.passes.iter().map(|p| p.depends.always.is_some()).collect(),
        };
        for p in 0..n {
            for &r in &reads[p] {
                if let Some(w) = writer_before(r, p) {
                    push_once(&mut g.fed_by[p], w);
                    if Some(w) != last_writer(r) {
                        push_once(&mut g.needs[p], w);
                    }
                }
            }
            for &r in &writes[p] {
                for l in (p + 1..n).filter(|&l| writes[l].contains(&r)) {
                    push_once(&mut g.later[p], l);
                }
            }
        }
        g
    }

    /// Passes that must run in full because of others: forward (a reader of what a running
    /// pass writes), backward (`needs`) and later writers of what a running pass writes.
    fn propagate(&self, dirty: &[bool]) -> Vec<bool> {
        let n = dirty.len();
        let mut run = dirty.to_vec();
        let mut forced = vec![false; n];
        let mut changed = true;
        while changed {
            changed = false;
            let mut mark = |i: usize, run: &mut Vec<bool>| {
                if !forced[i] {
                    forced[i] = true;
                    run[i] = true;
                    changed = true;
                }
            };
            for p in 0..n {
                if self.fed_by[p].iter().any(|&w| run[w]) {
                    mark(p, &mut run);
                }
                if run[p] {
                    for &w in self.needs[p].iter().chain(&self.later[p]) {
                        mark(w, &mut run);
                    }
                }
            }
        }
        forced
    }
}

fn push_once(v: &mut Vec<usize>, x: usize) {
    if !v.contains(&x) {
        v.push(x);
    }
}

/// The keys each repetition last ran with.
pub struct Reuse {
    /// Off: every pass runs every frame (for comparison, `render --no-reuse`).
    pub enabled: bool,
    last: Vec<Vec<Option<u64>>>,
    /// This frame's keys per repetition (kept to reuse the buffers).
    sigs: Vec<Vec<u64>>,
}

impl Reuse {
    pub fn new(enabled: bool) -> Reuse {
        Reuse {
            enabled,
            last: vec![],
            sigs: vec![],
        }
    }

    /// Forget what ran: the next frame runs everything (new resources, new inputs).
    pub fn reset(&mut self) {
        self.last.clear();
    }

    /// Which repetitions run this frame, per pass; remembers the keys of those that do.
    pub fn decide(&mut self, graph: &Graph, keys: &FrameKeys, passes: &[PassInputs]) -> Vec<Vec<bool>> {
        self.last.resize_with(passes.len(), Vec::new);
        // This frame's keys, in buffers kept from frame to frame (an executor decides every
        // frame; nothing here needs to allocate once they have their sizes).
        self.sigs.resize_with(passes.len(), Vec::new);
        for (p, sig) in passes.iter().zip(&mut self.sigs) {
            signatures(p, keys, sig);
        }
        // Each repetition's own verdict: its key changed (or it always runs).
        let mut run: Vec<Vec<bool>> = self
            .sigs
            .iter()
            .zip(&self.last)
            .enumerate()
            .map(|(i, (s, last))| {
                let always = !self.enabled || graph.always[i];
                s.iter()
                    .enumerate()
                    .map(|(r, sig)| always || last.get(r).copied().flatten() != Some(*sig))
                    .collect()
            })
            .collect();
        let dirty: Vec<bool> = run.iter().map(|o| o.iter().any(|d| *d)).collect();
        let forced = graph.propagate(&dirty);
        for (i, reps) in run.iter_mut().enumerate() {
            if forced[i] || (dirty[i] && !graph.separable[i]) {
                reps.iter_mut().for_each(|r| *r = true);
            }
        }
        for (i, s) in self.sigs.iter().enumerate() {
            self.last[i].resize(s.len(), None);
            for (r, sig) in s.iter().enumerate() {
                if run[i][r] {
                    self.last[i][r] = Some(*sig);
                }
            }
        }
        run
    }
}

/// Each repetition's key: everything its result depends on besides what it reads.
fn signatures(p: &PassInputs, keys: &FrameKeys, out: &mut Vec<u64>) {
    let d = &p.plan.depends;
    out.clear();
    out.extend(p.rep_lights.iter().map(|light| {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        p.params.hash(&mut h);
        (d.camera.then_some(keys.camera)).hash(&mut h);
        (d.time.then_some(keys.time)).hash(&mut h);
        (d.frame_index.then_some(keys.frame_index)).hash(&mut h);
        (d.lights.then_some(keys.lights)).hash(&mut h);
        light.and_then(|l| keys.light.get(l as usize)).hash(&mut h);
        h.finish()
    }));
}

/// Resources a pass reads this frame: declared reads and attachments it loads.
fn reads_of(p: &PlanPass) -> Vec<ResourceId> {
    let t = p.work.targets();
    let loaded_color = t
        .into_iter()
        .flat_map(|t| &t.color)
        .filter(|c| c.load.is_load())
        .map(|c| c.resource);
    let loaded_depth = t.and_then(|t| t.depth.as_ref()).filter(|d| d.load.is_load()).map(|d| d.resource);
    p.reads
        .iter()
        .filter(|r| !r.prev)
        .map(|r| r.resource)
        .chain(loaded_color)
        .chain(loaded_depth)
        .collect()
}

/// Resources a pass changes: colour targets, a depth target it writes or clears, storage.
fn writes_of(p: &PlanPass) -> Vec<ResourceId> {
    let t = p.work.targets();
    let color = t.into_iter().flat_map(|t| &t.color).map(|c| c.resource);
    let depth = t
        .and_then(|t| t.depth.as_ref())
        .filter(|d| d.write || !matches!(d.load, Load::Load))
        .map(|d| d.resource);
    color.chain(depth).chain(p.writes.iter().copied()).collect()
}

/// Can the repetitions of a pass run alone? Only when each writes its own part: the
/// instance of its light (per-light resources) and its cube face (`layer: Face`).
fn separable(plan: &Plan, p: &PlanPass) -> bool {
    let own = |r: ResourceId, layer: Option<LayerSel>| {
        let per_light_ok = p.per_light.is_empty() || !plan.res(r).per_light.is_empty();
        let face_ok = !p.per_face || layer == Some(LayerSel::Face);
        per_light_ok && face_ok
    };
    let t = p.work.targets();
    let color = t.into_iter().flat_map(|t| &t.color).all(|c| own(c.resource, Some(c.layer)));
    let depth = t.and_then(|t| t.depth.as_ref()).is_none_or(|d| own(d.resource, Some(d.layer)));
    let storage = p.writes.iter().all(|&w| own(w, None));
    // The levels of a per-mip pass and the runs of a `repeat` pass build on each other:
    // never alone.
    p.repetitions > 1 && p.per_mip.is_none() && p.repeat <= 1 && color && depth && storage
}
