//! `lightbench render`: compile, run headless, save the output and optional dumps, timings
//! and a manifest.

use super::{usage_error, EXIT_ERRORS, EXIT_OK};
use crate::gpu::{DeviceOptions, Gpu};
use crate::io::write_atomic;
use crate::render::{compile, fnv1a, render};
use crate::scene::file as scene_file;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Pipeline file (.ron or .lbp).
    #[arg(long, default_value = "pipelines/deferred.ron")]
    pub pipeline: PathBuf,
    /// Scene file (.ron) or built-in scene: cornell, colonnade, many_lights.
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Choose a variant option, e.g. --variant cube_shadow=multiview (repeatable).
    #[arg(long = "variant", value_name = "K=V")]
    pub variants: Vec<String>,
    /// Output size, overriding the scene's.
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Frames to render (history and animation advance by 1/60 s per frame).
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// Output image: .png (sRGB) or .exr (linear float).
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
    /// Print a per-pass table: GPU ms (timestamp queries) and CPU encode µs.
    #[arg(long)]
    pub timings: bool,
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
    if !matches!(
        a.out
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref(),
        Some("png" | "exr")
    ) {
        return usage_error(format!("--out {}: use a .png or .exr file name", a.out.display()));
    }
    if !a.pipeline.is_file() {
        return usage_error(format!("no such pipeline file: {}", a.pipeline.display()));
    }
    let mut scene = match scene_file::load(&a.scene) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_ERRORS;
        }
    };
    if let Some(sz) = &a.size {
        match super::plan::parse_size(sz) {
            Ok(v) => scene.size = v,
            Err(e) => return usage_error(e),
        }
    }
    let gpu = match Gpu::new(&DeviceOptions {
        backend: a.backend,
        adapter: a.adapter.clone(),
    }) {
        Ok(g) => g,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_ERRORS;
        }
    };
    eprintln!("{}", gpu.describe());
    let (exe, warnings) = match compile(&gpu, &a.pipeline, a.shaders.as_deref(), &scene, &variants) {
        Ok(x) => x,
        Err(report) => {
            eprint!("{report}");
            return EXIT_ERRORS;
        }
    };
    eprint!("{warnings}");
    for v in &exe.plan.variants {
        if let Some(r) = &v.reason {
            eprintln!("variant {} = {} ({r})", v.variant, v.option);
        }
    }
    let ex = match render(&gpu, &exe, &scene, a.frames) {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_ERRORS;
        }
    };
    let out = match ex.read_texture(&gpu, &exe.plan.output, 0, 0) {
        Ok(img) => img,
        Err(e) => {
            eprintln!("error: reading the output `{}`: {e}", exe.plan.output);
            return EXIT_ERRORS;
        }
    };
    if let Err(e) = out.save(&a.out) {
        eprintln!("error: {e}");
        return EXIT_ERRORS;
    }
    eprintln!(
        "wrote {} ({}×{}, {} frame(s), scene {})",
        a.out.display(),
        out.width,
        out.height,
        a.frames.max(1),
        scene.name
    );
    if let Some(list) = &a.dump {
        if let Err(e) = dump(&gpu, &ex, list, &a.dump_dir, a.dump_format) {
            eprintln!("error: {e}");
            return EXIT_ERRORS;
        }
    }
    if a.timings {
        println!("{:<26} {:>5} {:>10} {:>12}", "pass", "reps", "GPU ms", "CPU enc µs");
        for t in &ex.last_timings {
            let gpu_ms = t.gpu_ms.map(|v| format!("{v:.3}")).unwrap_or_else(|| "n/a".into());
            println!("{:<26} {:>5} {:>10} {:>12.1}", t.pass, t.repetitions, gpu_ms, t.cpu_encode_us);
        }
    }
    if let Some(p) = &a.timings_json {
        let text = serde_json::to_string_pretty(&ex.last_timings).unwrap_or_default();
        if let Err(e) = write_atomic(p, text.as_bytes()) {
            eprintln!("error: {e}");
            return EXIT_ERRORS;
        }
    }
    if let Some(p) = &a.manifest {
        let files: Vec<serde_json::Value> = exe
            .files
            .iter()
            .map(|f| serde_json::json!({"file": f, "fnv1a64": std::fs::read(f).map(|b| format!("{:016x}", fnv1a(&b))).unwrap_or_else(|_| "unreadable".into())}))
            .collect();
        let m = serde_json::json!({
            "pipeline": a.pipeline.display().to_string(),
            "files": files,
            "variants": exe.plan.variants,
            "params": exe.plan.params.iter().map(|p| serde_json::json!({"name": p.name, "value": p.default})).collect::<Vec<_>>(),
            "adapter": {"name": gpu.info.name, "backend": format!("{:?}", gpu.info.backend), "driver": gpu.info.driver, "features": gpu.profile.features.iter().map(|f| f.name()).collect::<Vec<_>>()},
            "scene": scene.name,
            "size": [scene.size.0, scene.size.1],
            "frames": a.frames.max(1),
            "output": a.out.display().to_string(),
        });
        if let Err(e) = write_atomic(p, serde_json::to_string_pretty(&m).unwrap_or_default().as_bytes()) {
            eprintln!("error: {e}");
            return EXIT_ERRORS;
        }
    }
    EXIT_OK
}

/// Write each named resource: every light instance and layer, as EXR (all channels, linear)
/// or PNG (8-bit, clamped); buffers as JSON arrays of f32.
fn dump(gpu: &Gpu, ex: &crate::gpu::Executor, list: &str, dir: &Path, format: super::DumpFormat) -> Result<(), String> {
    for name in list.split(',').map(str::trim).filter(|n| !n.is_empty()) {
        let res = ex.plan.resource(name).ok_or_else(|| {
            let names: Vec<&str> = ex.plan.resources.iter().map(|r| r.name.as_str()).collect();
            format!("--dump: `{name}` is not a resource of this plan (resources: {})", names.join(", "))
        })?;
        let safe: String = name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        for (inst, layer) in ex.slices(name)? {
            let mut file = safe.clone();
            if !res.per_light.is_empty() {
                file += &format!(".light{inst}");
            }
            if res.layers > 1 {
                file += &format!(".layer{layer}");
            }
            if res.kind == "buffer" {
                let words = ex.read_buffer(gpu, name, inst)?;
                write_atomic(
                    &dir.join(format!("{file}.json")),
                    serde_json::to_string(&words).unwrap_or_default().as_bytes(),
                )?;
                continue;
            }
            let img = ex.read_texture(gpu, name, inst, layer)?;
            let path = dir.join(format!("{file}.{}", if format == super::DumpFormat::Png { "png" } else { "exr" }));
            img.save(&path)?;
            eprintln!("dumped {}", path.display());
        }
    }
    Ok(())
}
