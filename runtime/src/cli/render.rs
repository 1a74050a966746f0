//! `lightbench render`: compile, run headless, save the output and optional dumps, timings
//! and a manifest.

use super::{failed, usage_error, EXIT_ERRORS, EXIT_OK};
use crate::error::{Error, Result};
use crate::gpu::{DeviceOptions, Executor, Gpu};
use crate::io::fnv1a;
use crate::io::write_atomic;
use crate::render::{compile_in, parse_params, render_scene};
use crate::scene::Scene;
use lightbench_compiler::Executable;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Pipeline file (.ron or .lbp); default `pipelines/deferred.ron`, or the copy bundled
    /// in the binary when there is none on disk.
    #[arg(long)]
    pub pipeline: Option<PathBuf>,
    /// Scene file (.ron), glTF model (.gltf, .glb) or built-in scene: cornell, cornell_lamp, colonnade, many_lights, panes.
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    #[command(flatten)]
    pub effects: super::EffectArgs,
    /// Choose a variant option, e.g. --variant cube_shadow=multiview (repeatable).
    #[arg(long = "variant", value_name = "K=V")]
    pub variants: Vec<String>,
    /// Override a parameter, e.g. --param exposure.ev=2 or --param ambient.color=0.1,0.1,0.1 (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// Contents of an `external: true` resource: a PNG/EXR for a texture, raw bytes or a JSON
    /// array of numbers for a buffer (repeatable).
    #[arg(long = "input", value_name = "NAME=FILE")]
    pub inputs: Vec<String>,
    /// Output size, overriding the scene's.
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Frames to render, 1 or more (history and animation advance by 1/60 s per frame).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub frames: u32,
    /// Output image: .png (the tone-mapped output, sRGB) or .exr (the pipeline's `hdr_output`,
    /// linear, before tone mapping; the output if it names none).
    #[arg(long, default_value = "lightbench.png")]
    pub out: PathBuf,
    /// Resources to read back after the last frame, comma-separated (every light and layer).
    #[arg(long, value_name = "NAME,NAME...")]
    pub dump: Option<String>,
    #[arg(long, default_value = "dump")]
    pub dump_dir: PathBuf,
    /// Image type of dumps: exr (every channel, linear float) or png (8-bit, clamped).
    #[arg(long, value_enum, default_value = "exr")]
    pub dump_format: super::DumpFormat,
    /// Print a per-pass table: GPU ms (timestamp queries) and CPU encode µs (means over the
    /// frames each pass ran in), and in how many frames it ran.
    #[arg(long)]
    pub timings: bool,
    /// Run every pass every frame, even when nothing it depends on changed.
    #[arg(long)]
    pub no_reuse: bool,
    /// Let transient resources share memory where the Plan allows (`plan --memory`); every
    /// pass then runs every frame, and they cannot be dumped.
    #[arg(long)]
    pub alias: bool,
    /// Keep rendering, headless, and reload when the pipeline, a shader it reads or the scene
    /// file changes: each reload's outcome and latency is printed, `--out` rewritten after it.
    #[arg(long)]
    pub watch: bool,
    /// With `--watch`: stop after this many reloads (successful or not); default: never.
    #[arg(long, value_name = "N", requires = "watch")]
    pub watch_reloads: Option<u32>,
    #[arg(long, value_name = "FILE")]
    pub timings_json: Option<PathBuf>,
    /// Write a manifest: pipeline and shader hashes, variants, params, adapter, scene.
    #[arg(long, value_name = "FILE")]
    pub manifest: Option<PathBuf>,
    #[arg(long)]
    pub shaders: Option<PathBuf>,
    #[arg(long, value_enum)]
    pub backend: Option<crate::gpu::device::BackendChoice>,
    /// Pick the adapter whose name contains this text.
    #[arg(long)]
    pub adapter: Option<String>,
}

pub fn run(a: Args) -> i32 {
    let variants = match super::parse_variants(&a.variants) {
        Ok(v) => v,
        Err(e) => return usage_error(e),
    };
    let params = match super::parse_assignments("--param", "NAME=VALUE", &a.params) {
        Ok(v) => v,
        Err(e) => return usage_error(e),
    };
    let inputs: Vec<(String, PathBuf)> = match super::parse_assignments("--input", "NAME=FILE", &a.inputs) {
        Ok(v) => v.into_iter().map(|(n, f)| (n, PathBuf::from(f))).collect(),
        Err(e) => return usage_error(e),
    };
    let ext = a.out.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase());
    if !matches!(ext.as_deref(), Some("png" | "exr")) {
        return usage_error(format!("--out {}: use a .png or .exr file name", a.out.display()));
    }
    let (pipeline, ws) = match resolve_pipeline(a.pipeline.as_deref()) {
        Ok(p) => p,
        Err(e) => return usage_error(e),
    };
    if let Err(e) = distinct_outputs(&a) {
        return usage_error(e);
    }
    let size = match a.size.as_deref().map(super::plan::parse_size).transpose() {
        Ok(s) => s,
        Err(e) => return usage_error(e),
    };
    match execute(&a, (&pipeline, &ws), (&variants, &params), &inputs, size) {
        Ok(()) => EXIT_OK,
        // Compile and scene errors are rendered diagnostics already.
        Err(Error::Executor(crate::gpu::Error::Compile(report)) | Error::Scene(crate::scene::Error::Scene(report))) => {
            eprint!("{report}");
            EXIT_ERRORS
        }
        Err(e) => failed(e),
    }
}

/// The pipeline to render and the workspace that reads it: the file named; else
/// `pipelines/deferred.ron` on disk; else the copy bundled in the binary.
pub(super) fn resolve_pipeline(named: Option<&Path>) -> Result<(PathBuf, lightbench_compiler::Workspace)> {
    match named {
        Some(p) if !p.is_file() => Err(Error::Usage(format!("no such pipeline file: {}", p.display()))),
        Some(p) => Ok((p.to_path_buf(), lightbench_compiler::Workspace::disk())),
        None if Path::new(crate::bundled::DEFAULT_PIPELINE).is_file() => Ok((
            PathBuf::from(crate::bundled::DEFAULT_PIPELINE),
            lightbench_compiler::Workspace::disk(),
        )),
        None => {
            eprintln!(
                "no {} here: rendering the one bundled in lightbench (`lightbench init DIR` writes the bundled pipelines, shaders and scenes out)",
                crate::bundled::DEFAULT_PIPELINE
            );
            Ok((crate::bundled::default_pipeline(), crate::bundled::workspace()))
        }
    }
}

/// `key=value` pairs as given (variant choices, parameter texts).
type Settings<'a> = &'a [(String, String)];

fn execute(
    a: &Args,
    (pipeline, ws): (&Path, &lightbench_compiler::Workspace),
    (variants, params): (Settings, Settings),
    inputs: &[(String, PathBuf)],
    size: Option<(u32, u32)>,
) -> Result<()> {
    let started = Instant::now();
    // Watching, the models are kept: a change to one parses that one again.
    let mut models = match a.watch {
        true => crate::scene::model_cache::ModelCache::keeping(),
        false => crate::scene::model_cache::ModelCache::default(),
    };
    let scene = crate::scene::load::load_sized_with(&a.scene, size, &a.effects.effects, &mut models)?;
    let loaded = started.elapsed();
    let gpu = Gpu::new(&DeviceOptions {
        backend: a.backend,
        adapter: a.adapter.clone(),
    })?;
    eprintln!("{}", gpu.describe());
    if a.watch {
        return watch(a, &gpu, pipeline, (scene, models), (variants, params));
    }
    // One workspace: planning again with parameters reuses the compiled shaders.
    let (mut exe, warnings) = compile_in(ws, &gpu, pipeline, a.shaders.as_deref(), &scene, variants)?;
    eprint!("{warnings}");
    let parsed = parse_params(&exe.plan, params)?;
    if !parsed.is_empty() {
        // Parameters may size resources (`size: Param(..)`): plan again with them.
        let values = crate::render::param_values(&exe.plan, &parsed)?;
        exe = crate::render::compile_with(ws, &gpu, (pipeline, a.shaders.as_deref()), &scene, variants, &values)?.0;
    }
    for v in &exe.plan.variants {
        if let Some(r) = &v.reason {
            eprintln!("variant {} = {} ({r})", v.variant, v.option);
        }
    }
    for note in crate::notes::effect_notes(&exe.plan) {
        eprintln!("{note}");
    }
    if let Some(note) = area_lights_note(&exe.plan, &scene) {
        eprintln!("{note}");
    }
    // Checked before rendering, so a typo costs no frames.
    let dumps = a.dump.as_deref().map(|l| dump_names(&exe, l, a.alias)).transpose()?;
    let params = parsed;
    // The scene is handed over: its textures are dropped once uploaded.
    let ex = render_scene(&gpu, &exe, scene, (a.frames, !a.no_reuse, a.alias), &params, inputs)?;
    if a.alias {
        let (logical, physical) = (exe.plan.memory_bytes, ex.resource_bytes());
        eprintln!(
            "resources: {} with transient memory aliased ({} each its own)",
            lightbench_compiler::plan::mib_text(physical),
            lightbench_compiler::plan::mib_text(logical)
        );
    }
    save_output(a, &gpu, &ex, &exe)?;
    if let Some(names) = &dumps {
        dump(&gpu, &ex, names, &a.dump_dir, a.dump_format)?;
    }
    timings(a, &ex, loaded)?;
    if let Some(p) = &a.manifest {
        manifest(p, (a, pipeline), &gpu, &ex, &exe)?;
    }
    Ok(())
}

/// Said when a pass shades the scene's area lights and some emissive triangles are over the
/// limit (the dimmest are left out).
fn area_lights_note(plan: &lightbench_compiler::plan::Plan, scene: &Scene) -> Option<String> {
    use lightbench_compiler::layout::BindSource;
    let binds = plan.passes.iter().flat_map(|p| &p.bind_groups).flat_map(|g| &g.entries);
    if !binds.into_iter().any(|e| e.source == BindSource::AreaLights) {
        return None;
    }
    let (_, dropped) = crate::gpu::scene_gpu::area_lights(scene);
    (dropped > 0).then(|| {
        let max = crate::gpu::scene_gpu::MAX_AREA_LIGHTS;
        format!(
            "note: the scene has {} emissive triangles; the {max} most powerful light it, {dropped} are left out",
            max + dropped
        )
    })
}

/// `--watch`: render continuously, reloading on changes (see `crate::reload`).
fn watch(
    a: &Args,
    gpu: &Gpu,
    pipeline: &Path,
    (scene, models): (Scene, crate::scene::model_cache::ModelCache),
    (variants, params): (Settings, Settings),
) -> Result<()> {
    if pipeline.starts_with(crate::bundled::ROOT) {
        return Err(Error::Usage(
            "--watch needs pipeline files on disk to watch: `lightbench init DIR` writes the bundled ones out".into(),
        ));
    }
    let scene_file = Path::new(&a.scene);
    let scene_file = scene_file.is_file().then_some(scene_file);
    let (mut reloader, exe) = crate::reload::Reloader::new(gpu, (pipeline, a.shaders.as_deref()), (&scene, scene_file), variants)?;
    reloader.add_effects(&a.effects.effects);
    reloader.keep_models(models);
    let mut ex = Executor::with_scene(gpu, &exe, scene)?;
    for (name, value) in parse_params(&exe.plan, params)? {
        ex.set_param(&name, value)?;
    }
    let frame = |ex: &mut Executor| -> Result<()> {
        let inputs = ex.inputs(ex.frame_index as f32 / 60.0);
        Ok(ex.render_frame(gpu, &inputs)?)
    };
    frame(&mut ex)?;
    ex.read_texture(gpu, &ex.plan().output_resource().name.clone(), 0, 0)?
        .save(&a.out)?;
    eprintln!("watching {} (and the shaders and scene it reads); Ctrl-C stops", pipeline.display());
    let mut reloads = 0;
    while a.watch_reloads.is_none_or(|n| reloads < n) {
        let Some(outcome) = reloader.poll(gpu, &mut ex, std::time::Duration::from_millis(16)) else {
            frame(&mut ex)?;
            continue;
        };
        match outcome {
            crate::reload::Outcome::Rewatched { folders } => eprintln!("{}", crate::reload::rewatched(&folders)),
            crate::reload::Outcome::Reloaded {
                latency, compile, report, ..
            } => {
                reloads += 1;
                let start = Instant::now();
                frame(&mut ex)?;
                let total = latency + start.elapsed();
                ex.read_texture(gpu, &ex.plan().output_resource().name.clone(), 0, 0)?
                    .save(&a.out)?;
                eprintln!(
                    "reloaded: first new frame {:.1} ms after the change (compiling {:.1} ms); wrote {}{}",
                    total.as_secs_f64() * 1e3,
                    compile.as_secs_f64() * 1e3,
                    a.out.display(),
                    report.scene_kept.map(kept_line).unwrap_or_default()
                );
            }
            crate::reload::Outcome::Failed { message, .. } => {
                reloads += 1;
                eprint!("{message}");
                eprintln!("reload failed: still rendering the last good pipeline");
            }
        }
    }
    Ok(())
}

/// What a reloaded scene kept: its models as they were (files unchanged, not parsed again)
/// and what stayed resident on the GPU, unchanged.
fn kept_line(k: crate::gpu::scene_gpu::Kept) -> String {
    let blas = k.blas.map(|(n, of)| format!(", {n} of {of} BLAS")).unwrap_or_default();
    let models = k
        .models
        .map(|(n, of)| format!(" ({n} of {of} models as they were)"))
        .unwrap_or_default();
    format!(
        "; scene reloaded{models}, kept resident: {} of {} meshes, {} of {} textures{blas}",
        k.meshes.0, k.meshes.1, k.textures.0, k.textures.1
    )
}

/// `--out`: the output, or for an .exr the pipeline's linear `hdr_output` when it names one.
fn save_output(a: &Args, gpu: &Gpu, ex: &Executor, exe: &Executable) -> Result<()> {
    let exr = a.out.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    let saved = match exe.plan.hdr_output.filter(|_| exr) {
        Some(h) => exe.plan.res(h),
        None => exe.plan.output_resource(),
    };
    let img = ex.read_texture(gpu, &saved.name, 0, 0)?;
    img.save(&a.out)?;
    eprintln!(
        "wrote {} ({}, {}×{}, {} frame(s), scene {})",
        a.out.display(),
        saved.name,
        img.width,
        img.height,
        a.frames.max(1),
        ex.scene().name
    );
    Ok(())
}

fn timings(a: &Args, ex: &Executor, scene_load: std::time::Duration) -> Result<()> {
    if a.timings {
        println!(
            "scene load {:.1} ms; peak memory {}",
            scene_load.as_secs_f64() * 1e3,
            crate::memory::mib(crate::memory::peak_resident())
        );
        let frames = ex.timing_log.len();
        println!("{:<26} {:>5} {:>10} {:>12} {:>8}", "pass", "reps", "GPU ms", "CPU enc µs", "ran");
        let mut cold_only = false;
        for (i, t) in ex.last_timings.iter().enumerate() {
            let ran: Vec<(usize, &crate::gpu::PassTiming)> = ex
                .timing_log
                .iter()
                .enumerate()
                .filter_map(|(f, frame)| frame.get(i).map(|t| (f, t)))
                .filter(|(_, t)| !t.reused)
                .collect();
            // Means over the warm frames the pass ran in (reused frames cost nothing; the
            // first frame pays for first use): the first frame only when it ran in no other.
            let warm: Vec<&crate::gpu::PassTiming> = ran.iter().filter(|(f, _)| *f > 0).map(|(_, t)| *t).collect();
            let cold = warm.is_empty() && frames > 1 && !ran.is_empty();
            let counted: Vec<&crate::gpu::PassTiming> = if warm.is_empty() {
                ran.iter().map(|(_, t)| *t).collect()
            } else {
                warm
            };
            let mean = |v: Vec<f64>| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
            let gpu_ms = mean(counted.iter().filter_map(|t| t.gpu_ms).collect());
            let cpu = mean(counted.iter().map(|t| t.cpu_encode_us).collect()).unwrap_or(0.0);
            let mark = if cold { "*" } else { "" };
            let gpu_ms = gpu_ms.map(|v| format!("{v:.3}{mark}")).unwrap_or_else(|| "n/a".into());
            cold_only |= cold;
            let runs = format!("{}/{frames}", ran.len());
            println!("{:<26} {:>5} {:>10} {:>12.1} {:>8}", t.pass, t.repetitions, gpu_ms, cpu, runs);
        }
        if cold_only {
            println!("* ran only in the first frame (cold: first use), then reused; --no-reuse times it every frame");
        }
    }
    if let Some(p) = &a.timings_json {
        // One array per frame: a reused pass shows `"reused": true` in the frames it skipped.
        let text = serde_json::to_string_pretty(&ex.timing_log).map_err(|e| Error::io(p, e))?;
        write_atomic(p, text.as_bytes())?;
    }
    Ok(())
}

fn manifest(p: &Path, (a, pipeline): (&Args, &Path), gpu: &Gpu, ex: &Executor, exe: &Executable) -> Result<()> {
    let values = ex.inputs(0.0).params;
    let scene = ex.scene();
    let files: Vec<serde_json::Value> = exe
        .files
        .iter()
        .map(|f| {
            let hash = crate::bundled::read(f)
                .or_else(|| lightbench_compiler::vfs::read_bytes(f, lightbench_compiler::vfs::MAX_FILE_BYTES).ok())
                .map(|b| format!("{:016x}", fnv1a(&b)))
                .unwrap_or_else(|| "unreadable".into());
            serde_json::json!({"file": f.display().to_string(), "fnv1a64": hash})
        })
        .collect();
    let m = serde_json::json!({
        "pipeline": pipeline.display().to_string(),
        "files": files,
        "variants": exe.plan.variants,
        "params": exe.plan.params.iter().map(|p| serde_json::json!({"name": p.name, "value": values.value_of(p)})).collect::<Vec<_>>(),
        "adapter": {"name": gpu.info.name, "backend": format!("{:?}", gpu.info.backend), "driver": gpu.info.driver, "features": gpu.profile.features.iter().map(|f| f.name()).collect::<Vec<_>>()},
        "scene": scene.name,
        "size": [scene.size.0, scene.size.1],
        "frames": a.frames.max(1),
        "output": a.out.display().to_string(),
    });
    let text = serde_json::to_string_pretty(&m).map_err(|e| Error::io(p, e))?;
    Ok(write_atomic(p, text.as_bytes())?)
}

/// The `--dump` list, each name a resource of the Plan (with a suggestion when not).
/// With `alias`, a resource living in another's memory, or lending its own, is refused: after
/// the frame it holds what last lived there.
fn dump_names(exe: &Executable, list: &str, alias: bool) -> Result<Vec<String>> {
    let names: Vec<String> = list.split(',').map(str::trim).filter(|n| !n.is_empty()).map(String::from).collect();
    if names.is_empty() {
        return Err(Error::Usage("--dump: no resource names given".into()));
    }
    let known: Vec<&str> = exe.plan.resources.iter().map(|r| r.name.as_str()).collect();
    for n in &names {
        if !known.contains(&n.as_str()) {
            let hint = lightbench_compiler::diag::did_you_mean(n, known.iter().copied())
                .map(|m| format!("did you mean `{m}`? "))
                .unwrap_or_default();
            return Err(Error::Usage(format!(
                "--dump: `{n}` is not a resource of this plan ({hint}resources: {})",
                known.join(", ")
            )));
        }
        if alias {
            if let Some(other) = memory_partner(&exe.plan, n) {
                return Err(Error::Usage(format!(
                    "--dump: `{n}` shares memory with `{other}` under --alias (after the frame it holds what last lived there); drop --alias to read it back"
                )));
            }
        }
    }
    Ok(names)
}

/// A resource whose memory `name` shares, or one living in `name`'s.
fn memory_partner(plan: &lightbench_compiler::plan::Plan, name: &str) -> Option<String> {
    let id = plan.resources.iter().position(|r| r.name == name)?;
    let r = &plan.resources[id];
    if let Some(o) = r.shares {
        return Some(plan.res(o).name.clone());
    }
    let lodger = plan.resources.iter().find(|x| x.shares.is_some_and(|o| o.0 as usize == id));
    lodger.map(|x| x.name.clone())
}

/// `--out`, `--manifest` and `--timings-json` must name different files, each one that may
/// be written (not a device, FIFO or directory): refused before any work.
fn distinct_outputs(a: &Args) -> std::result::Result<(), String> {
    let named = [
        ("--out", Some(&a.out)),
        ("--manifest", a.manifest.as_ref()),
        ("--timings-json", a.timings_json.as_ref()),
    ];
    let given: Vec<(&str, &PathBuf)> = named.iter().filter_map(|(f, p)| p.map(|p| (*f, p))).collect();
    for (flag, p) in &given {
        crate::files::replaceable(p).map_err(|e| format!("{flag} {}: {e}", p.display()))?;
    }
    for (i, (fa, pa)) in given.iter().enumerate() {
        for (fb, pb) in &given[i + 1..] {
            if crate::files::same_file(pa, pb) {
                return Err(format!(
                    "{fa} and {fb} name the same file ({}); each output needs its own",
                    pa.display()
                ));
            }
        }
    }
    Ok(())
}

/// Write each named resource: every light instance, layer and mip level, as EXR (all
/// channels, linear) or PNG (8-bit, clamped); buffers as JSON arrays of f32.
fn dump(gpu: &Gpu, ex: &Executor, names: &[String], dir: &Path, format: super::DumpFormat) -> Result<()> {
    for name in names {
        let res = ex
            .plan()
            .resource(name)
            .ok_or_else(|| Error::resource(format!("--dump: `{name}` vanished from the plan")))?;
        for (inst, layer) in ex.slices(name)? {
            let file = crate::io::slice_stem(name, res, (inst, layer), 0);
            if res.is_buffer() {
                let words = ex.read_buffer(gpu, name, inst)?;
                let path = dir.join(format!("{file}.json"));
                // Written as the shaders declare the words: `array<u32>` as whole numbers.
                use lightbench_compiler::plan::{ResourceShape, Words};
                let text = match res.shape {
                    ResourceShape::Buffer { words: Words::U32, .. } => {
                        serde_json::to_string(&words.iter().map(|w| w.to_bits()).collect::<Vec<_>>())
                    }
                    ResourceShape::Buffer { words: Words::I32, .. } => {
                        serde_json::to_string(&words.iter().map(|w| w.to_bits() as i32).collect::<Vec<_>>())
                    }
                    _ => serde_json::to_string(&words),
                }
                .map_err(|e| Error::io(&path, e))?;
                write_atomic(&path, text.as_bytes())?;
                eprintln!("dumped {}", path.display());
                continue;
            }
            for mip in 0..ex.mips(name)? {
                let part = crate::gpu::Part {
                    instance: inst,
                    layer,
                    mip,
                    previous: false,
                };
                let mut img = ex.read_part(gpu, name, part)?;
                if let lightbench_compiler::plan::ResourceShape::Texture { format, .. } = &res.shape {
                    if format.components() == 1 {
                        img.grey_from_red();
                    }
                }
                let stem = crate::io::slice_stem(name, res, (inst, layer), mip);
                let path = dir.join(format!("{stem}.{}", if format == super::DumpFormat::Png { "png" } else { "exr" }));
                img.save(&path)?;
                eprintln!("dumped {}", path.display());
            }
        }
    }
    Ok(())
}
