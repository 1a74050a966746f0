//! `lightbench sweep`: what accuracy costs in time. For every point of a sweep spec (scenes,
//! sizes, variant options and parameter values), render the pipeline, time the effect's
//! passes and the frame on the GPU, and measure the compared resource against a reference
//! term from the path tracer. Sub-stages: `spec` (the file and its points), `settings`
//! (every point's settings checked up front), `measure` (error metrics), `rows` (the
//! resumable store, shards and merging), `pareto`, `report` (CSV, JSON, markdown, SVG);
//! here: the run itself.

pub mod measure;
pub mod pareto;
pub mod report;
pub mod rows;
pub mod settings;
pub mod spec;

use crate::diff::timing::stats;
use crate::error::{Error, Result};
use crate::gpu::{Executor, Gpu};
use crate::reference::{self, Budget, Reference, Settings};
use crate::scene::Scene;
use lightbench_compiler::Workspace;
use rows::Row;
use spec::{Loaded, Point};
use std::collections::HashMap;
use std::path::PathBuf;
use std::time::Instant;

pub struct Options {
    pub out: PathBuf,
    /// (K, N): measure the points whose index is K modulo N.
    pub shard: (usize, usize),
    /// Where references are cached (default: `OUT/references`).
    pub references: Option<PathBuf>,
    pub progress: bool,
}

/// What a run did.
pub struct Summary {
    pub measured: usize,
    pub skipped: usize,
    pub rows: Vec<Row>,
    pub points: usize,
    pub written: Vec<PathBuf>,
}

/// A scene as a spec names it, at a size (none: its own).
type SceneKey = (String, Option<(u32, u32)>);

/// Scenes and references (with their cache keys and the surface each pixel shows), each made
/// once per scene and size.
struct Inputs {
    scenes: HashMap<SceneKey, Scene>,
    references: HashMap<SceneKey, (Reference, String, measure::Surfaces)>,
}

pub fn run(gpu: &Gpu, l: &Loaded, opts: &Options) -> Result<Summary> {
    let points = spec::points(l);
    let mut rows = rows::load(&opts.out)?;
    if let Some(other) = rows.iter().find(|r| r.spec != l.fingerprint) {
        return Err(Error::Usage(format!(
            "{} holds rows of another sweep spec ({} `{}`): use a fresh --out, or delete its {}",
            opts.out.display(),
            other.sweep,
            other.spec,
            rows::FILE
        )));
    }
    let id = |p: &Point| p.id(&l.spec.compare);
    // Rows of points the spec still lists take their places in its current order; rows of
    // points it no longer lists stay in the file, out of the reports.
    for r in rows.iter_mut() {
        if let Some(p) = points.iter().find(|p| id(p) == r.id) {
            (r.index, r.points) = (p.index, points.len());
        }
    }
    let ws = Workspace::disk();
    let mine: Vec<&Point> = points.iter().filter(|p| p.index % opts.shard.1 == opts.shard.0).collect();
    let todo: Vec<&Point> = mine.iter().copied().filter(|p| !rows.iter().any(|r| r.id == id(p))).collect();
    let mut inputs = Inputs {
        scenes: HashMap::new(),
        references: HashMap::new(),
    };
    if let Some(first) = todo.first() {
        // The names the spec uses do not depend on the point: checked once, planned as it is.
        let scene = scene(&mut inputs, l, first)?.clone();
        let plan = check_up_front(&ws, &gpu.profile, l, &scene, &points)?;
        for note in crate::notes::effect_notes(&plan) {
            eprintln!("{note}");
        }
    }
    let bar = progress(todo.len(), opts.progress);
    for p in &todo {
        bar.set_message(id(p));
        let row = measure_point(gpu, &ws, l, (p, points.len()), opts, &mut inputs)?;
        rows = rows::add(&opts.out, row)?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mut listed: Vec<Row> = rows.into_iter().filter(|r| points.iter().any(|p| id(p) == r.id)).collect();
    listed.sort_by_key(|r| r.index);
    let written = report::write_all(&opts.out, &listed, points.len())?;
    Ok(Summary {
        measured: todo.len(),
        skipped: mine.len() - todo.len(),
        rows: listed,
        points: points.len(),
        written,
    })
}

/// What `run` checks before it renders anything (GPU-free): the pipeline plans on `scene`
/// (the first point's) and every point's settings fit it. Returns the default Plan.
pub fn check_up_front(
    ws: &Workspace,
    profile: &lightbench_compiler::profile::Profile,
    l: &Loaded,
    scene: &Scene,
    points: &[Point],
) -> Result<lightbench_compiler::plan::Plan> {
    // A pipeline that cannot be read is said at the spec's `pipeline`; one that does not
    // compile brings its own located diagnostics.
    let plan = crate::render::plan_configured(ws, (&l.pipeline(), None), (profile, scene), &[]).map_err(|e| match Error::from(e) {
        e @ (Error::Scene(crate::scene::Error::Io { .. }) | Error::Usage(_) | Error::Param(_)) => l.error_at("pipeline:", e),
        e => e,
    })?;
    let checked = ws.session().load_checked(&l.pipeline(), None, profile);
    let checked = checked.ok_or_else(|| Error::Input(format!("{}: the pipeline has errors", l.pipeline().display())))?;
    settings::check(l, &plan.exe.plan, &checked, points)?;
    Ok(plan.exe.plan)
}

fn progress(n: usize, visible: bool) -> indicatif::ProgressBar {
    if !visible {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(n as u64);
    if let Ok(st) = indicatif::ProgressStyle::with_template("sweep {bar:30} {pos}/{len} points, ETA {eta}  {msg}") {
        bar.set_style(st);
    }
    bar
}

fn scene<'a>(inputs: &'a mut Inputs, l: &Loaded, p: &Point) -> Result<&'a Scene> {
    let key = (p.scene.clone(), p.size);
    if !inputs.scenes.contains_key(&key) {
        let s = load_scene(l, p)?;
        inputs.scenes.insert(key.clone(), s);
    }
    Ok(&inputs.scenes[&key])
}

/// A point's scene at its size; a scene that does not load is said at its name in `scenes`.
pub fn load_scene(l: &Loaded, p: &Point) -> Result<Scene> {
    crate::scene::load::load_sized(&l.scene(&p.scene), p.size, &l.effects)
        .map_err(|e| l.error_in("scenes", &format!("\"{}\"", p.scene), Error::from(e)))
}

fn reference_for(gpu: &Gpu, inputs: &mut Inputs, l: &Loaded, p: &Point, opts: &Options) -> Result<()> {
    let key = (p.scene.clone(), p.size);
    if inputs.references.contains_key(&key) {
        return Ok(());
    }
    let scene = scene(inputs, l, p)?.clone();
    let r = &l.spec.reference;
    let settings = Settings {
        budget: Budget::Spp(r.spp),
        terms: vec![r.term],
        ao_radius: r.ao_radius,
        ao_falloff: r.ao_falloff,
        seed: r.seed,
        brdf: reference::Brdf::BlinnPhong,
        sample_emitters: true,
        integrator: reference::Integrator::default(),
    };
    let device = match r.device {
        spec::ReferenceDevice::Cpu => reference::store::Device::Cpu,
        spec::ReferenceDevice::Gpu => reference::store::Device::Gpu(gpu.info.name.clone()),
    };
    let cache_key = reference::store::key_on(&scene, &settings, &device);
    let dir = opts
        .references
        .clone()
        .unwrap_or_else(|| opts.out.join("references"))
        .join(&cache_key);
    let made = match r.device {
        spec::ReferenceDevice::Cpu => reference::store::cached(&scene, &settings, &dir, false)?.0,
        spec::ReferenceDevice::Gpu => {
            // Said at the spec's `device`, naming the scene.
            crate::gpu_reference::check(&scene, &settings).map_err(|e| l.error_at("device", e))?;
            let (pipeline, ws) = crate::gpu_reference::source(None)?;
            let tracer = crate::gpu_reference::Tracer {
                ws: &ws,
                pipeline: &pipeline,
            };
            let render = || crate::gpu_reference::render(gpu, &tracer, &scene, &settings, false);
            reference::store::cached_on(&scene, (&settings, &device), &dir, render)?.0
        }
    };
    let surfaces = measure::Surfaces {
        seen: reference::surfaces_seen(&scene),
        names: scene.meshes.iter().map(|m| m.name.clone()).collect(),
    };
    inputs.references.insert(key, (made, cache_key, surfaces));
    Ok(())
}

/// The point's compared resource, if its configuration has it (located where it is named:
/// the spec's `compare`, or the point's own).
fn check_compare(l: &Loaded, plan: &lightbench_compiler::plan::Plan, p: &Point) -> Result<()> {
    if plan.resource(&p.compare).is_some() {
        return Ok(());
    }
    let (needle, msg) = (
        format!("\"{}\"", p.compare),
        format!("this configuration has no resource `{}`", p.compare),
    );
    Err(if p.compare == l.spec.compare {
        l.error_in("compare", &needle, msg)
    } else {
        l.error_at(&needle, msg)
    })
}

fn measure_point(gpu: &Gpu, ws: &Workspace, l: &Loaded, (p, total): (&Point, usize), opts: &Options, inputs: &mut Inputs) -> Result<Row> {
    reference_for(gpu, inputs, l, p, opts)?;
    let scene = scene(inputs, l, p)?.clone();
    let pipeline = l.pipeline();
    let configured = crate::render::plan_configured(ws, (&pipeline, None), (&gpu.profile, &scene), &p.settings)?;
    check_compare(l, &configured.exe.plan, p)?;
    let mut ex = Executor::new(gpu, &configured.exe, &scene)?;
    ex.set_reuse(false);
    for (name, value) in &configured.params {
        ex.set_param(name, value.clone())?;
    }
    let (effect, frame, timing) = time_frames(gpu, &mut ex, l)?;
    let estimate = ex.read_texture(gpu, &p.compare, 0, 0)?;
    let (reference, key, surfaces) = &inputs.references[&(p.scene.clone(), p.size)];
    let term = reference
        .term(l.spec.reference.term)
        .ok_or_else(|| Error::Usage("the reference lacks its term".into()))?;
    let error = measure::error(&estimate, term, &p.compare, Some(surfaces)).map_err(|e| l.error_at("compare", e))?;
    Ok(Row {
        spec: l.fingerprint.clone(),
        sweep: l.name.clone(),
        index: p.index,
        points: total,
        id: p.id(&l.spec.compare),
        scene: scene.name.clone(),
        size: scene.size,
        settings: p.varying.clone(),
        variants: configured
            .exe
            .plan
            .variants
            .iter()
            .map(|v| (v.variant.clone(), v.option.clone()))
            .collect(),
        effect_ms: effect,
        frame_ms: frame,
        timing: timing.into(),
        error,
        reference: key.clone(),
        reference_spp: reference.spp,
    })
}

type Timed = (Option<crate::diff::timing::Stats>, Option<crate::diff::timing::Stats>, &'static str);

/// Warm-up frames, then the measured ones: per frame the effect's GPU ms (its passes
/// summed) and the frame's (all passes; wall-clock where the adapter has no timestamps).
/// Time stands still (every frame at t = 0) so the image matches the reference's scene.
fn time_frames(gpu: &Gpu, ex: &mut Executor, l: &Loaded) -> Result<Timed> {
    let inputs = ex.inputs(0.0);
    for _ in 0..l.spec.warmup {
        ex.render_frame(gpu, &inputs)?;
    }
    let (mut effect, mut frame, mut wall) = (vec![], vec![], vec![]);
    for _ in 0..l.spec.frames {
        let start = Instant::now();
        ex.render_frame(gpu, &inputs)?;
        wall.push(start.elapsed().as_secs_f64() * 1e3);
        let gpu_ms: Option<f64> = ex.last_timings.iter().map(|t| t.gpu_ms).sum();
        let effect_ms: Option<f64> = ex
            .last_timings
            .iter()
            .filter(|t| l.spec.effect.contains(&t.pass))
            .map(|t| t.gpu_ms)
            .sum();
        // An empty float sum is -0.0 (passes all culled): count it as 0.
        frame.extend(gpu_ms.map(|v| v + 0.0));
        effect.extend(effect_ms.map(|v| v + 0.0));
    }
    if frame.is_empty() {
        return Ok((None, stats(&wall), "wall"));
    }
    Ok((stats(&effect), stats(&frame), "gpu"))
}
