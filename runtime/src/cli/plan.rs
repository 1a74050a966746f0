//! `lightbench plan`: the Plan for one configuration, as text, JSON or Graphviz.

use super::{usage_error, Format, EXIT_ERRORS, EXIT_OK};
use crate::error::{Error, Result};
use lightbench_compiler::ir::LightKind;
use lightbench_compiler::plan;
use lightbench_compiler::scene::{SceneFeatures, MAX_SIZE};
use lightbench_compiler::Session;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    pub file: PathBuf,
    /// Choose a variant option, e.g. --variant cube_shadow=multiview (repeatable).
    #[arg(long = "variant", value_name = "K=V")]
    pub variants: Vec<String>,
    /// Scene file (.ron), glTF model or built-in scene (cornell, cornell_lamp, colonnade, many_lights, panes).
    #[arg(long)]
    pub scene: Option<String>,
    /// Set a parameter's value in the Plan, e.g. --param exposure.ev=2 (repeatable; typed and
    /// range-checked).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    #[arg(long, default_value = "vulkan")]
    pub profile: String,
    /// Say why each variant option was chosen and each pass culled; show full layouts.
    #[arg(long)]
    pub explain: bool,
    /// Print a Graphviz graph instead.
    #[arg(long, conflicts_with_all = ["explain", "json"])]
    pub dot: bool,
    /// Print the Plan as JSON (format version in `format`; specified in docs/plan.md).
    #[arg(long)]
    pub json: bool,
    /// Print each resource's memory, the passes using it, and which transient resources can
    /// share memory (logical vs physical bytes).
    #[arg(long, conflicts_with_all = ["explain", "json", "dot"])]
    pub memory: bool,
    /// Resolution for sizes and the memory estimate (default: the scene's, else 1280x720).
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Lights per kind for the memory estimate when no scene is given, e.g. point=4,spot=2.
    #[arg(long, value_name = "KIND=N,...")]
    pub lights: Option<String>,
    #[arg(long)]
    pub shaders: Option<PathBuf>,
}

/// The most lights of one kind `--lights` takes (per-light resources scale with it).
pub const MAX_PLAN_LIGHTS: u32 = 4096;

pub fn parse_size(s: &str) -> Result<(u32, u32)> {
    let bad = |why: String| Error::Usage(why);
    let (w, h) = s
        .split_once(['x', 'X', '×'])
        .ok_or_else(|| bad(format!("invalid size `{s}`: expected WxH, e.g. 1920x1080")))?;
    let w: u32 = w.trim().parse().map_err(|_| bad(format!("invalid width in `{s}`")))?;
    let h: u32 = h.trim().parse().map_err(|_| bad(format!("invalid height in `{s}`")))?;
    if w == 0 || h == 0 || w > MAX_SIZE || h > MAX_SIZE {
        return Err(bad(format!("size `{s}` out of range: width and height must be 1 to {MAX_SIZE}")));
    }
    Ok((w, h))
}

fn parse_lights(s: &str) -> Result<Vec<(LightKind, u32)>> {
    let mut out = vec![];
    for part in s.split(',').filter(|p| !p.is_empty()) {
        let (k, n) = part
            .split_once('=')
            .ok_or_else(|| Error::Usage(format!("invalid light count `{part}`: expected KIND=N")))?;
        let kind = match k.trim().to_ascii_lowercase().as_str() {
            "directional" => LightKind::Directional,
            "spot" => LightKind::Spot,
            "point" => LightKind::Point,
            "area" => LightKind::Area,
            other => {
                return Err(Error::Usage(format!(
                    "unknown light kind `{other}`: expected directional, spot, point or area (an emissive mesh)"
                )))
            }
        };
        let n: u32 = n.trim().parse().ok().filter(|n| *n <= MAX_PLAN_LIGHTS).ok_or_else(|| {
            Error::Usage(format!(
                "invalid count in `{part}`: expected a whole number from 0 to {MAX_PLAN_LIGHTS}"
            ))
        })?;
        if out.iter().any(|(k, _)| *k == kind) {
            return Err(Error::Usage(format!("--lights names `{}` twice", kind.name().to_lowercase())));
        }
        out.push((kind, n));
    }
    Ok(out)
}

pub fn run(a: Args) -> i32 {
    let profile = match super::profile(&a.profile) {
        Ok(p) => p,
        Err(e) => return usage_error(e),
    };
    let (variants, params) = match (
        super::parse_variants(&a.variants),
        super::parse_assignments("--param", "NAME=VALUE", &a.params),
    ) {
        (Ok(v), Ok(p)) => (v, p),
        (Err(e), _) | (_, Err(e)) => return usage_error(e),
    };
    if !a.file.is_file() {
        return usage_error(format!("no such file: {}", a.file.display()));
    }
    // One workspace: planning again with parameters reuses the compiled shaders.
    let ws = lightbench_compiler::Workspace::disk();
    let mut s = ws.session();
    let scene = match plan_scene(&a, &mut s) {
        Ok(sf) => sf,
        Err(code) => return code,
    };
    let plan = s.plan_file(&a.file, a.shaders.as_deref(), &profile, &scene, &variants);
    if plan.is_none() {
        // A --variant typo is a usage error (exit 2), as a --param typo is.
        if let Some(e) = crate::render::request_error(&s) {
            return usage_error(Error::from(e));
        }
    }
    super::check::emit(&s, Format::Human);
    let Some(mut plan) = plan else { return EXIT_ERRORS };
    // Parameters may size resources (`size: Param(..)`): plan again with them.
    if !params.is_empty() {
        let values = match crate::render::parse_params(&plan, &params).and_then(|p| crate::render::param_values(&plan, &p)) {
            Ok(v) => v,
            Err(e) => return usage_error(Error::from(e)),
        };
        let mut s2 = ws.session();
        let exe = s2.executable_with(&a.file, a.shaders.as_deref(), (&profile, &scene), &variants, &values);
        super::check::emit(&s2, Format::Human);
        let Some(exe) = exe else { return EXIT_ERRORS };
        plan = exe.plan;
    }
    if let Err(e) = set_params(&mut plan, &params) {
        return usage_error(e);
    }
    print_plan(&a, &plan)
}

/// What the Plan is for: the scene (`--scene`) or every feature, at `--size`, with
/// `--lights` counts when planning without a scene. `Err` is the exit code.
fn plan_scene(a: &Args, s: &mut Session) -> std::result::Result<SceneFeatures, i32> {
    let mut scene = match &a.scene {
        // What planning needs of it (its models' JSON, no geometry or texture).
        Some(spec) => match crate::scene::features_in(s, spec) {
            Some(features) => features,
            None => {
                super::check::emit(s, Format::Human);
                return Err(EXIT_ERRORS);
            }
        },
        None => SceneFeatures::everything(),
    };
    if let Some(sz) = &a.size {
        scene.size = parse_size(sz).map_err(usage_error)?;
    }
    if let Some(l) = &a.lights {
        if a.scene.is_some() {
            return Err(usage_error("--lights is for planning without a scene; the scene's lights are used"));
        }
        // Lights cast shadows unless a scene says otherwise.
        for (k, n) in parse_lights(l).map_err(usage_error)? {
            scene.lights.insert(k, n);
            scene.casters.insert(k, n);
        }
    }
    Ok(scene)
}

/// `--param` values become the values the Plan carries.
fn set_params(plan: &mut plan::Plan, params: &[(String, String)]) -> Result<()> {
    for (name, value) in crate::render::parse_params(plan, params)? {
        if let Some(p) = plan.params.iter_mut().find(|p| p.name == name) {
            eprintln!("param {name} = {} (was {})", value.describe(), p.default.describe());
            p.default = value;
        }
    }
    Ok(())
}

fn print_plan(a: &Args, plan: &plan::Plan) -> i32 {
    if a.dot {
        print!("{}", plan::to_dot(plan));
    } else if a.memory {
        print!("{}", plan::memory_text(plan));
    } else if a.json {
        match serde_json::to_string_pretty(plan) {
            Ok(j) => println!("{j}"),
            Err(e) => {
                eprintln!("error: cannot serialize plan: {e}");
                return EXIT_ERRORS;
            }
        }
    } else {
        print!("{}", plan::to_text(plan, a.explain));
    }
    EXIT_OK
}
