//! Stage `integrate` in lanes: the `full` term's paths of one pixel 8 side by side. Each lane
//! follows one sample's path with that sample's own random numbers (so a seed's image does not
//! depend on how samples share lanes or threads). At every vertex the 8 paths' BRDF draws
//! (`brdf`), the BRDF towards the points drawn on emitters, and each light's light at the
//! vertices just reached (`lights`) are computed at once in SIMD lanes. The rays are traced one
//! at a time through the 4-wide tree (8 bounce rays visit together 0.25–0.5 of the nodes they
//! visit one by one past the first bounce, measured for issue 60: too many for packets to pay);
//! the points on emitters, the hits' surfaces and the BRDF's constants stay as `integrate` does
//! them. A path that ends hands its lane to the pixel's next sample (lane compaction), so lanes
//! stay full until the pixel's last samples.
//!
//! `Context::full` stays as the oracle: with `Draws::Exact` (the scalar integrator's own
//! arithmetic in every lane) the values are bit-identical to it (tested); with the lanes'
//! arithmetic they agree within noise.

mod brdf;
mod lights;
mod math;
mod simd;

use crate::emitters::LightSample;
use crate::integrate::{Context, Primary, MAX_BOUNCES, ROULETTE_FROM};
use crate::sample::Rng;
use crate::shading::Lobes;
use crate::world::{Faces, Hit};
use glam::Vec3A;
use simd::V8;
use std::ops::Range;

pub use simd::LANES;

/// The lanes' arithmetic: SIMD, or the scalar integrator's own one lane at a time
/// (`Lobes::sample`, `Lobes::eval_pdf` and `Context::lights`, with libm), for checking the rest
/// of the lanes' integrator against `Context::full` bit for bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Draws {
    Simd,
    Exact,
}

/// One sample's path: where it is, what it has gathered and its random numbers.
struct Path {
    sample: u32,
    rng: Rng,
    h: Hit,
    v: Vec3A,
    b: Lobes,
    lit: Vec3A,
    sum: Vec3A,
    throughput: Vec3A,
    bounce: u32,
    /// The numbers of the vertex's BRDF draw.
    u: ((f32, f32), f32),
}

impl Context<'_> {
    /// `full` for `samples` of the pixel whose camera ray found `p` (seen from `v`), each sample
    /// drawing from `rng(sample)`: sample `s`'s value is `out[s - samples.start]`.
    pub fn full_lanes(&self, p: &Primary, v: Vec3A, samples: Range<u32>, rng: impl Fn(u32) -> Rng, draws: Draws, out: &mut [Vec3A]) {
        let lit = self.primary_lights(p, v);
        let begin = |sample| Path {
            sample,
            rng: rng(sample),
            h: p.hit,
            v,
            b: p.lobes,
            lit,
            sum: p.hit.emissive,
            throughput: Vec3A::ONE,
            bounce: 1,
            u: ((0.0, 0.0), 0.0),
        };
        let mut pending = samples.clone();
        let mut lanes: [Option<Path>; LANES] = std::array::from_fn(|_| pending.next().map(begin));
        // Each lane's vertex, set where its path starts (the pixel's first vertex) and where it
        // moves to: what the draw, the emitters' BRDF and the lights read.
        let mut vertices = brdf::Vertices::default();
        (0..LANES).for_each(|i| vertices.set(i, &p.hit, &p.lobes, v));
        while lanes.iter().any(Option::is_some) {
            self.vertex_light(&mut lanes, &mut vertices, draws);
            let drawn = match draws {
                Draws::Simd => Some(brdf::sample(&vertices)),
                Draws::Exact => None,
            };
            let mut moved = [false; LANES];
            for (i, lane) in lanes.iter_mut().enumerate() {
                let Some(path) = lane else { continue };
                let (l, w, pdf) = match &drawn {
                    Some(d) => d.at(i),
                    None => path.b.sample(&path.h, path.v, path.u.0, path.u.1),
                };
                moved[i] = self.bounce(path, l, w, pdf);
                if moved[i] {
                    vertices.set(i, &path.h, &path.b, path.v);
                } else {
                    out[(path.sample - samples.start) as usize] = path.sum;
                    *lane = pending.next().map(begin);
                    vertices.set(i, &p.hit, &p.lobes, v);
                }
            }
            self.lit(&mut lanes, &vertices, moved, draws);
        }
    }

    /// Every path's vertex up to its BRDF draw: a point drawn on an emitter (next-event
    /// estimation, its BRDF evaluated in lanes), the light arriving from it and from the
    /// lights, and the draw's random numbers (in `Context::full`'s order) set in `vertices`.
    fn vertex_light(&self, lanes: &mut [Option<Path>; LANES], vertices: &mut brdf::Vertices, draws: Draws) {
        let mut points: [Option<LightSample>; LANES] = std::array::from_fn(|_| None);
        let mut towards = V8::default();
        for (i, lane) in lanes.iter_mut().enumerate() {
            let Some(path) = lane else { continue };
            points[i] = self.emitter_point(&path.h, &mut path.rng);
            if let Some(s) = &points[i] {
                towards.set(i, s.l);
            }
            path.u = (path.rng.pair(), path.rng.uniform());
            vertices.set_numbers(i, path.u.0, path.u.1);
        }
        let in_lanes = draws == Draws::Simd && points.iter().any(Option::is_some);
        let evaluated = in_lanes.then(|| brdf::eval_pdf_towards(vertices, &towards));
        for (i, lane) in lanes.iter_mut().enumerate() {
            let Some(path) = lane else { continue };
            let emitted = match (&points[i], &evaluated) {
                (None, _) => Vec3A::ZERO,
                (Some(s), Some((f, pdf))) => self.emitter_light(&path.h, s, (f.at(i), pdf.0[i]), true),
                (Some(s), None) => self.emitter_light(&path.h, s, path.b.eval_pdf(&path.h, s.l, path.v), true),
            };
            path.sum += path.throughput * (path.lit + emitted);
        }
    }

    /// A vertex after its draw: Russian roulette, the bounce ray and what it finds emitting;
    /// whether the path goes on (to the vertex it found, its lights' light not yet known).
    fn bounce(&self, path: &mut Path, l: Vec3A, w: Vec3A, pdf: f32) -> bool {
        path.throughput *= w;
        if path.throughput.max_element() <= 0.0 {
            return false;
        }
        if path.bounce > ROULETTE_FROM {
            let survive = path.throughput.max_element().min(0.95);
            if path.rng.uniform() >= survive {
                return false;
            }
            path.throughput /= survive;
        }
        let Some(y) = self.trace_from(&path.h, l, f32::INFINITY, Faces::Seen) else {
            return false;
        };
        path.sum += path.throughput * self.emission_found(&y, l, pdf);
        if path.bounce == MAX_BOUNCES {
            return false;
        }
        (path.h, path.v, path.bounce) = (y, -l, path.bounce + 1);
        path.b = self.brdf.at(&y);
        true
    }

    /// The lights' light at the vertices the `moved` lanes' paths have reached
    /// (`Context::lights`, the lights evaluated in lanes, or one lane at a time for `Exact`).
    fn lit(&self, lanes: &mut [Option<Path>; LANES], vertices: &brdf::Vertices, moved: [bool; LANES], draws: Draws) {
        if !moved.contains(&true) {
            return;
        }
        for (i, lane) in lanes.iter_mut().enumerate() {
            if let Some(path) = lane.as_mut().filter(|_| moved[i]) {
                path.lit = match draws {
                    Draws::Exact => self.lights(&path.h, &path.b, path.v, 0),
                    Draws::Simd => Vec3A::ZERO,
                };
            }
        }
        if draws == Draws::Exact {
            return;
        }
        for light in &self.lights {
            let lit = lights::light(light, vertices);
            for (i, lane) in lanes.iter_mut().enumerate() {
                let (Some(path), Some((reflected, l, dist))) = (lane.as_mut().filter(|_| moved[i]), lit.at(i)) else {
                    continue;
                };
                let origin = path.h.position + path.h.ng * self.eps;
                let tmax = dist - self.eps;
                if tmax <= 0.0 || !self.world.occluded_with_coin(origin, l, (self.eps, tmax), 0) {
                    path.lit += reflected;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{context, world::World, Camera, Settings, Term};
    use lightbench_scene::builtin;

    /// With libm's draw the lanes compute each sample's path exactly as `Context::full` does
    /// (the same numbers in the same order), whichever lane and whenever it starts: bit for
    /// bit, over pixels of the point-lit and the emitter-lit box (paths that end early hand
    /// their lanes on; 21 samples leave the last group part-full). With the lanes' own draw
    /// the values differ in the last bits, and often after a few bounces' divergence — the
    /// images agree within noise (`tests/reference`'s z-scores).
    #[test]
    fn exact_draws_give_the_scalar_paths_bit_for_bit() {
        for mut scene in [builtin::cornell(), builtin::cornell_lamp()] {
            scene.size = (16, 16);
            let world = World::new(&scene);
            let ctx = context(&scene, &world, &Settings::default());
            let cam = Camera::new(&scene);
            let (mut compared, mut differ) = (0, 0);
            for (x, y) in [(3, 3), (8, 8), (12, 4), (5, 13), (15, 15)] {
                let (origin, dir, len) = cam.ray(x, y);
                let Some(hit) = world.trace(origin, dir, (0.0, len), crate::world::Faces::Seen) else {
                    continue;
                };
                let p = ctx.primary(&hit, -dir, true, 0);
                let rng = |i: u32| Rng::new(7, (y * 16 + x) as u64, i as u64, Term::Full as u64);
                let scalar: Vec<Vec3A> = (0..21).map(|i| ctx.full(&p, -dir, &mut rng(i))).collect();
                for (draws, same) in [(Draws::Exact, true), (Draws::Simd, false)] {
                    let mut lanes = vec![Vec3A::NAN; 21];
                    ctx.full_lanes(&p, -dir, 0..21, rng, draws, &mut lanes);
                    let bits = |v: &[Vec3A]| v.iter().map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<_>>();
                    if same {
                        assert_eq!(bits(&lanes), bits(&scalar), "{} ({x}, {y})", scene.name);
                        compared += 1;
                    } else {
                        assert!(lanes.iter().all(|v| v.is_finite()));
                        differ += (bits(&lanes) != bits(&scalar)) as u32;
                    }
                }
            }
            assert!(compared >= 4, "{}: {compared} pixels hit", scene.name);
            assert!(differ > 0, "the SIMD draw is not libm's: some path differs");
        }
    }
}
