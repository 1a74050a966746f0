//! Sub-stage `scan` of verify: every value of every part of a resource read back and
//! checked to be finite. WGSL has no `isnan`, so a read-back is the only reliable check.

use crate::error::Result;
use crate::gpu::{Executor, Gpu, Part};
use lightbench_compiler::plan::{PlanResource, ResourceShape, Words};
use serde::Serialize;

/// Where in a part a value sits.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum At {
    Pixel { x: u32, y: u32, channel: u32 },
    Word(usize),
}

/// The first non-finite value of a resource part, and how many there are in it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bad {
    pub resource: String,
    pub part: Part,
    /// The part in words, naming only what the resource has: `light instance 1, layer 3`.
    pub place: String,
    pub at: At,
    /// As text: `NaN`, `inf`, `-inf` (JSON has no non-finite numbers).
    pub value: String,
    pub count: usize,
}

/// The first part of `res` (in `parts` order) holding a non-finite value.
pub fn resource(gpu: &Gpu, ex: &Executor, res: &PlanResource, parts: &[Part]) -> Result<Option<Bad>> {
    for &part in parts {
        let found = match res.shape {
            // Integer words are always finite.
            ResourceShape::Buffer {
                words: Words::U32 | Words::I32,
                ..
            } => None,
            ResourceShape::Buffer { .. } => words(&ex.read_buffer_part(gpu, &res.name, part)?),
            ResourceShape::Texture { .. } => ex
                .scan_part(gpu, &res.name, part)?
                .map(|((x, y, channel), v, n)| (At::Pixel { x, y, channel }, v, n)),
        };
        if let Some((at, value, count)) = found {
            return Ok(Some(Bad {
                resource: res.name.clone(),
                part,
                place: place(res, part),
                at,
                value: value_text(value),
                count,
            }));
        }
    }
    Ok(None)
}

/// Every resource of the Plan, every part: the first non-finite value of each offender.
pub fn all(gpu: &Gpu, ex: &Executor) -> Result<Vec<Bad>> {
    let mut out = vec![];
    for r in &ex.plan().resources {
        let parts = ex.parts(&r.name)?;
        out.extend(resource(gpu, ex, r, &parts)?);
    }
    Ok(out)
}

fn place(res: &PlanResource, p: Part) -> String {
    let mips = match res.shape {
        ResourceShape::Texture { mips, .. } => mips,
        ResourceShape::Buffer { .. } => 1,
    };
    let mut parts = vec![];
    if !res.per_light.is_empty() {
        parts.push(format!("light instance {}", p.instance));
    }
    if res.layers() > 1 {
        parts.push(format!("layer {}", p.layer));
    }
    if mips > 1 {
        parts.push(format!("mip {}", p.mip));
    }
    if res.history {
        parts.push(if p.previous { "previous frame's copy" } else { "this frame's copy" }.to_string());
    }
    parts.join(", ")
}

fn words(w: &[f32]) -> Option<(At, f32, usize)> {
    let count = w.iter().filter(|v| !v.is_finite()).count();
    let i = w.iter().position(|v| !v.is_finite())?;
    Some((At::Word(i), w[i], count))
}

pub fn value_text(v: f32) -> String {
    if v.is_nan() {
        "NaN".into()
    } else if v > 0.0 {
        "inf".into()
    } else {
        "-inf".into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_first_non_finite_word_and_counts_them() {
        assert!(words(&[1.0; 8]).is_none());
        let (at, v, n) = words(&[0.0, f32::NEG_INFINITY, f32::NAN]).unwrap();
        assert_eq!((at, value_text(v), n), (At::Word(1), "-inf".to_string(), 2));
    }
}
