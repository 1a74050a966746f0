//! Stage `world`, its ray queries: a 4-wide BVH whose leaves are packets of up to 4
//! triangles, each node's 4 boxes and each packet's 4 triangles tested at once (SSE, through
//! glam's `Vec4`). obvhs builds the tree (PLOC with reinsertion); it is collapsed here to 4
//! children per node and 4 triangles per leaf. A scene of over half a million triangles is
//! built as clusters of neighbours under a tree over them (`CLUSTER`): the build stays linear.
//!
//! Why not obvhs's own traversal: its compressed nodes start every box at an absolute 1e-4
//! from the ray's origin whatever the ray's `tmin` (`cwbvh/node.rs`, `EPSILON`), so a surface
//! nearer than that in a thin box is never met — a tenth of the chair in a millimetre-scale
//! scene, and the wall beside any point in a corner. This one honours `tmin`, and on the
//! Cornell box takes 6% fewer instructions per path (1.15× the paths per second, median of 6
//! runs interleaved with obvhs's traversal).
//!
//! The triangle test is the scalar Möller–Trumbore this module used before, lane by lane:
//! the same operations in the same order (no fused multiply-adds), so a hit's distance is bit
//! for bit what one triangle at a time gives.

use glam::{Vec3A, Vec4};
use obvhs::aabb::Aabb;
use obvhs::bvh2::{
    builder::{build_bvh2, build_bvh2_from_tris},
    Bvh2,
};
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;

/// Four triangles side by side (x, y and z lanes): corner 0, the edges from it to corners 1
/// and 2, and which triangle each lane holds (`NONE` for padding, whose edges are zero).
#[derive(Clone, Copy)]
struct Packet {
    v0: [Vec4; 3],
    e1: [Vec4; 3],
    e2: [Vec4; 3],
    ids: [u32; 4],
}

/// Four children's boxes side by side and what each child is: a node, a packet (`LEAF`), or
/// nothing (`NONE`, left out of `valid`).
#[derive(Clone, Copy)]
struct Node {
    min: [Vec4; 3],
    max: [Vec4; 3],
    child: [u32; 4],
    valid: u32,
}

impl Node {
    /// Child `slot`: `code`, in `aabb` grown by `BOX_GROWTH`.
    fn set(&mut self, slot: usize, aabb: &Aabb, code: u32) {
        let grow = Vec3A::splat(aabb.min.abs().max(aabb.max.abs()).max_element() * BOX_GROWTH);
        let (lo, hi) = (aabb.min - grow, aabb.max + grow);
        for axis in 0..3 {
            self.min[axis][slot] = lo[axis];
            self.max[axis][slot] = hi[axis];
        }
        self.child[slot] = code;
        self.valid |= 1 << slot;
    }
}

const LEAF: u32 = 1 << 31;
const NONE: u32 = u32::MAX;

/// A slab test's far distance is stretched by this much: the rounding of the three slabs
/// never drops a box a ray grazes (Pharr et al., "Robust ray-bounds intersection").
const FAR_SCALE: f32 = 1.0 + 4.0 * f32::EPSILON;
/// Boxes are grown by this fraction of their largest coordinate: a triangle the rounded
/// triangle test hits at its very edge still lies inside its box.
const BOX_GROWTH: f32 = 1.0 / (1 << 18) as f32;

pub struct Bvh {
    nodes: Vec<Node>,
    packets: Vec<Packet>,
    /// A node's index, `LEAF | packet`, or `NONE` for a scene without triangles.
    root: u32,
}

/// A ray and the precomputed reciprocal of its direction (finite: a zero component is
/// replaced by a tiny one, which keeps the slab test free of 0 × ∞).
pub struct Ray {
    pub origin: Vec3A,
    pub dir: Vec3A,
    pub tmin: f32,
    pub tmax: f32,
    inv: Vec3A,
}

impl Ray {
    pub fn new(origin: Vec3A, dir: Vec3A, tmin: f32, tmax: f32) -> Ray {
        let safe = |d: f32| if d.abs() < 1e-30 { 1e30f32.copysign(d) } else { 1.0 / d };
        Ray {
            origin,
            dir,
            tmin,
            tmax,
            inv: Vec3A::new(safe(dir.x), safe(dir.y), safe(dir.z)),
        }
    }
}

/// Whether a hit on triangle `id` at distance `t` (determinant `det`, negative from behind)
/// counts; else the ray passes through.
pub type Accept<'a> = &'a mut dyn FnMut(usize, f32, f32) -> bool;

/// A traversal stack that spills to the heap only for deep trees (a balanced one needs 24
/// entries at a quarter of a million triangles); small, as it is cleared for every ray.
struct Stack {
    fixed: [(u32, f32); 24],
    len: usize,
    spill: Vec<(u32, f32)>,
}

impl Stack {
    fn new() -> Stack {
        Stack {
            fixed: [(0, 0.0); 24],
            len: 0,
            spill: Vec::new(),
        }
    }

    fn push(&mut self, e: (u32, f32)) {
        if self.len < self.fixed.len() {
            self.fixed[self.len] = e;
            self.len += 1;
        } else {
            self.spill_push(e);
        }
    }

    /// Out of line: deep trees only, and inlined it crowds the traversal loop.
    #[cold]
    #[inline(never)]
    fn spill_push(&mut self, e: (u32, f32)) {
        self.spill.push(e);
    }

    fn pop(&mut self) -> Option<(u32, f32)> {
        if let Some(e) = self.spill.pop() {
            return Some(e);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.fixed[self.len])
    }
}

/// Triangles per cluster: a scene of more is built as clusters of this many neighbours (runs
/// of the Morton order), each its own tree, under a tree over the clusters' boxes.
/// Reinsertion's search for where a node fits best costs more per node the larger the tree
/// (1.2× per triangle from 2.5 M to 10 M), so one tree over everything grew faster than the
/// scene: CPU time's exponent 1.09–1.16 from 640 k to 16 M triangles, 1.035 with clusters.
/// What it costs: rays took 3–10% longer on 1–2 M-triangle scenes built as clusters of this
/// size (a bumpy height field, a soup of small triangles; one thread), while their build took
/// 10–15% less: past 2–3 million rays such a scene's reference takes a few percent longer.
const CLUSTER: usize = 1 << 19;

/// One cluster's tree, the order its packets hold the scene's triangles in, and its box.
struct Cluster {
    bvh: Bvh,
    order: Vec<usize>,
    bounds: Aabb,
}

impl Bvh {
    /// The BVH over `tris`, and the order its packets hold them in: a hit's id is a position
    /// in that order.
    pub fn build(tris: &[Triangle]) -> (Bvh, Vec<usize>) {
        Bvh::build_clustered(tris, CLUSTER)
    }

    /// `build`, with clusters of `cluster` triangles when there are more.
    fn build_clustered(tris: &[Triangle], cluster: usize) -> (Bvh, Vec<usize>) {
        if tris.len() <= cluster {
            return Bvh::build_one(tris);
        }
        // One cluster at a time (obvhs builds each on every core): a build's transient memory
        // is held for one cluster, not for one per core.
        let clusters: Vec<Cluster> = morton_order(tris)
            .chunks(cluster)
            .map(|ids| {
                let own: Vec<Triangle> = ids.iter().map(|&i| tris[i as usize]).collect();
                let bounds = own.iter().fold(Aabb::empty(), |b, t| b.union(&t.aabb()));
                let (bvh, order) = Bvh::build_one(&own);
                let order = order.into_iter().map(|k| ids[k] as usize).collect();
                Cluster { bvh, order, bounds }
            })
            .collect();
        Bvh::join(clusters)
    }

    /// One tree over all of `tris`.
    fn build_one(tris: &[Triangle]) -> (Bvh, Vec<usize>) {
        let mut bvh = Bvh {
            nodes: vec![],
            packets: vec![],
            root: NONE,
        };
        if tris.is_empty() {
            return (bvh, vec![]);
        }
        // One triangle per leaf of the binary tree: every leaf fits a packet.
        let tree = build_bvh2_from_tris(tris, params(), &mut std::time::Duration::default());
        let mut counts = vec![0; tree.nodes.len()];
        count(&tree, 0, &mut counts);
        let mut order = vec![];
        bvh.root = bvh.collapse(&tree, 0, &counts, tris, &mut order);
        (bvh, order)
    }

    /// The clusters' trees as one, under a tree built over their boxes; hit ids (positions in
    /// the joined order) follow the clusters' order.
    fn join(clusters: Vec<Cluster>) -> (Bvh, Vec<usize>) {
        let boxes: Vec<Aabb> = clusters.iter().map(|c| c.bounds).collect();
        let mut bvh = Bvh {
            nodes: vec![],
            packets: vec![],
            root: NONE,
        };
        // Reserved whole: grown by doubling, each would for a moment be held twice.
        let total = |f: fn(&Cluster) -> usize| clusters.iter().map(f).sum::<usize>();
        bvh.nodes.reserve_exact(total(|c| c.bvh.nodes.len()) + clusters.len());
        bvh.packets.reserve_exact(total(|c| c.bvh.packets.len()));
        let (mut roots, mut order) = (vec![], Vec::with_capacity(total(|c| c.order.len())));
        for Cluster { bvh: c, order: ids, .. } in clusters {
            let (nodes, packets, ids_at) = (bvh.nodes.len() as u32, bvh.packets.len() as u32, order.len() as u32);
            let moved = |code: u32| match code {
                NONE => NONE,
                c if c & LEAF != 0 => LEAF | ((c & !LEAF) + packets),
                c => c + nodes,
            };
            bvh.nodes.extend(c.nodes.into_iter().map(|mut n| {
                n.child = n.child.map(moved);
                n
            }));
            bvh.packets.extend(c.packets.into_iter().map(|mut p| {
                p.ids = p.ids.map(|i| if i == NONE { NONE } else { i + ids_at });
                p
            }));
            roots.push(moved(c.root));
            order.extend(ids);
        }
        let top = build_bvh2(&boxes, params(), &mut std::time::Duration::default());
        bvh.root = bvh.collapse_top(&top, 0, &roots);
        (bvh, order)
    }

    /// Node `n` of the tree over the clusters as a node of up to 4 children: its leaves are
    /// the clusters' roots.
    fn collapse_top(&mut self, top: &Bvh2, n: usize, roots: &[u32]) -> u32 {
        let node = &top.nodes[n];
        if node.prim_count > 0 {
            return roots[top.primitive_indices[node.first_index as usize] as usize];
        }
        let kids = widest_children(top, n, |k| top.nodes[k].prim_count == 0);
        let index = self.node_for();
        for (slot, &k) in kids.iter().enumerate() {
            let code = self.collapse_top(top, k, roots);
            self.nodes[index].set(slot, top.nodes[k].aabb(), code);
        }
        index as u32
    }

    /// Node `n` of the binary tree as a packet (4 triangles or fewer below it) or as a node
    /// of up to 4 children, opening the largest children that are not packets.
    fn collapse(&mut self, tree: &Bvh2, n: usize, counts: &[u32], tris: &[Triangle], order: &mut Vec<usize>) -> u32 {
        if counts[n] <= 4 {
            let mut prims = vec![];
            gather(tree, n, &mut prims);
            return LEAF | self.packet(&prims, tris, order);
        }
        let kids = widest_children(tree, n, |k| counts[k] > 4);
        let index = self.node_for();
        for (slot, &k) in kids.iter().enumerate() {
            let code = self.collapse(tree, k, counts, tris, order);
            self.nodes[index].set(slot, tree.nodes[k].aabb(), code);
        }
        index as u32
    }

    /// An empty node, its children set later: a parent comes before its children, as a ray
    /// meets them.
    fn node_for(&mut self) -> usize {
        self.nodes.push(Node {
            min: [Vec4::ZERO; 3],
            max: [Vec4::ZERO; 3],
            child: [NONE; 4],
            valid: 0,
        });
        self.nodes.len() - 1
    }

    /// A packet of the triangles `prims` (indices into `tris`), appended to `order`.
    fn packet(&mut self, prims: &[usize], tris: &[Triangle], order: &mut Vec<usize>) -> u32 {
        let mut p = Packet {
            v0: [Vec4::ZERO; 3],
            e1: [Vec4::ZERO; 3],
            e2: [Vec4::ZERO; 3],
            ids: [NONE; 4],
        };
        for (lane, &i) in prims.iter().enumerate() {
            let t = &tris[i];
            let (e1, e2) = (t.v1 - t.v0, t.v2 - t.v0);
            for axis in 0..3 {
                p.v0[axis][lane] = t.v0[axis];
                p.e1[axis][lane] = e1[axis];
                p.e2[axis][lane] = e2[axis];
            }
            p.ids[lane] = order.len() as u32;
            order.push(i);
        }
        self.packets.push(p);
        (self.packets.len() - 1) as u32
    }

    /// The nearest triangle `accept` counts along `ray`: its id and distance.
    pub fn closest(&self, ray: &Ray, accept: Accept) -> Option<(u32, f32)> {
        let mut tmax = ray.tmax;
        let mut best = None;
        self.traverse(ray, &mut tmax, |id, t, det, tmax| {
            if accept(id as usize, t, det) && t < *tmax {
                *tmax = t;
                best = Some((id, t));
            }
            false
        });
        best
    }

    /// Whether `ray` meets any triangle `accept` counts.
    pub fn any(&self, ray: &Ray, accept: Accept) -> bool {
        let mut tmax = ray.tmax;
        self.traverse(ray, &mut tmax, |id, t, det, tmax| t < *tmax && accept(id as usize, t, det))
    }

    /// Visits the packets `ray` reaches nearest first, calling `on_hit` for each triangle hit
    /// no farther than `tmax` (which it may shorten); stops where `on_hit` returns true.
    fn traverse(&self, ray: &Ray, tmax: &mut f32, mut on_hit: impl FnMut(u32, f32, f32, &mut f32) -> bool) -> bool {
        if self.root == NONE {
            return false;
        }
        let lanes = Lanes::new(ray);
        let mut stack = Stack::new();
        let mut next = Some((self.root, ray.tmin));
        while let Some((code, near)) = next.or_else(|| stack.pop()) {
            next = None;
            if near > *tmax {
                continue;
            }
            if code & LEAF == 0 {
                next = enter(&self.nodes[code as usize], &lanes, *tmax, &mut stack);
                continue;
            }
            let p = &self.packets[(code & !LEAF) as usize];
            let (mut mask, t, det) = packet_hits(p, &lanes, *tmax);
            let (t, det) = (t.to_array(), det.to_array());
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if t[lane] <= *tmax && on_hit(p.ids[lane], t[lane], det[lane], tmax) {
                    return true;
                }
            }
        }
        false
    }
}

/// A ray's origin, direction, reciprocal direction and start, each copied to 4 lanes.
struct Lanes {
    o: [Vec4; 3],
    d: [Vec4; 3],
    inv: [Vec4; 3],
    tmin: Vec4,
}

impl Lanes {
    fn new(ray: &Ray) -> Lanes {
        Lanes {
            o: ray.origin.to_array().map(Vec4::splat),
            d: ray.dir.to_array().map(Vec4::splat),
            inv: ray.inv.to_array().map(Vec4::splat),
            tmin: Vec4::splat(ray.tmin),
        }
    }
}

/// The children of `node` that the ray reaches before `tmax`: the nearest returned, the
/// others pushed farthest first.
#[inline(always)]
fn enter(node: &Node, ray: &Lanes, tmax: f32, stack: &mut Stack) -> Option<(u32, f32)> {
    let slab = |axis: usize| {
        let a = (node.min[axis] - ray.o[axis]) * ray.inv[axis];
        let b = (node.max[axis] - ray.o[axis]) * ray.inv[axis];
        (a.min(b), a.max(b))
    };
    let ((nx, fx), (ny, fy), (nz, fz)) = (slab(0), slab(1), slab(2));
    let near = nx.max(ny).max(nz).max(ray.tmin);
    let far = fx.min(fy).min(fz).min(Vec4::splat(tmax)) * FAR_SCALE;
    let mut mask = near.cmple(far).bitmask() & node.valid;
    if mask == 0 {
        return None;
    }
    let near = near.to_array();
    if mask & (mask - 1) == 0 {
        let slot = mask.trailing_zeros() as usize;
        return Some((node.child[slot], near[slot]));
    }
    let first = mask.trailing_zeros() as usize;
    let rest = mask & (mask - 1);
    if rest & (rest - 1) == 0 {
        // Two children: one comparison orders them.
        let second = rest.trailing_zeros() as usize;
        let (a, b) = ((node.child[first], near[first]), (node.child[second], near[second]));
        // A tie goes to the later slot, as the insertion below orders them.
        let (nearer, farther) = if b.1 <= a.1 { (b, a) } else { (a, b) };
        stack.push(farther);
        return Some(nearer);
    }
    let mut hits = [(0u32, 0f32); 4];
    let mut n = 0;
    while mask != 0 {
        let slot = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        // Insertion by distance, nearest last.
        let mut at = n;
        while at > 0 && hits[at - 1].1 < near[slot] {
            hits[at] = hits[at - 1];
            at -= 1;
        }
        hits[at] = (node.child[slot], near[slot]);
        n += 1;
    }
    for &h in &hits[..n - 1] {
        stack.push(h);
    }
    Some(hits[n - 1])
}

/// Möller–Trumbore on a packet's 4 lanes, from either side, edges included: the lanes hit
/// after `ray.tmin` and no later than `tmax` (a bit mask), their distances and determinants
/// (negative where the ray meets the back). A ray through the edge two triangles share hits
/// one of them whichever side it comes from (obvhs's `Triangle::intersect` tests signs by
/// bits, so -0.0 on a shared edge seen from behind misses both); a hit at the ray's very
/// start (t = ±0: an origin on the plane of another surface, as in a corner) is no hit.
fn packet_hits(p: &Packet, ray: &Lanes, tmax: f32) -> (u32, Vec4, Vec4) {
    let cross = |a: &[Vec4; 3], b: &[Vec4; 3]| [a[1] * b[2] - b[1] * a[2], a[2] * b[0] - b[2] * a[0], a[0] * b[1] - b[0] * a[1]];
    let dot = |a: &[Vec4; 3], b: &[Vec4; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (o, d) = (&ray.o, &ray.d);
    let pv = cross(d, &p.e2);
    let det = dot(&p.e1, &pv);
    let s = [o[0] - p.v0[0], o[1] - p.v0[1], o[2] - p.v0[2]];
    let q = cross(&s, &p.e1);
    let inv = Vec4::ONE / det;
    let (u, v) = (dot(&s, &pv) * inv, dot(d, &q) * inv);
    let t = dot(&p.e2, &q) * inv;
    let zero = Vec4::ZERO;
    let usable = det.abs().cmplt(Vec4::INFINITY) & det.cmpne(zero);
    let inside = u.cmpge(zero) & v.cmpge(zero) & (u + v).cmple(Vec4::ONE);
    let range = t.cmpgt(ray.tmin) & t.cmple(Vec4::splat(tmax));
    ((usable & inside & range).bitmask(), t, det)
}

/// Triangle counts below every node of `tree` from `n` down.
fn count(tree: &Bvh2, n: usize, counts: &mut [u32]) -> u32 {
    let node = &tree.nodes[n];
    let c = if node.prim_count > 0 {
        node.prim_count
    } else {
        let first = node.first_index as usize;
        count(tree, first, counts) + count(tree, first + 1, counts)
    };
    counts[n] = c;
    c
}

/// How obvhs builds each binary tree: one triangle per leaf, so that every leaf fits a packet.
fn params() -> BvhBuildParams {
    BvhBuildParams {
        max_prims_per_leaf: 1,
        ..BvhBuildParams::medium_build()
    }
}

/// The children of node `n` of a binary tree that one 4-wide node holds: its two, then, while
/// fewer than 4, the largest that `opens` allows replaced by its own two.
fn widest_children(tree: &Bvh2, n: usize, opens: impl Fn(usize) -> bool) -> Vec<usize> {
    let first = tree.nodes[n].first_index as usize;
    let mut kids = vec![first, first + 1];
    while kids.len() < 4 {
        let open = kids
            .iter()
            .enumerate()
            .filter(|(_, &k)| opens(k))
            .max_by(|a, b| tree.nodes[*a.1].aabb().half_area().total_cmp(&tree.nodes[*b.1].aabb().half_area()));
        let Some((at, &k)) = open else { break };
        let first = tree.nodes[k].first_index as usize;
        kids[at] = first;
        kids.push(first + 1);
    }
    kids
}

/// The triangles' indices in the order of their centres' Morton codes (21 bits an axis, in the
/// scene's box; obvhs's encoding, the one its own build sorts by): runs of it are clusters of
/// neighbours.
fn morton_order(tris: &[Triangle]) -> Vec<u32> {
    use rayon::prelude::*;
    let bounds = tris.iter().fold(Aabb::empty(), |b, t| b.union(&t.aabb()));
    let extent = bounds.max - bounds.min;
    // A flat scene's thin axis counts for nothing.
    let scale = Vec3A::select(
        extent.cmpgt(Vec3A::ZERO),
        Vec3A::splat(((1u32 << 21) - 1) as f32) / extent,
        Vec3A::ZERO,
    );
    let mut keyed: Vec<(u64, u32)> = tris
        .par_iter()
        .enumerate()
        .map(|(i, t)| {
            let c = ((t.v0 + t.v1 + t.v2) / 3.0 - bounds.min) * scale;
            let q = |x: f32| x.clamp(0.0, ((1u32 << 21) - 1) as f32) as u32;
            (obvhs::ploc::morton::morton_encode_u64(q(c.x), q(c.y), q(c.z)), i as u32)
        })
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// The triangles below node `n`.
fn gather(tree: &Bvh2, n: usize, out: &mut Vec<usize>) {
    let node = &tree.nodes[n];
    if node.prim_count > 0 {
        let first = node.first_index as usize;
        out.extend(
            tree.primitive_indices[first..first + node.prim_count as usize]
                .iter()
                .map(|&i| i as usize),
        );
    } else {
        gather(tree, node.first_index as usize, out);
        gather(tree, node.first_index as usize + 1, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::Rng;

    /// One triangle at a time, as the world tested them before packets: the distance and
    /// the determinant, or infinity.
    fn one(tri: &Triangle, ray: &Ray) -> (f32, f32) {
        let (e1, e2) = (tri.v1 - tri.v0, tri.v2 - tri.v0);
        let p = ray.dir.cross(e2);
        let det = e1.dot(p);
        let s = ray.origin - tri.v0;
        let q = s.cross(e1);
        let inv = 1.0 / det;
        let (u, v) = (s.dot(p) * inv, ray.dir.dot(q) * inv);
        let t = e2.dot(q) * inv;
        let hit = det != 0.0 && det.is_finite() && u >= 0.0 && v >= 0.0 && u + v <= 1.0;
        if hit && t > ray.tmin && t <= ray.tmax {
            (t, det)
        } else {
            (f32::INFINITY, det)
        }
    }

    /// `n` small triangles in a cube of side 4 × `scale` about the origin.
    fn soup(n: usize, scale: f32, rng: &mut Rng) -> Vec<Triangle> {
        let mut p = || (Vec3A::new(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0 - 2.0) * scale;
        (0..n)
            .map(|_| {
                let c = p();
                let (a, b) = (p() * 0.2, p() * 0.2);
                Triangle {
                    v0: c,
                    v1: c + a,
                    v2: c + b,
                }
            })
            .collect()
    }

    /// A ray from anywhere in the soup's cube, or from just off a triangle (at 1e-6 to 1e-2 of
    /// the scale: where obvhs's traversal lost surfaces nearer than 1e-4), either way along.
    fn ray(k: usize, tris: &[Triangle], scale: f32, rng: &mut Rng) -> Ray {
        let sign = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
        let (o, axis) = if k % 4 < 2 {
            (Vec3A::new(rng.uniform(), rng.uniform(), rng.uniform()) * 6.0 - 3.0, Vec3A::Y)
        } else {
            let t = &tris[(rng.uniform() * tris.len() as f32) as usize % tris.len()];
            let n = (t.v1 - t.v0).cross(t.v2 - t.v0).normalize_or(Vec3A::Y);
            let (u, v) = rng.pair();
            let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
            let lift = 10f32.powf(-6.0 + 4.0 * rng.uniform());
            ((t.v0 + (t.v1 - t.v0) * u + (t.v2 - t.v0) * v) / scale + n * lift, n)
        };
        let d = crate::sample::cosine_hemisphere(axis, rng.pair()) * sign;
        let tmax = if k.is_multiple_of(3) { 1.5 * scale } else { f32::INFINITY };
        Ray::new(o * scale, d, 0.0, tmax)
    }

    /// Nearest hits and occlusion are exactly those of testing every triangle in turn, on
    /// soups of 1 to 3000 triangles at scales 1e-4, 1 and 1e4, with rays from inside and
    /// outside them and from just off their surfaces; and so they are with the triangles
    /// built as clusters (of 1 and of 64 triangles: a cluster's root a packet or a node).
    #[test]
    fn queries_match_testing_every_triangle() {
        let mut rng = Rng::new(3, 0, 0, 0);
        for scale in [1e-4, 1.0, 1e4] {
            for n in [1, 3, 4, 5, 17, 300, 3000] {
                let tris = soup(n, scale, &mut rng);
                let builds = [Bvh::build(&tris), Bvh::build_clustered(&tris, 1), Bvh::build_clustered(&tris, 64)];
                for (_, order) in &builds {
                    let mut sorted = order.clone();
                    sorted.sort();
                    assert!(sorted.iter().enumerate().all(|(i, &k)| i == k), "every triangle once");
                }
                for k in 0..2000 {
                    let ray = ray(k, &tris, scale, &mut rng);
                    let want = tris
                        .iter()
                        .enumerate()
                        .map(|(i, t)| (i, one(t, &ray).0))
                        .filter(|(_, t)| t.is_finite())
                        .min_by(|a, b| a.1.total_cmp(&b.1));
                    for (b, (bvh, order)) in builds.iter().enumerate() {
                        let got = bvh.closest(&ray, &mut |_, _, _| true).map(|(id, t)| (order[id as usize], t));
                        assert_eq!(got, want, "build {b}, scale {scale}, {n} triangles, ray {k}");
                        assert_eq!(bvh.any(&ray, &mut |_, _, _| true), want.is_some());
                    }
                }
            }
        }
    }

    /// Clusters are runs of neighbours: on a grid of 64 × 64 quads cut into clusters of 512
    /// triangles (a sixteenth of it), each cluster's box is a sixteenth of the grid's area.
    #[test]
    fn clusters_are_runs_of_neighbours() {
        let mut tris = vec![];
        for j in 0..64 {
            for i in 0..64 {
                let at = |di: u32, dj: u32| Vec3A::new((i + di) as f32, 0.0, (j + dj) as f32);
                tris.push(Triangle {
                    v0: at(0, 0),
                    v1: at(1, 0),
                    v2: at(0, 1),
                });
                tris.push(Triangle {
                    v0: at(1, 0),
                    v1: at(1, 1),
                    v2: at(0, 1),
                });
            }
        }
        let order = morton_order(&tris);
        for run in order.chunks(512) {
            let b = run.iter().fold(Aabb::empty(), |b, &i| b.union(&tris[i as usize].aabb()));
            let e = b.max - b.min;
            assert_eq!((e.x * e.z, e.y), (256.0, 0.0), "a 16 × 16 square");
        }
    }

    /// A scene without triangles: nothing is hit, nothing occludes.
    #[test]
    fn an_empty_scene_meets_nothing() {
        let (bvh, order) = Bvh::build(&[]);
        let ray = Ray::new(Vec3A::ZERO, Vec3A::X, 0.0, f32::INFINITY);
        assert!(order.is_empty() && bvh.closest(&ray, &mut |_, _, _| true).is_none());
        assert!(!bvh.any(&ray, &mut |_, _, _| true));
    }
}
