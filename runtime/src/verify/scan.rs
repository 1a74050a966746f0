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

/// What is wrong with a value.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    NonFinite,
    /// Outside the resource's declared `valid` range.
    OutOfRange {
        min: f64,
        max: f64,
    },
}

/// The first bad value of a resource part, and how many there are in it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bad {
    pub kind: Kind,
    pub resource: String,
    pub part: Part,
    /// The part in words, naming only what the resource has: `light instance 1, layer 3`.
    pub place: String,
    pub at: At,
    /// As text: `NaN`, `inf`, `-inf` (JSON has no non-finite numbers), or the number.
    pub value: String,
    pub count: usize,
}

/// The first part of `res` (in `parts` order) holding a non-finite value, or else a value
/// outside its declared `valid` range.
pub fn resource(gpu: &Gpu, ex: &Executor, res: &PlanResource, parts: &[Part]) -> Result<Option<Bad>> {
    if let Some(b) = non_finite(gpu, ex, res, parts)? {
        return Ok(Some(b));
    }
    match res.valid {
        Some(range) => out_of_range(gpu, ex, res, parts, range),
        None => Ok(None),
    }
}

fn non_finite(gpu: &Gpu, ex: &Executor, res: &PlanResource, parts: &[Part]) -> Result<Option<Bad>> {
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
            // Built from the scene's own (checked) positions; nothing to read back.
            ResourceShape::AccelerationStructure => None,
        };
        if let Some((at, value, count)) = found {
            return Ok(Some(Bad {
                kind: Kind::NonFinite,
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
    for r in ex.plan().resources.iter().filter(|r| !r.is_accel()) {
        let parts = ex.parts(&r.name)?;
        out.extend(resource(gpu, ex, r, &parts)?);
    }
    Ok(out)
}

/// The first value outside `[min, max]` (the channels the format has; float words).
fn out_of_range(gpu: &Gpu, ex: &Executor, res: &PlanResource, parts: &[Part], (min, max): (f64, f64)) -> Result<Option<Bad>> {
    let outside = |v: f32| (v as f64) < min || (v as f64) > max;
    for &part in parts {
        let found = match res.shape {
            ResourceShape::Buffer { words: Words::F32, .. } => {
                let w = ex.read_buffer_part(gpu, &res.name, part)?;
                let count = w.iter().filter(|v| outside(**v)).count();
                w.iter().position(|v| outside(*v)).map(|i| (At::Word(i), w[i], count))
            }
            ResourceShape::Buffer { .. } | ResourceShape::AccelerationStructure => None,
            ResourceShape::Texture { format, .. } => {
                let img = ex.read_part(gpu, &res.name, part)?;
                let n = format.components().clamp(1, 4) as usize;
                let channels = || {
                    img.rgba
                        .chunks_exact(4)
                        .enumerate()
                        .flat_map(|(t, px)| px[..n].iter().enumerate().map(move |(c, v)| (t, c, *v)))
                };
                let count = channels().filter(|(_, _, v)| outside(*v)).count();
                channels().find(|(_, _, v)| outside(*v)).map(|(t, c, v)| {
                    let (x, y) = (t as u32 % img.width, t as u32 / img.width);
                    (At::Pixel { x, y, channel: c as u32 }, v, count)
                })
            }
        };
        if let Some((at, value, count)) = found {
            return Ok(Some(Bad {
                kind: Kind::OutOfRange { min, max },
                resource: res.name.clone(),
                part,
                place: place(res, part),
                at,
                value: value.to_string(),
                count,
            }));
        }
    }
    Ok(None)
}

fn place(res: &PlanResource, p: Part) -> String {
    let mips = match res.shape {
        ResourceShape::Texture { mips, .. } => mips,
        ResourceShape::Buffer { .. } | ResourceShape::AccelerationStructure => 1,
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
