//! Stage `emitters` of the reference renderer: the scene's emissive triangles as lights. One
//! is chosen in proportion to its power (an alias table: O(1) per sample), then a point
//! uniformly on it; `pdf` gives the density of having chosen a point a bounce ray found, so
//! that the two ways of reaching an emitter (this, and sampling the BRDF) are combined by
//! multiple importance sampling.

use super::world::World;
use glam::Vec3A;

/// A point drawn on an emitter, as seen from the point being lit.
pub struct LightSample {
    /// Unit direction from the lit point towards it, and its distance.
    pub l: Vec3A,
    pub dist: f32,
    /// What it emits towards the lit point (0 from behind a single-sided emitter).
    pub radiance: Vec3A,
    /// Density of having drawn it, per unit solid angle at the lit point.
    pub pdf: f32,
}

pub struct Emitters {
    /// World triangle of each emitter, its unit face normal, its area and its probability
    /// of being chosen.
    triangle: Vec<u32>,
    normal: Vec<Vec3A>,
    area: Vec<f32>,
    prob: Vec<f32>,
    alias: AliasTable,
    /// Emitter slot of each world triangle (`NONE` for those that emit nothing).
    slot: Vec<u32>,
}

const NONE: u32 = u32::MAX;

impl Emitters {
    /// Every triangle of `world` that emits, weighted by area × its largest mean channel.
    pub fn new(world: &World) -> Emitters {
        let means = world.texture_means();
        let mut e = Emitters {
            triangle: vec![],
            normal: vec![],
            area: vec![],
            prob: vec![],
            alias: AliasTable::new(&[]),
            slot: vec![NONE; world.triangles()],
        };
        let mut power = vec![];
        for i in 0..world.triangles() {
            let [a, b, c] = world.corners(i);
            let cross = (b - a).cross(c - a);
            let area = 0.5 * cross.length();
            let p = area * world.emission_bound(i, &means).max_element();
            if p > 0.0 && p.is_finite() {
                e.slot[i] = e.triangle.len() as u32;
                e.triangle.push(i as u32);
                e.normal.push(cross.normalize_or_zero());
                e.area.push(area);
                power.push(p as f64);
            }
        }
        let total: f64 = power.iter().sum();
        e.prob = power.iter().map(|p| (p / total) as f32).collect();
        e.alias = AliasTable::new(&power);
        e
    }

    pub fn is_empty(&self) -> bool {
        self.triangle.is_empty()
    }

    pub fn len(&self) -> usize {
        self.triangle.len()
    }

    /// A point on an emitter for the surface point `x`, from three uniform numbers.
    pub fn sample(&self, world: &World, x: Vec3A, u: (f32, f32, f32)) -> Option<LightSample> {
        let k = self.alias.pick(u.0)?;
        let i = self.triangle[k] as usize;
        // Uniform on the triangle: the square root warp of two numbers to barycentrics.
        let r = u.1.sqrt();
        let w = Vec3A::new(1.0 - r, r * (1.0 - u.2), r * u.2);
        let [a, b, c] = world.corners(i);
        let p = a * w.x + b * w.y + c * w.z;
        let d = p - x;
        let dist = d.length();
        if dist <= 0.0 || !dist.is_finite() {
            return None;
        }
        let l = d / dist;
        let cos = self.facing(world, i, self.normal[k].dot(-l))?;
        Some(LightSample {
            l,
            dist,
            radiance: world.emission(i, w),
            pdf: self.prob[k] / self.area[k] * dist * dist / cos,
        })
    }

    /// Density per unit solid angle at a point `dist` away that `sample` would have drawn
    /// the point of triangle `i` a ray along `dir` met (0 for a triangle that does not emit).
    pub fn pdf(&self, world: &World, i: u32, dir: Vec3A, dist: f32) -> f32 {
        let Some(&k) = self.slot.get(i as usize).filter(|&&k| k != NONE) else {
            return 0.0;
        };
        match self.facing(world, i as usize, self.normal[k as usize].dot(-dir)) {
            Some(cos) => self.prob[k as usize] / self.area[k as usize] * dist * dist / cos,
            None => 0.0,
        }
    }

    /// The cosine at the emitter towards the lit point, if it emits that way: from its front
    /// only, or from both sides when it is double-sided.
    fn facing(&self, world: &World, i: usize, cos: f32) -> Option<f32> {
        let cos = if world.double_sided(i) { cos.abs() } else { cos };
        (cos > 1e-7).then_some(cos)
    }
}

/// Vose's alias table: a discrete distribution sampled with one number in O(1).
struct AliasTable {
    /// Per bucket: the probability of keeping it, and the other bucket otherwise.
    keep: Vec<f32>,
    other: Vec<u32>,
}

impl AliasTable {
    fn new(weights: &[f64]) -> AliasTable {
        let n = weights.len();
        let total: f64 = weights.iter().sum();
        let mut scaled: Vec<f64> = weights.iter().map(|w| w / total * n as f64).collect();
        let (mut keep, mut other) = (vec![1.0f32; n], (0..n as u32).collect::<Vec<_>>());
        let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
        while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
            keep[s] = scaled[s] as f32;
            other[s] = l as u32;
            scaled[l] -= 1.0 - scaled[s];
            if scaled[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // What is left holds (up to rounding) exactly one bucket's share: kept whole.
        AliasTable { keep, other }
    }

    /// The bucket for a uniform number in [0, 1).
    fn pick(&self, u: f32) -> Option<usize> {
        let n = self.keep.len();
        if n == 0 {
            return None;
        }
        let x = u * n as f32;
        let i = (x as usize).min(n - 1);
        let frac = x - i as f32;
        Some(if frac < self.keep[i] { i } else { self.other[i] as usize })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_alias_table_draws_each_bucket_by_its_weight() {
        let weights = [1.0, 0.0, 3.0, 0.5, 5.5];
        let table = AliasTable::new(&weights);
        let n = 200_000;
        let mut counts = [0u32; 5];
        for j in 0..n {
            counts[table.pick((j as f32 + 0.5) / n as f32).unwrap()] += 1;
        }
        for (c, w) in counts.iter().zip(weights) {
            let share = *c as f64 / n as f64;
            assert!((share - w / 10.0).abs() < 0.002, "{counts:?}");
        }
        assert!(AliasTable::new(&[]).pick(0.5).is_none());
    }
}
