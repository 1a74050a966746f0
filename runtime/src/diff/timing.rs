//! Stage `timing` of `diff`: each side's per-pass GPU ms and CPU encode µs, and its frame
//! time, over the frames after a warm-up: median, min and max, and B's ratio to A.

use crate::gpu::Executor;
use serde::Serialize;

#[derive(Clone, Copy, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct Stats {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

pub fn stats(values: &[f64]) -> Option<Stats> {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 { v[n / 2] } else { (v[n / 2 - 1] + v[n / 2]) / 2.0 };
    Some(Stats {
        median,
        min: v[0],
        max: v[n - 1],
    })
}

/// B's median over A's (`None` when either is missing or A's is 0).
fn ratio(a: Option<Stats>, b: Option<Stats>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) if a.median > 0.0 => Some(b.median / a.median),
        _ => None,
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct PassTime {
    pub pass: String,
    pub a_gpu_ms: Option<Stats>,
    pub b_gpu_ms: Option<Stats>,
    pub a_encode_us: Option<Stats>,
    pub b_encode_us: Option<Stats>,
    /// B's GPU median over A's.
    pub ratio: Option<f64>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Timing {
    pub frames: u32,
    pub passes: Vec<PassTime>,
    /// Wall-clock ms of a frame (encode, submit, wait) and the sum of its passes' GPU ms.
    pub a_frame_ms: Option<Stats>,
    pub b_frame_ms: Option<Stats>,
    pub a_gpu_ms: Option<Stats>,
    pub b_gpu_ms: Option<Stats>,
    /// B's frame time over A's: GPU time where the adapter has timestamps, else wall-clock.
    pub frame_ratio: Option<f64>,
}

/// What one side's frames took.
#[derive(Default)]
pub struct Recorder {
    /// (pass, GPU ms per frame, encode µs per frame), in the order passes ran.
    passes: Vec<(String, Vec<f64>, Vec<f64>)>,
    wall_ms: Vec<f64>,
    gpu_ms: Vec<f64>,
}

impl Recorder {
    pub fn record(&mut self, ex: &Executor, wall_ms: f64) {
        self.wall_ms.push(wall_ms);
        let mut total = Some(0.0);
        for t in &ex.last_timings {
            let i = match self.passes.iter().position(|(p, ..)| *p == t.pass) {
                Some(i) => i,
                None => {
                    self.passes.push((t.pass.clone(), vec![], vec![]));
                    self.passes.len() - 1
                }
            };
            total = total.zip(t.gpu_ms).map(|(s, g)| s + g);
            self.passes[i].1.extend(t.gpu_ms);
            self.passes[i].2.push(t.cpu_encode_us);
        }
        self.gpu_ms.extend(total);
    }

    fn pass(&self, name: &str) -> (Option<Stats>, Option<Stats>) {
        self.passes
            .iter()
            .find(|(p, ..)| p == name)
            .map(|(_, g, c)| (stats(g), stats(c)))
            .unwrap_or((None, None))
    }
}

pub fn summarize(a: &Recorder, b: &Recorder, frames: u32) -> Timing {
    let mut names: Vec<&str> = a.passes.iter().map(|(p, ..)| p.as_str()).collect();
    names.extend(b.passes.iter().map(|(p, ..)| p.as_str()).filter(|p| a.pass(p).1.is_none()));
    let passes = names
        .into_iter()
        .map(|name| {
            let ((ag, ac), (bg, bc)) = (a.pass(name), b.pass(name));
            PassTime {
                pass: name.to_string(),
                a_gpu_ms: ag,
                b_gpu_ms: bg,
                a_encode_us: ac,
                b_encode_us: bc,
                ratio: ratio(ag, bg),
            }
        })
        .collect();
    let (a_gpu, b_gpu) = (stats(&a.gpu_ms), stats(&b.gpu_ms));
    let (a_wall, b_wall) = (stats(&a.wall_ms), stats(&b.wall_ms));
    Timing {
        frames,
        passes,
        a_frame_ms: a_wall,
        b_frame_ms: b_wall,
        a_gpu_ms: a_gpu,
        b_gpu_ms: b_gpu,
        frame_ratio: ratio(a_gpu, b_gpu).or(ratio(a_wall, b_wall)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_of_odd_and_even_counts() {
        let s = stats(&[3.0, 1.0, 2.0]).unwrap();
        assert_eq!((s.median, s.min, s.max), (2.0, 1.0, 3.0));
        assert_eq!(stats(&[4.0, 1.0, 2.0, 3.0]).unwrap().median, 2.5);
        assert!(stats(&[]).is_none() && stats(&[f64::NAN]).is_none());
        assert_eq!(ratio(stats(&[2.0]), stats(&[3.0])), Some(1.5));
    }
}
