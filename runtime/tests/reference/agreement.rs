//! Two estimates of one reference within noise: per-value z-scores and 8×8 blocks' bias,
//! the comparison the GPU path tracer and the CPU reference's two integrators are held to.

use crate::gpu_common;
use lightbench::reference::{self, Budget, Reference, Settings, Term};
use lightbench::scene::Scene;

/// Scene `spec` (a built-in's name, or a file under the repository) at `size`.
pub fn load(spec: &str, size: (u32, u32)) -> Scene {
    let spec = if spec.ends_with(".ron") {
        gpu_common::root().join(spec).display().to_string()
    } else {
        spec.to_string()
    };
    lightbench::scene::load::load_sized(&spec, Some(size), &[]).unwrap_or_else(|e| panic!("{spec}: {e}"))
}

/// `terms` at `spp` samples per pixel, seed 7.
pub fn settings(terms: &[Term], spp: u32) -> Settings {
    Settings {
        budget: Budget::Spp(spp),
        terms: terms.to_vec(),
        seed: 7,
        ..Settings::default()
    }
}

/// How two estimates of one term differ, in units of their combined noise: per value the
/// z-score (mean, RMS), and each 8×8 block's bias (the block's summed difference over its
/// summed noise). Pixels on an edge between surfaces (`reference::edge_pixels`) are left
/// out; where neither has noise (an exact term, a black pixel) the two must agree to 1e-3.
pub struct Agreement {
    pub mean: f64,
    pub rms: f64,
    /// Each block's bias in σ (signed), row by row.
    pub blocks: Vec<f64>,
    pub exact_off: usize,
}

pub fn agreement(a: &reference::TermImage, b: &reference::TermImage, edges: &[bool]) -> Agreement {
    let (w, h) = (a.mean.width as usize, a.mean.height as usize);
    let (mut z, mut exact_off) = (vec![], 0);
    let mut blocks = vec![(0.0f64, 0.0f64); w.div_ceil(8) * h.div_ceil(8)];
    for p in (0..w * h).filter(|&p| !edges[p]) {
        let (mut d_sum, mut sd) = (0.0, [0.0f64; 2]);
        // AO is grey: its three channels are one value.
        let channels = if a.term == Term::Ao { 1 } else { 3 };
        for c in 0..channels {
            let i = p * 4 + c;
            let d = a.mean.rgba[i] as f64 - b.mean.rgba[i] as f64;
            let (va, vb) = (a.variance.rgba[i] as f64, b.variance.rgba[i] as f64);
            let scale = (a.mean.rgba[i].abs() as f64).max(b.mean.rgba[i].abs() as f64);
            if va + vb <= (1e-4 * scale).powi(2) {
                exact_off += (d.abs() > 1e-3 * scale.max(1e-2)) as usize;
                continue;
            }
            z.push(d / (va + vb).sqrt());
            d_sum += d;
            sd = [sd[0] + va.sqrt(), sd[1] + vb.sqrt()];
        }
        // A path's channels move together: the noise of their sum is at most the sum of their
        // noises (exactly that for a grey path), so a block is judged by that bound.
        let block = &mut blocks[(p / w / 8) * w.div_ceil(8) + (p % w) / 8];
        *block = (block.0 + d_sum, block.1 + sd[0] * sd[0] + sd[1] * sd[1]);
    }
    let n = z.len().max(1) as f64;
    Agreement {
        mean: z.iter().sum::<f64>() / n,
        rms: (z.iter().map(|v| v * v).sum::<f64>() / n).sqrt(),
        blocks: blocks.iter().map(|b| if b.1 > 0.0 { b.0 / b.1.sqrt() } else { 0.0 }).collect(),
        exact_off,
    }
}

/// Every term of the two references agrees (see `Agreement`): the failures of the values'
/// z-scores, named, and the blocks biased by more than 3σ as (term, block, signed σ).
fn compare(scene: &Scene, cpu: &Reference, gpu: &Reference) -> (Vec<String>, Vec<(Term, usize, f64)>) {
    let edges = reference::edge_pixels(scene);
    let (mut bad, mut biased) = (vec![], vec![]);
    for t in &cpu.terms {
        let g = gpu.term(t.term).unwrap();
        let a = agreement(t, g, &edges);
        let left = edges.iter().filter(|e| **e).count();
        let worst = a.blocks.iter().map(|b| b.abs()).fold(0.0, f64::max);
        eprintln!(
            "{} {}: z mean {:+.3}, RMS {:.3}, worst 8×8 block {worst:.2}σ, {} exact values off, {left} edge pixels left out",
            scene.name,
            t.term.name(),
            a.mean,
            a.rms,
            a.exact_off
        );
        if a.mean.abs() > 0.1 || a.rms > 1.3 || a.exact_off > 0 {
            bad.push(format!("{} {}", scene.name, t.term.name()));
        }
        biased.extend(
            a.blocks
                .iter()
                .enumerate()
                .filter(|(_, b)| b.abs() > 3.0)
                .map(|(i, b)| (t.term, i, *b)),
        );
    }
    (bad, biased)
}

/// Renderer `b` against renderer `a` on `scene` with `s`: the failures, named. A block beyond
/// 3σ is biased if it is again, the same way, with the next seed: among the hundreds of
/// blocks of a run a few pass 3σ by chance (0.27% each), a bias does not go away.
pub fn judge(scene: &Scene, s: &Settings, a: impl Fn(&Settings) -> Reference, b: impl Fn(&Settings) -> Reference) -> Vec<String> {
    let run = |s: &Settings| {
        let (ra, rb) = (a(s), b(s));
        assert_eq!(rb.spp, ra.spp, "{}", scene.name);
        for (x, y) in ra.terms.iter().zip(&rb.terms) {
            assert_eq!((x.term, x.samples), (y.term, y.samples), "{}", scene.name);
        }
        compare(scene, &ra, &rb)
    };
    let (mut bad, first) = run(s);
    if !first.is_empty() {
        let (_, again) = run(&Settings {
            seed: s.seed + 1,
            ..s.clone()
        });
        for (term, block, z) in first {
            let twice = again.iter().any(|(t, b, z2)| (*t, *b) == (term, block) && z * z2 > 0.0);
            eprintln!(
                "{} {} block {block}: {z:+.2}σ, with the next seed {}",
                scene.name,
                term.name(),
                if twice { "again" } else { "not" }
            );
            if twice {
                bad.push(format!("{} {} block {block}", scene.name, term.name()));
            }
        }
    }
    bad
}
