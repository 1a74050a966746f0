//! Sub-stage `bisect` of verify: after a finding, the configuration is rendered again pass by
//! pass, every pass's outputs read back as soon as it is done, to name the first pass (and
//! light instance and layer) whose output holds a non-finite value, with what it read there.

use super::scan::{self, At, Bad};
use crate::error::Result;
use crate::gpu::{Executor, Gpu, Part};
use crate::scene::Scene;
use lightbench_compiler::plan::{Plan, PlanPass, ResourceShape};
use lightbench_compiler::Executable;
use serde::Serialize;

/// The first pass whose output holds a non-finite value.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Offender {
    /// 1-based.
    pub frame: u32,
    pub pass: String,
    /// Its first non-finite output value (the part names the light instance and layer).
    pub output: Bad,
    /// What it read at that place: `name` and the value there.
    pub inputs: Vec<(String, String)>,
}

/// Render `frames` frames pass by pass (every pass runs: no reuse) until a pass writes a
/// non-finite value.
pub fn first_offender(
    gpu: &Gpu,
    exe: &Executable,
    scene: &Scene,
    frames: u32,
    params: &[(String, lightbench_compiler::ir::ParamValue)],
) -> Result<Option<Offender>> {
    let mut ex = super::executor(gpu, exe, scene, params, Default::default())?;
    let mut found: Option<Offender> = None;
    for f in 0..frames.max(1) {
        let inputs = ex.inputs(f as f32 / 60.0);
        let mut after = |ex: &Executor, pi: usize| -> Result<bool> {
            let pass = &ex.plan().passes[pi];
            if let Some(bad) = written_bad(gpu, ex, pass)? {
                let inputs = read_at(gpu, ex, pass, &bad)?;
                found = Some(Offender {
                    frame: f + 1,
                    pass: pass.name.clone(),
                    output: bad,
                    inputs,
                });
                return Ok(true);
            }
            Ok(false)
        };
        if ex.render_frame_probed(gpu, &inputs, &mut after)? {
            break;
        }
    }
    Ok(found)
}

/// The first non-finite value among the current copies of what a pass writes.
fn written_bad(gpu: &Gpu, ex: &Executor, pass: &PlanPass) -> Result<Option<Bad>> {
    let plan = ex.plan();
    let mut ids = pass.written();
    ids.dedup();
    for id in ids {
        let r = plan.res(id);
        let parts: Vec<Part> = ex.parts(&r.name)?.into_iter().filter(|p| !p.previous).collect();
        if let Some(b) = scan::resource(gpu, ex, r, &parts)? {
            return Ok(Some(b));
        }
    }
    Ok(None)
}

/// The values a pass read where it wrote the bad one: the same pixel (scaled to each input's
/// size) of each texture it reads, and for buffers their first non-finite word if any.
fn read_at(gpu: &Gpu, ex: &Executor, pass: &PlanPass, bad: &Bad) -> Result<Vec<(String, String)>> {
    let plan = ex.plan();
    let out_size = size_of(plan, &bad.resource, bad.part.mip);
    let mut out = vec![];
    for read in &pass.reads {
        let r = plan.res(read.resource);
        let instance = if r.per_light.is_empty() { 0 } else { bad.part.instance };
        let part = Part {
            instance,
            layer: match (read.layer, &r.shape) {
                (Some(l), ResourceShape::Texture { layers, .. }) => l.at(0, *layers).unwrap_or(0),
                _ => 0,
            },
            mip: 0,
            previous: read.prev,
        };
        let text = match (&r.shape, bad.at) {
            (ResourceShape::Texture { .. }, At::Pixel { x, y, .. }) => {
                let img = ex.read_part(gpu, &r.name, part)?;
                let (w, h) = out_size;
                let (ix, iy) = (x * img.width / w.max(1), y * img.height / h.max(1));
                let [a, b, c, d] = img.pixel(ix.min(img.width - 1), iy.min(img.height - 1));
                format!("[{}, {}, {}, {}] at ({ix}, {iy})", num(a), num(b), num(c), num(d))
            }
            (ResourceShape::Texture { .. }, At::Word(_)) => "(a texture)".into(),
            (ResourceShape::AccelerationStructure, _) => "(the scene's acceleration structure)".into(),
            (ResourceShape::Buffer { .. }, _) => match scan::resource(gpu, ex, r, &[part])? {
                Some(b) => format!("{} at {:?} ({} non-finite)", b.value, b.at, b.count),
                None => "all finite".into(),
            },
        };
        out.push((r.name.clone(), text));
    }
    Ok(out)
}

fn size_of(plan: &Plan, name: &str, mip: u32) -> (u32, u32) {
    match plan.resource(name).map(|r| &r.shape) {
        Some(ResourceShape::Texture { extent, .. }) => ((extent.0 >> mip).max(1), (extent.1 >> mip).max(1)),
        _ => (1, 1),
    }
}

fn num(v: f32) -> String {
    if v.is_finite() {
        format!("{v}")
    } else {
        scan::value_text(v)
    }
}
