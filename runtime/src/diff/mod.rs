//! `lightbench diff`: two pipelines, or one pipeline in two configurations, side by side —
//! Plan structure (no GPU needed), the pixels of every resource both sides have, per-pass time
//! — in one report. Sub-stages: `spec` (the sides as written), `metrics`, `images`, `timing`,
//! `report` (markdown, HTML, JSON), and here: planning, rendering frame by frame
//! interleaved, reading back and comparing.

pub mod images;
pub mod metrics;
pub mod report;
pub mod spec;
pub mod timing;

use crate::error::{Error, Result};
use crate::gpu::{Executor, Gpu};
use crate::scene::Scene;
use lightbench_compiler::ir::ParamValue;
use lightbench_compiler::plan::{Plan, PlanDiff, PlanResource, ResourceShape};
use lightbench_compiler::workspace::Executable;
use serde::Serialize;
use spec::Side;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One side as planned: the choices made and the values that differ from the defaults.
#[derive(Clone, Debug, Serialize)]
pub struct SideReport {
    pub label: String,
    pub pipeline: String,
    /// (variant, option chosen, why it is not the one asked for).
    pub variants: Vec<(String, String, Option<String>)>,
    /// Parameter overrides from the side's `@...`.
    pub params: Vec<(String, String)>,
    pub memory_bytes: u64,
}

/// One compared image: a resource's light instance and layer (buffers: their words).
#[derive(Clone, Debug, Serialize)]
pub struct ImageDiff {
    pub resource: String,
    pub instance: u32,
    pub layer: u32,
    /// The mip level (textures with a mip chain are compared level by level).
    pub mip: u32,
    pub format: String,
    pub size: (u32, u32),
    pub metrics: metrics::Metrics,
    /// File names in the output folder (textures only).
    pub heat_map: Option<String>,
    pub side_by_side: Option<String>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub a: SideReport,
    pub b: SideReport,
    pub scene: String,
    pub size: (u32, u32),
    pub structure: PlanDiff,
    /// The output first, then every other resource compared.
    pub images: Vec<ImageDiff>,
    /// Resources not compared, and why.
    pub not_compared: Skipped,
    pub timing: Option<timing::Timing>,
    pub thresholds: Vec<Threshold>,
}

/// What `--fail-above` compares: the output's FLIP, RMSE or largest difference, B's frame time
/// or memory over A's.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Metric {
    Flip,
    Rmse,
    Max,
    Time,
    Memory,
}

impl Metric {
    pub const NAMES: [&'static str; 5] = ["flip", "rmse", "max", "time", "memory"];
    const ALL: [Metric; 5] = [Metric::Flip, Metric::Rmse, Metric::Max, Metric::Time, Metric::Memory];
    pub fn from_name(s: &str) -> Option<Metric> {
        Self::NAMES.iter().position(|n| *n == s).map(|i| Self::ALL[i])
    }
    pub fn name(self) -> &'static str {
        Self::NAMES[Self::ALL.iter().position(|m| *m == self).unwrap_or(0)]
    }
    /// Needs rendering (all but memory).
    pub fn rendered(self) -> bool {
        self != Metric::Memory
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct Threshold {
    pub metric: Metric,
    pub limit: f64,
    /// `None`: not measured (e.g. FLIP of an output that is not 8-bit colour).
    pub value: Option<f64>,
    pub crossed: bool,
}

/// What to run.
pub struct Options {
    pub frames: u32,
    /// Resources to compare besides the output (`None`: all).
    pub resources: Option<Vec<String>>,
    pub out: PathBuf,
    pub fail_above: Vec<(Metric, f64)>,
}

/// A side planned (and compiled for the GPU when rendering).
pub struct Planned {
    pub side: Side,
    pub exe: Executable,
    pub params: Vec<(String, ParamValue)>,
}

impl Planned {
    fn report(&self) -> SideReport {
        SideReport {
            label: self.side.label.clone(),
            pipeline: self.side.pipeline.display().to_string(),
            variants: self
                .exe
                .plan
                .variants
                .iter()
                .map(|v| (v.variant.clone(), v.option.clone(), v.reason.clone()))
                .collect(),
            params: self.params.iter().map(|(k, v)| (k.clone(), v.describe())).collect(),
            memory_bytes: self.exe.plan.memory_bytes,
        }
    }
}

/// The report of a structure-only diff (`--no-render`, or before rendering).
pub fn structure(a: &Planned, b: &Planned, scene: &str, size: (u32, u32)) -> Report {
    let mut pa = a.exe.plan.clone();
    let mut pb = b.exe.plan.clone();
    // Overrides count as the parameters' values.
    for (plan, params) in [(&mut pa, &a.params), (&mut pb, &b.params)] {
        for (name, value) in params {
            if let Some(p) = plan.params.iter_mut().find(|p| p.name == *name) {
                p.default = value.clone();
            }
        }
    }
    Report {
        a: a.report(),
        b: b.report(),
        scene: scene.to_string(),
        size,
        structure: lightbench_compiler::plan::diff(&pa, &pb),
        images: vec![],
        not_compared: vec![],
        timing: None,
        thresholds: vec![],
    }
}

fn executor(gpu: &Gpu, p: &Planned, scene: &Scene) -> Result<Executor> {
    let mut ex = Executor::new(gpu, &p.exe, scene)?;
    ex.set_reuse(false);
    for (name, value) in &p.params {
        ex.set_param(name, value.clone())?;
    }
    Ok(ex)
}

/// Render both sides frame by frame, interleaved (drift in the machine's speed hits both
/// alike), one warm-up frame each first.
pub fn render(gpu: &Gpu, (a, b): (&Planned, &Planned), scene: &Scene, frames: u32) -> Result<(Executor, Executor, timing::Timing)> {
    let (mut ea, mut eb) = (executor(gpu, a, scene)?, executor(gpu, b, scene)?);
    let (mut ra, mut rb) = (timing::Recorder::default(), timing::Recorder::default());
    for f in 0..=frames {
        for (ex, rec) in [(&mut ea, &mut ra), (&mut eb, &mut rb)] {
            let inputs = ex.inputs(f as f32 / 60.0);
            let start = Instant::now();
            ex.render_frame(gpu, &inputs)?;
            if f > 0 {
                rec.record(ex, start.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    Ok((ea, eb, timing::summarize(&ra, &rb, frames)))
}

/// Why two resources of the same name cannot be compared, if they cannot.
fn incomparable(a: &PlanResource, b: &PlanResource) -> Option<String> {
    match (&a.shape, &b.shape) {
        (
            ResourceShape::Texture {
                format: fa,
                extent: ea,
                layers: la,
                ..
            },
            ResourceShape::Texture {
                format: fb,
                extent: eb,
                layers: lb,
                ..
            },
        ) => {
            if fa != fb {
                Some(format!("format differs: {} vs {}", fa.name(), fb.name()))
            } else if (ea, la) != (eb, lb) {
                Some(format!("size differs: {}×{}×{la} vs {}×{}×{lb}", ea.0, ea.1, eb.0, eb.1))
            } else {
                None
            }
        }
        (ResourceShape::Buffer { size: sa, .. }, ResourceShape::Buffer { size: sb, .. }) if sa != sb => {
            Some(format!("size differs: {sa} vs {sb} bytes"))
        }
        (ResourceShape::Buffer { .. }, ResourceShape::Buffer { .. }) => None,
        _ => Some("a texture on one side, a buffer on the other".into()),
    }
}

/// Resources left out of the comparison: (name, why).
pub type Skipped = Vec<(String, String)>;

/// Pairs of resources to compare, (A's name, B's name): the outputs first, whatever their
/// names, then the resources of the same name; and those left out with the reason.
pub fn pairs<'p>(a: &'p Plan, b: &'p Plan, only: Option<&[String]>) -> Result<(Vec<(&'p str, &'p str)>, Skipped)> {
    let (oa, ob) = (a.output_resource(), b.output_resource());
    if let Some(list) = only {
        if let Some(bad) = list.iter().find(|n| a.resource(n).is_none() && b.resource(n).is_none()) {
            return Err(Error::Usage(format!("--resources: neither side has a resource `{bad}`")));
        }
    }
    let wanted = |n: &str| only.is_none_or(|l| l.iter().any(|x| x == n));
    let mut candidates = vec![(oa, Some(ob))];
    candidates.extend(
        a.resources
            .iter()
            .filter(|r| r.name != oa.name && r.name != ob.name && wanted(&r.name))
            .map(|r| (r, b.resource(&r.name))),
    );
    let (mut keep, mut skipped) = (vec![], vec![]);
    for (ra, rb) in candidates {
        match rb.map(|rb| (rb, incomparable(ra, rb))) {
            Some((rb, None)) => keep.push((ra.name.as_str(), rb.name.as_str())),
            Some((_, Some(why))) => skipped.push((ra.name.clone(), why)),
            None => skipped.push((ra.name.clone(), "only in A".into())),
        }
    }
    for r in b
        .resources
        .iter()
        .filter(|r| a.resource(&r.name).is_none() && r.name != ob.name && wanted(&r.name))
    {
        skipped.push((r.name.clone(), "only in B".into()));
    }
    Ok((keep, skipped))
}

/// Both sides' values of one slice of a resource, as read back.
struct Slice {
    name: String,
    slice: (u32, u32),
    mip: u32,
    a: Values,
    b: Values,
    channels: usize,
    colour: bool,
    format: String,
    buffer: bool,
    stem: String,
}

/// A slice's values: texels as copied (decoded on the analysing thread) or a buffer's words.
enum Values {
    Texels(crate::gpu::readback::Raw),
    Words(crate::io::Image),
}

impl Values {
    /// The same bytes on both sides (a NaN equal to the same NaN).
    fn same(&self, other: &Values) -> bool {
        match (self, other) {
            (Values::Texels(a), Values::Texels(b)) => a == b,
            (Values::Words(a), Values::Words(b)) => metrics::same_bits(a, b),
            _ => false,
        }
    }

    fn image(self) -> Result<crate::io::Image> {
        match self {
            Values::Texels(raw) => Ok(raw.decode()?),
            Values::Words(img) => Ok(img),
        }
    }
}

/// Read back every slice (light instance, layer, mip level) of a resource both sides have.
fn read_resource(gpu: &Gpu, (ea, eb): (&Executor, &Executor), (name, name_b): (&str, &str)) -> Result<Vec<Slice>> {
    let r = ea.plan().resource(name).expect("paired resources exist");
    let slices_b = eb.slices(name_b)?;
    let mips = ea.mips(name)?.min(eb.mips(name_b)?);
    let parts = ea.slices(name)?.into_iter().filter(|s| slices_b.contains(s));
    let mut out = vec![];
    for (slice, mip) in parts.flat_map(|s| (0..mips).map(move |m| (s, m))) {
        let (a, b, channels, colour, format) = match &r.shape {
            ResourceShape::Texture { format, .. } => {
                let (a, b) = (
                    Values::Texels(ea.read_texture_raw(gpu, name, slice, mip)?),
                    Values::Texels(eb.read_texture_raw(gpu, name_b, slice, mip)?),
                );
                (a, b, format.components() as usize, format.is_srgb(), format.name().to_string())
            }
            ResourceShape::Buffer { .. } => {
                let words = |ex: &Executor, n: &str| ex.read_buffer(gpu, n, slice.0).map(|w| Values::Words(crate::io::Image::row(w)));
                (words(ea, name)?, words(eb, name_b)?, 1, false, "buffer".to_string())
            }
            // Built from the scene, not by the passes: nothing of it can be read back.
            ResourceShape::AccelerationStructure => continue,
        };
        out.push(Slice {
            name: if name == name_b {
                name.to_string()
            } else {
                format!("{name} / {name_b}")
            },
            slice,
            mip,
            a,
            b,
            channels,
            colour,
            format,
            buffer: r.is_buffer(),
            stem: crate::io::slice_stem(name, r, slice, mip),
        });
    }
    Ok(out)
}

/// Metrics and images of one slice (runs on any thread).
fn analyze(s: Slice, out: &Path) -> Result<ImageDiff> {
    // Equal slices (most of them, for a variant that should not change the image) are decoded
    // once and measured as equal.
    let same = s.a.same(&s.b);
    let a = s.a.image()?;
    let decoded;
    let b = match same {
        true => &a,
        false => {
            decoded = s.b.image()?;
            &decoded
        }
    };
    let compared = metrics::compare(&a, b, s.channels, s.colour);
    let files = match s.buffer {
        true => None,
        false => Some(images::write(out, &s.stem, (&a, b), (s.channels, !s.colour), &compared.error_map)?),
    };
    Ok(ImageDiff {
        resource: s.name,
        instance: s.slice.0,
        layer: s.slice.1,
        mip: s.mip,
        format: s.format,
        size: (a.width, a.height),
        metrics: compared.metrics,
        heat_map: files.as_ref().map(|f| f.0.clone()),
        side_by_side: files.map(|f| f.1),
    })
}

/// Read back and compare every slice of `names`: each resource's slices are analysed on
/// rayon's threads while the next resource is read back (FLIP alone takes ~0.1 s at 512² on
/// one core). Results keep the order of `names`.
pub fn compare_all(gpu: &Gpu, sides: (&Executor, &Executor), names: &[(&str, &str)], out: &Path) -> Result<Vec<ImageDiff>> {
    let results = std::sync::Mutex::new(vec![]);
    let mut read_error = None;
    rayon::scope(|sc| {
        let mut order = 0usize;
        for name in names {
            let slices = match read_resource(gpu, sides, *name) {
                Ok(s) => s,
                Err(e) => {
                    read_error = Some(e);
                    return;
                }
            };
            for s in slices {
                let (i, results) = (order, &results);
                order += 1;
                sc.spawn(move |_| {
                    let r = analyze(s, out);
                    results.lock().unwrap_or_else(|e| e.into_inner()).push((i, r));
                });
            }
        }
    });
    if let Some(e) = read_error {
        return Err(e);
    }
    let mut done = results.into_inner().unwrap_or_else(|e| e.into_inner());
    done.sort_by_key(|(i, _)| *i);
    done.into_iter().map(|(_, r)| r).collect()
}

/// Render both sides, compare their resources and time their passes, writing images to
/// `opts.out`.
pub fn run(gpu: &Gpu, (a, b): (&Planned, &Planned), scene: &Scene, opts: &Options) -> Result<Report> {
    let mut report = structure(a, b, &scene.name, scene.size);
    let (pa, pb) = (&a.exe.plan, &b.exe.plan);
    let (names, skipped) = pairs(pa, pb, opts.resources.as_deref())?;
    std::fs::create_dir_all(&opts.out).map_err(|e| Error::io(&opts.out, e))?;
    let (ea, eb, timing) = render(gpu, (a, b), scene, opts.frames)?;
    report.images = compare_all(gpu, (&ea, &eb), &names, &opts.out)?;
    report.not_compared = skipped;
    report.timing = Some(timing);
    report.thresholds = thresholds(&report, &opts.fail_above);
    Ok(report)
}

/// Each `--fail-above` limit against what was measured.
pub fn thresholds(r: &Report, limits: &[(Metric, f64)]) -> Vec<Threshold> {
    let output = r.images.first();
    limits
        .iter()
        .map(|&(metric, limit)| {
            let value = match metric {
                Metric::Flip => output.and_then(|o| o.metrics.flip_mean),
                Metric::Rmse => output.map(|o| o.metrics.rmse),
                Metric::Max => output.map(|o| o.metrics.max_abs),
                Metric::Time => r.timing.as_ref().and_then(|t| t.frame_ratio),
                Metric::Memory => Some(r.b.memory_bytes as f64 / r.a.memory_bytes.max(1) as f64),
            };
            Threshold {
                metric,
                limit,
                value,
                // A metric that could not be measured does not pass silently.
                crossed: value.is_none_or(|v| v > limit || v.is_nan()),
            }
        })
        .collect()
}
