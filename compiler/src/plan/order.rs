//! Stage `graph` (ordering, a planning step): over the passes a configuration keeps, every read has a producer (or is
//! external / a previous-frame read), there are no cycles except through history, and no
//! two passes overwrite one resource in an undefined order. Yields the execution order.
//!
//! A resource has one value per frame: readers see it after all its writers. Writers that
//! `load` build on the previous writer in file order; two writers that both start afresh
//! must be ordered by some other dependency.

use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::span::Span;
use std::collections::{BTreeMap, BTreeSet};

pub struct Ordered {
    /// Indices into `pipeline.passes`, in execution order.
    pub order: Vec<usize>,
    /// Direct predecessors of each kept pass.
    pub after: BTreeMap<usize, Vec<usize>>,
}

/// Orders already worked out for sets of kept passes of one pipeline: the configurations
/// `check` plans often keep the same passes (another shader substituted, another constant),
/// which order alike. Only orders made without a diagnostic are kept.
#[derive(Default)]
pub struct Orders(crate::memo::Memo<Vec<usize>, std::sync::Arc<Ordered>>);

impl Orders {
    /// `order` of `kept`, or the order another configuration kept the same passes in.
    pub fn order(
        &self,
        p: &Pipeline,
        kept: &[usize],
        culled: &dyn Fn(usize) -> Option<String>,
        diags: &mut Diagnostics,
    ) -> Option<std::sync::Arc<Ordered>> {
        if let Some(o) = self.0.get(kept) {
            return Some(o);
        }
        let before = diags.list.len();
        let o = std::sync::Arc::new(order(p, kept, culled, diags)?);
        if diags.list.len() == before {
            self.0.put(kept.to_vec(), o.clone());
        }
        Some(o)
    }
}

/// edge (from, to) -> (resource, span of the use in `to`)
type Edges<'p> = BTreeMap<(usize, usize), (&'p str, Span)>;

/// `culled` gives a culled pass's reason (`None` for a pass not culled), to explain missing
/// producers.
pub fn order(p: &Pipeline, kept: &[usize], culled: &dyn Fn(usize) -> Option<String>, diags: &mut Diagnostics) -> Option<Ordered> {
    let before = diags.error_count();
    let writers = writers(p, kept);
    let mut edges = Edges::new();
    for &i in kept {
        read_edges(p, i, &writers, culled, &mut edges, diags);
    }
    for (res, ws) in &writers {
        writer_edges(p, res, ws, &mut edges, diags);
    }
    if diags.error_count() > before {
        return None;
    }
    let order = topological(kept, &edges);
    if order.len() < kept.len() {
        diags.push(cycle_error(p, kept, &order, &edges));
        return None;
    }
    let mut after: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for &(from, to) in edges.keys() {
        after.entry(to).or_default().push(from);
    }
    Some(Ordered { order, after })
}

/// The kept passes writing each resource, in file order.
fn writers<'p>(p: &'p Pipeline, kept: &[usize]) -> BTreeMap<&'p str, Vec<usize>> {
    let mut writers: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for &i in kept {
        for w in p.passes[i].written() {
            let list = writers.entry(w.value.as_str()).or_default();
            if !list.contains(&i) {
                list.push(i);
            }
        }
    }
    writers
}

/// Edges from the writers of everything pass `i` reads; reads without a producer are errors.
fn read_edges<'p>(
    p: &'p Pipeline,
    i: usize,
    writers: &BTreeMap<&str, Vec<usize>>,
    culled: &dyn Fn(usize) -> Option<String>,
    edges: &mut Edges<'p>,
    diags: &mut Diagnostics,
) {
    let pass = &p.passes[i];
    let reads = pass
        .reads
        .iter()
        .map(|r| (r.name(), r.is_prev()))
        .chain(pass.depth_tested().map(|d| (d, false)));
    for (name, prev) in reads {
        let Some(res) = p.resource(name) else {
            continue;
        };
        let ws: &[usize] = writers.get(name.value.as_str()).map(Vec::as_slice).unwrap_or(&[]);
        if prev {
            if ws.is_empty() {
                diags.push(Diagnostic::error(
                    Code::ReadBeforeWrite,
                    format!(
                        "`{}` is a history resource but no pass writes it, so there is no previous frame to read",
                        name.value
                    ),
                    name.span,
                ));
            }
            continue;
        }
        // Other mips or layers of what it writes are inputs, not a cycle (checked by `declarations`).
        let own_parts = ws.contains(&i) && reads_other_parts(pass, &name.value);
        if ws.contains(&i) && !own_parts {
            diags.push(
                Diagnostic::error(
                    Code::Cycle,
                    format!("pass `{}` both reads and writes `{}`", pass.name.value, name.value),
                    name.span,
                )
                .with_note(format!(
                    "to read the previous frame, declare `{}` with `history: true` and read `Prev(\"{}\")`",
                    name.value, name.value
                )),
            );
            continue;
        }
        let others: Vec<usize> = ws.iter().copied().filter(|&w| w != i).collect();
        // Shadow maps whose writers were all culled for lack of casting lights stay cleared;
        // the lights read as unshadowed. (Asked last: it walks every pass.)
        let unshadowed = || ws.is_empty() && p.written_by_casters_only(res);
        if others.is_empty() && !own_parts && !res.supplied() && !unshadowed() {
            diags.push(missing_producer(p, pass, name, res, culled));
        }
        // A resource rewritten within the frame: a reader sees the writes before it in file
        // order, and later writers wait for it. With no earlier writer it sees them all.
        let before: Vec<usize> = others.iter().copied().filter(|&w| w < i).collect();
        let sources = if before.is_empty() { &others } else { &before };
        for &w in sources {
            edges.entry((w, i)).or_insert((name.value.as_str(), name.span));
        }
        if !before.is_empty() {
            for &w in others.iter().filter(|&&w| w > i) {
                edges.entry((i, w)).or_insert((name.value.as_str(), name.span));
            }
        }
    }
}

/// Does a pass that writes `res` read only other mip levels or array layers of it (`Mip(..)`,
/// `Layer(..)` reads, written through attachments only)? Whether they really differ is
/// `declarations`' check.
fn reads_other_parts(pass: &Pass, res: &str) -> bool {
    let reads_whole = pass
        .reads
        .iter()
        .any(|r| r.name().value == res && r.mip().is_none() && r.layer().is_none());
    let storage = pass.writes.iter().any(|w| w.value == res);
    !reads_whole && !storage && pass.depth_tested().is_none_or(|d| d.value != res)
}

fn missing_producer(
    p: &Pipeline,
    pass: &Pass,
    name: &crate::span::Spanned<String>,
    res: &Resource,
    culled: &dyn Fn(usize) -> Option<String>,
) -> Diagnostic {
    let mut d = Diagnostic::error(
        Code::ReadBeforeWrite,
        format!("`{}` is read by pass `{}` but no pass writes it first", name.value, pass.name.value),
        name.span,
    )
    .with_secondary(res.span, "declared here");
    let culled_writers: Vec<String> = (0..p.passes.len())
        .filter(|&j| p.passes[j].written().any(|w| w.value == name.value))
        .filter_map(|j| culled(j).map(|why| format!("its writer `{}` was culled: {why}", p.passes[j].name.value)))
        .collect();
    if culled_writers.is_empty() {
        d = d.with_note(
            "add a pass that writes it, give it `data` (a file or numbers), or mark it `external: true` if the caller supplies it",
        );
    }
    for n in culled_writers {
        d = d.with_note(n);
    }
    d
}

/// Writers that `load` build on the previous writer in file order, and so do storage writes
/// (`writes`: nothing clears a storage resource, so a later one appends to or updates what the
/// earlier left, as fragment lists do after their clear); writers that start afresh must be
/// ordered by some other dependency.
fn writer_edges<'p>(p: &Pipeline, res: &'p str, ws: &[usize], edges: &mut Edges<'p>, diags: &mut Diagnostics) {
    let span_of = |i: usize| {
        p.passes[i]
            .written()
            .find(|n| n.value == res)
            .map(|n| n.span)
            .unwrap_or(p.passes[i].span)
    };
    let mut fresh: Vec<usize> = vec![];
    for (k, &w) in ws.iter().enumerate() {
        let pass = &p.passes[w];
        let stores = k > 0 && pass.writes.iter().any(|n| n.value == res);
        if !pass.accumulates(res) && !stores {
            fresh.push(w);
        } else if k > 0 {
            edges.entry((ws[k - 1], w)).or_insert((res, span_of(w)));
        } else if !p.resource(res).is_some_and(|r| r.supplied() || r.history()) {
            diags.push(
                Diagnostic::error(
                    Code::ReadBeforeWrite,
                    format!("pass `{}` loads `{res}` but no earlier pass writes it", pass.name.value),
                    span_of(w),
                )
                .with_note("clear it instead (`clear: (...)`), or write it in an earlier pass"),
            );
        }
    }
    // Different layers or mip levels of one texture are different resources here.
    let written: Vec<Vec<Part>> = fresh.iter().map(|&w| parts(&p.passes[w], res)).collect();
    for (a, &x) in fresh.iter().enumerate() {
        for (b, &y) in fresh.iter().enumerate().skip(a + 1) {
            let overlap = written[a].iter().any(|pa| written[b].iter().any(|pb| pa.overlaps(pb)));
            if overlap && !reaches(edges, x, y) && !reaches(edges, y, x) {
                diags.push(
                    Diagnostic::error(
                        Code::DoubleWriter,
                        format!("passes `{}` and `{}` both write `{res}` and nothing orders them", p.passes[x].name.value, p.passes[y].name.value),
                        span_of(y),
                    )
                    .with_secondary(span_of(x), "also written here")
                    .with_note("make the later one `load: Load` to build on the first, give them exclusive `when` conditions, or write different resources"),
                );
            }
        }
    }
}

/// Kahn's algorithm, preferring file order among ready passes.
fn topological(kept: &[usize], edges: &Edges) -> Vec<usize> {
    let mut indeg: BTreeMap<usize, usize> = kept.iter().map(|&i| (i, 0)).collect();
    for &(_, to) in edges.keys() {
        if let Some(d) = indeg.get_mut(&to) {
            *d += 1;
        }
    }
    let mut ready: BTreeSet<usize> = indeg.iter().filter(|(_, d)| **d == 0).map(|(i, _)| *i).collect();
    let mut order = vec![];
    while let Some(i) = ready.pop_first() {
        order.push(i);
        for (&(_, to), _) in edges.range((i, 0)..(i + 1, 0)) {
            if let Some(d) = indeg.get_mut(&to) {
                *d -= 1;
                if *d == 0 {
                    ready.insert(to);
                }
            }
        }
    }
    order
}

fn cycle_error(p: &Pipeline, kept: &[usize], order: &[usize], edges: &Edges) -> Diagnostic {
    let left: Vec<usize> = kept.iter().copied().filter(|i| !order.contains(i)).collect();
    let cycle = find_cycle(edges, &left);
    let names: Vec<&str> = cycle.iter().map(|&i| p.passes[i].name.value.as_str()).collect();
    let (res, span) = edges.get(&(cycle[cycle.len() - 1], cycle[0])).cloned().unwrap_or_default();
    let mut d = Diagnostic::error(
        Code::Cycle,
        format!("passes form a cycle: {} -> {}", names.join(" -> "), names[0]),
        span,
    )
    .with_label_text(format!(
        "`{}` reads `{res}` written by `{}`",
        p.passes[cycle[0]].name.value,
        p.passes[cycle[cycle.len() - 1]].name.value
    ));
    for w in cycle.windows(2) {
        if let Some((r, s)) = edges.get(&(w[0], w[1])) {
            d = d.with_secondary(
                *s,
                format!(
                    "`{}` reads `{r}` written by `{}`",
                    p.passes[w[1]].name.value, p.passes[w[0]].name.value
                ),
            );
        }
    }
    d.with_note("to use a value from the previous frame, declare the resource with `history: true` and read `Prev(\"name\")`")
}

/// Layers and mip levels a write covers (`None`: all of them).
struct Part {
    layers: Option<BTreeSet<u32>>,
    mips: Option<BTreeSet<u32>>,
}

impl Part {
    fn overlaps(&self, o: &Part) -> bool {
        let meet = |a: &Option<BTreeSet<u32>>, b: &Option<BTreeSet<u32>>| match (a, b) {
            (Some(a), Some(b)) => !a.is_disjoint(b),
            _ => true,
        };
        meet(&self.layers, &o.layers) && meet(&self.mips, &o.mips)
    }
}

/// What of `res` a pass writes: each attachment's layers and levels; storage writes are whole.
fn parts(pass: &Pass, res: &str) -> Vec<Part> {
    let levels = pass.per_mip.as_ref().map(|m| m.value.levels()).unwrap_or_else(|| vec![0]);
    let part = |layer: LayerSel, mip: MipSel| Part {
        layers: match layer {
            LayerSel::Base => Some([0].into()),
            LayerSel::Index(n) => Some([n].into()),
            LayerSel::Face => Some((0..6).collect()),
            LayerSel::All | LayerSel::Rep(_) => None,
        },
        mips: Some(levels.iter().filter_map(|&l| mip.level(l)).collect()),
    };
    let color = pass
        .color()
        .iter()
        .filter(|c| c.resource.value == res)
        .map(|c| part(c.layer, c.mip.value));
    let depth = pass.depth().filter(|d| d.resource.value == res).map(|d| part(d.layer, d.mip.value));
    let storage = pass
        .writes
        .iter()
        .filter(|w| w.value == res)
        .map(|_| Part { layers: None, mips: None });
    color.chain(depth).chain(storage).collect()
}

fn reaches(edges: &Edges, from: usize, to: usize) -> bool {
    let mut stack = vec![from];
    let mut seen = BTreeSet::new();
    while let Some(n) = stack.pop() {
        if n == to {
            return true;
        }
        if seen.insert(n) {
            stack.extend(edges.range((n, 0)..(n + 1, 0)).map(|(&(_, t), _)| t));
        }
    }
    false
}

/// A cycle among the passes Kahn's algorithm could not order. Every such pass has an
/// unordered predecessor among them, so walking predecessors must come back on itself.
fn find_cycle(edges: &Edges, left: &[usize]) -> Vec<usize> {
    let mut path = vec![left[0]];
    loop {
        let cur = path[path.len() - 1];
        let prev = edges
            .keys()
            .find(|(from, to)| *to == cur && left.contains(from))
            .map(|(from, _)| *from);
        match prev {
            Some(n) => {
                if let Some(pos) = path.iter().position(|&x| x == n) {
                    let mut cycle = path[pos..].to_vec();
                    cycle.reverse(); // predecessors were walked: restore edge direction
                    return cycle;
                }
                path.push(n);
            }
            None => return path,
        }
    }
}
