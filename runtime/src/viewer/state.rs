//! Sub-stage `state` of the viewer: what is shown and how input changes it — the buffer
//! view, the selected light, the camera, parameters and variants — as `Action`s applied to a
//! running executor. Keys, widgets and `--script` lines all become actions: one code path.

use crate::error::{Error, Result};
use crate::gpu::{Executor, Gpu};
use crate::scene::{Camera, Scene};
use lightbench_compiler::format::TextureFormat;
use lightbench_compiler::ir::{Effect, ParamValue};
use lightbench_compiler::plan::{ParamValues, ResourceShape};
use lightbench_compiler::{Executable, Workspace};
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Show the next (previous) entry of `views()`.
    NextView,
    PrevView,
    /// The next (previous) light instance or layer of the shown resource.
    NextSlice,
    PrevSlice,
    View(String),
    SelectLight(usize),
    ToggleLight,
    /// Turn the selected spot or directional light: yaw and pitch, degrees.
    RotateLight(f32, f32),
    /// Move the camera in its own frame (right, up, forward), world units.
    Move(glam::Vec3),
    /// Turn the camera: yaw and pitch, degrees.
    Look(f32, f32),
    Param(String, ParamValue),
    Variant(String, String),
    Screenshot(PathBuf),
    /// Replace light `i` (kind, colour, intensity, position, direction, cone, shadows…).
    SetLight(usize, Box<crate::scene::Light>),
    AddLight(lightbench_compiler::ir::LightKind),
    /// Remove the selected light.
    RemoveLight,
    /// Call for an effect or stop calling for it (passes conditioned on it run or are culled).
    Effect(lightbench_compiler::ir::Effect, bool),
    /// Show the path-traced view of the same scene (the GPU reference, refining while nothing
    /// changes) in place of the raster output, or the raster output again.
    Trace(bool),
    /// `Trace` on when it is off, off when it is on (key T).
    ToggleTrace,
}

pub struct Viewer {
    pub ex: Executor,
    ws: Workspace,
    pipeline: PathBuf,
    shaders: Option<PathBuf>,
    pub variants: Vec<(String, String)>,
    pub scene: Scene,
    pub camera: Camera,
    /// 0: the output; then the Plan's textures in order.
    pub view: usize,
    pub slice: usize,
    pub light: usize,
    /// Frame time, ms, averaged exponentially (seed 000 §7.1: a running mean, not one frame).
    pub frame_ms: f64,
    pub frames: u64,
    /// Why the last change could not be made (shown until the next one succeeds).
    pub last_error: Option<String>,
    /// Each variant's options, with what the adapter lacks for those it cannot run.
    pub options: Vec<(String, Vec<OptionState>)>,
    /// Values of parameters the Plan fixes (sizes, repeat counts, shader constants) set here:
    /// each Plan is made with them.
    plan_params: ParamValues,
    /// Hot reload of the pipeline and shader files (not for the bundled pipeline).
    reloader: Option<crate::reload::Reloader>,
    /// What the last reload of the scene kept: its models as they were, and meshes, textures
    /// and BLAS resident on the GPU.
    pub scene_kept: Option<crate::gpu::scene_gpu::Kept>,
    /// The path-traced view, while it is shown (`Action::Trace`).
    pub traced: Option<super::traced::Traced>,
}

/// A variant option and, when the adapter cannot run it, what it needs.
pub type OptionState = (String, Option<String>);

/// Compile `pipeline` for `scene` with `variants` and the values of parameters the Plan fixes;
/// `Err` holds the rendered diagnostics.
fn compile(
    ws: &Workspace,
    (pipeline, shaders): (&Path, Option<&Path>),
    gpu: &Gpu,
    scene: &Scene,
    (variants, params): (&[(String, String)], &ParamValues),
) -> Result<Executable> {
    let mut s = ws.session();
    let exe = s.executable_with(pipeline, shaders, (&gpu.profile, &scene.features()), variants, params);
    exe.ok_or_else(|| Error::compile(s.render()))
}

impl Viewer {
    pub fn new(
        gpu: &Gpu,
        (ws, pipeline, shaders): (Workspace, &Path, Option<&Path>),
        scene: Scene,
        variants: &[(String, String)],
    ) -> Result<Viewer> {
        let exe = compile(&ws, (pipeline, shaders), gpu, &scene, (variants, &ParamValues::new()))?;
        let mut ex = Executor::new(gpu, &exe, &scene)?;
        // The panel's per-pass times may be a frame old; the frame is not waited for.
        ex.set_late_timestamps(true);
        let options = ws
            .session()
            .load_pipeline(pipeline)
            .map(|p| {
                p.variants
                    .iter()
                    .map(|v| {
                        let opts = v.options.iter().map(|o| {
                            let lacks: Vec<&str> = o
                                .requires
                                .iter()
                                .filter(|f| !gpu.profile.has(f.value))
                                .map(|f| f.value.name())
                                .collect();
                            (
                                o.name.value.clone(),
                                (!lacks.is_empty()).then(|| format!("needs {}", lacks.join(", "))),
                            )
                        });
                        (v.name.value.clone(), opts.collect())
                    })
                    .collect()
            })
            .unwrap_or_default();
        Ok(Viewer {
            ex,
            ws,
            pipeline: pipeline.to_path_buf(),
            shaders: shaders.map(Path::to_path_buf),
            variants: variants.to_vec(),
            camera: scene.camera.clone(),
            scene,
            view: 0,
            slice: 0,
            light: 0,
            frame_ms: 0.0,
            frames: 0,
            last_error: None,
            options,
            plan_params: ParamValues::new(),
            reloader: None,
            scene_kept: None,
            traced: None,
        })
    }

    /// The Plan again for the current scene and variants, swapped in at this frame boundary;
    /// with `lights_changed`, the executor takes the scene's lights and effects as they are
    /// now (its geometry stays on the GPU: nothing else of the scene can change here).
    fn rebuild(&mut self, gpu: &Gpu, lights_changed: bool) -> Result<()> {
        let exe = compile(
            &self.ws,
            (&self.pipeline, self.shaders.as_deref()),
            gpu,
            &self.scene,
            (&self.variants, &self.plan_params),
        )?;
        match lights_changed {
            true => self
                .ex
                .replace_lights(gpu, &exe, (self.scene.lights.clone(), self.scene.effects.clone()))?,
            false => self.ex.replace(gpu, &exe)?,
        };
        if lights_changed {
            self.restart_traced(gpu)?;
        }
        if let Some(r) = self.reloader.as_mut() {
            r.set_variants(&self.variants);
            r.set_params(&self.plan_params);
            r.set_scene(&self.scene);
        }
        // The scene's camera would come back with a new scene: keep the viewer's.
        Ok(())
    }

    /// Watch the pipeline's files, and the scene file with its models where there is one
    /// (`effects`: asked for besides the file's own), and reload on a change (see
    /// `crate::reload`).
    pub fn watch(&mut self, gpu: &Gpu, (scene_file, effects): (Option<&Path>, &[Effect])) -> Result<()> {
        let (mut r, _) = crate::reload::Reloader::in_workspace(
            self.ws.clone(),
            gpu,
            (&self.pipeline, self.shaders.as_deref()),
            (&self.scene, scene_file),
            &self.variants,
        )?;
        r.add_effects(effects);
        r.set_params(&self.plan_params);
        self.reloader = Some(r);
        Ok(())
    }

    /// The models the scene was loaded with, for the watch's reloads (see `Reloader::keep_models`).
    pub fn keep_models(&mut self, models: crate::scene::model_cache::ModelCache) {
        if let Some(r) = self.reloader.as_mut() {
            r.keep_models(models);
        }
    }

    /// Apply a reload if a watched file changed; its failure stays shown until one succeeds.
    /// A scene loaded again replaces the viewer's (its lights as the file says; the camera
    /// stays where the viewer has it); a path-traced view that cannot start on it is closed,
    /// saying why, as a failed reload is.
    pub fn poll_reload(&mut self, gpu: &Gpu) {
        let Some(r) = self.reloader.as_mut() else { return };
        match r.poll(gpu, &mut self.ex, std::time::Duration::ZERO) {
            Some(crate::reload::Outcome::Reloaded { scene, report, .. }) => {
                self.last_error = None;
                self.scene_kept = report.scene_kept.or(self.scene_kept);
                if let Some(s) = scene {
                    self.scene = *s;
                    self.light = self.light.min(self.scene.lights.len().saturating_sub(1));
                    if let Err(e) = self.restart_traced(gpu) {
                        self.traced = None;
                        self.last_error = Some(e.to_string());
                    }
                }
            }
            Some(crate::reload::Outcome::Failed { message, .. }) => self.last_error = Some(message),
            Some(crate::reload::Outcome::Rewatched { folders }) => eprintln!("{}", crate::reload::rewatched(&folders)),
            None => {}
        }
    }

    /// Lights edited: a change the running Plan can take (the lights that are on keep their
    /// kinds and shadow casting, in order) is a frame input — no new Plan, no scene upload,
    /// and only the work that depends on the lights runs again; any other needs a new Plan.
    fn lights_changed(&mut self, gpu: &Gpu) -> Result<()> {
        let signature = |s: &Scene| s.active_lights().iter().map(|l| (l.kind, l.shadows)).collect::<Vec<_>>();
        if signature(&self.scene) == signature(self.ex.scene()) {
            // The path tracer's accumulation holds the old light: it starts again.
            return self.restart_traced(gpu);
        }
        self.rebuild(gpu, true)
    }

    /// A fresh path-traced view of the scene as it is now, if one is shown.
    fn restart_traced(&mut self, gpu: &Gpu) -> Result<()> {
        if self.traced.is_some() {
            self.traced = Some(super::traced::Traced::new(gpu, &self.scene)?);
        }
        Ok(())
    }

    /// Render one frame from the viewer's camera, with its lights as they are now.
    pub fn frame(&mut self, gpu: &Gpu) -> Result<()> {
        let start = std::time::Instant::now();
        let lights: Vec<_> = self.scene.active_lights().into_iter().cloned().collect();
        // While the path-traced view is shown, it is what renders.
        if let Some(t) = self.traced.as_mut() {
            t.frame(gpu, &self.camera, &lights)?;
        } else {
            let mut inputs = self.ex.inputs(self.frames as f32 / 60.0);
            inputs.camera = self.camera.clone();
            inputs.lights = Some(lights);
            self.ex.render_frame(gpu, &inputs)?;
        }
        let ms = start.elapsed().as_secs_f64() * 1e3;
        self.frame_ms = if self.frames == 0 { ms } else { 0.9 * self.frame_ms + 0.1 * ms };
        self.frames += 1;
        Ok(())
    }

    /// What can be shown: `output`, then every texture of the Plan.
    pub fn views(&self) -> Vec<String> {
        let plan = self.ex.plan();
        let mut v = vec!["output".to_string()];
        v.extend(plan.resources.iter().filter(|r| !r.is_buffer()).map(|r| r.name.clone()));
        v
    }

    /// The resource name shown, and its (instance, layer) slices.
    fn shown(&self) -> Result<(String, Vec<(u32, u32)>)> {
        let views = self.views();
        let name = match self.view.min(views.len() - 1) {
            0 => self.ex.plan().output_resource().name.clone(),
            i => views[i].clone(),
        };
        let slices = self.ex.slices(&name)?;
        Ok((name, slices))
    }

    /// The shown slice: its resource, (instance, layer), format and a caption naming it.
    fn shown_slice(&self) -> Result<(String, (u32, u32), TextureFormat, String)> {
        let (name, slices) = self.shown()?;
        let (inst, layer) = slices[self.slice % slices.len().max(1)];
        let format = match &self.ex.plan().resource(&name).map(|r| r.shape.clone()) {
            Some(ResourceShape::Texture { format, .. }) => *format,
            _ => return Err(Error::resource(format!("`{name}` is not a texture"))),
        };
        let mut caption = format!("{name} ({})", format.name());
        if slices.len() > 1 {
            caption += &format!(
                " — light {inst}, layer {layer} ({} of {})",
                self.slice % slices.len() + 1,
                slices.len()
            );
        }
        Ok((name, (inst, layer), format, caption))
    }

    /// The shown slice when the window can draw it from the GPU as it is — 8-bit sRGB colour,
    /// as the output is —: its texture (copied, never read back), layer and caption. `None`
    /// for what needs the display mapping first (HDR, depth, data: `view_image`).
    pub fn shown_texture(&self) -> Result<Option<(wgpu::Texture, u32, String)>> {
        if let Some(t) = &self.traced {
            let output = &t.ex.plan().output_resource().name;
            return Ok(Some((t.ex.texture(output)?.clone(), 0, t.caption())));
        }
        let (name, (inst, layer), format, caption) = self.shown_slice()?;
        if format != TextureFormat::Rgba8UnormSrgb || inst != 0 {
            return Ok(None);
        }
        Ok(Some((self.ex.texture(&name)?.clone(), layer, caption)))
    }

    /// The shown image mapped for display (8-bit RGB) and a caption naming it.
    pub fn view_image(&self, gpu: &Gpu) -> Result<(u32, u32, Vec<u8>, String)> {
        if let Some(t) = &self.traced {
            let img = t.ex.read_texture(gpu, &t.ex.plan().output_resource().name, 0, 0)?;
            let rgb = super::display::rgb8(&img, TextureFormat::Rgba8UnormSrgb, (self.camera.near, self.camera.far));
            return Ok((img.width, img.height, rgb, t.caption()));
        }
        let (name, (inst, layer), format, caption) = self.shown_slice()?;
        let img = self.ex.read_texture(gpu, &name, inst, layer)?;
        let rgb = super::display::rgb8(&img, format, (self.camera.near, self.camera.far));
        Ok((img.width, img.height, rgb, caption))
    }

    /// The shown image as a PNG file (atomic).
    fn screenshot(&self, gpu: &Gpu, path: &Path) -> Result<()> {
        let (w, h, rgb, _) = self.view_image(gpu)?;
        crate::diff::images::png(rgb, (w, h), path)
    }

    /// A parameter's new value: a frame input, or, for one the Plan fixes (a size, a repeat
    /// count, a shader constant), a new Plan made with it and swapped in (the camera and the
    /// resources whose descriptors stay, history included, are kept).
    fn set_param(&mut self, gpu: &Gpu, name: &str, value: ParamValue) -> Result<()> {
        match self.ex.fixed_param(name) {
            None => return Ok(self.ex.set_param(name, value)?),
            Some(fixed) if *fixed == value => return Ok(()),
            Some(_) => {}
        }
        let before = self.plan_params.clone();
        self.plan_params.set(&self.ex.plan().params, name, value)?;
        self.rebuild(gpu, false).inspect_err(|_| self.plan_params = before)
    }

    /// Apply an action; on failure the viewer keeps running as it was and says why.
    pub fn apply(&mut self, gpu: &Gpu, a: Action) -> Result<()> {
        let r = self.apply_inner(gpu, a);
        self.last_error = r.as_ref().err().map(|e| e.to_string());
        r
    }

    fn apply_inner(&mut self, gpu: &Gpu, a: Action) -> Result<()> {
        let n = self.views().len();
        match a {
            Action::NextView => (self.view, self.slice) = ((self.view + 1) % n, 0),
            Action::PrevView => (self.view, self.slice) = ((self.view + n - 1) % n, 0),
            Action::NextSlice => self.slice += 1,
            Action::PrevSlice => self.slice = self.slice.checked_sub(1).unwrap_or(usize::MAX / 2),
            Action::View(name) => {
                self.view = self
                    .views()
                    .iter()
                    .position(|v| *v == name)
                    .ok_or_else(|| Error::Usage(format!("no view `{name}`")))?;
                self.slice = 0;
            }
            Action::SelectLight(i) if i < self.scene.lights.len() => self.light = i,
            Action::SelectLight(i) => return Err(Error::Usage(format!("there is no light {}", i + 1))),
            Action::ToggleLight => {
                let l = self
                    .scene
                    .lights
                    .get_mut(self.light)
                    .ok_or_else(|| Error::Usage("the scene has no lights".into()))?;
                l.on = !l.on;
                self.lights_changed(gpu)?;
            }
            Action::RotateLight(yaw, pitch) => {
                let l = self
                    .scene
                    .lights
                    .get_mut(self.light)
                    .ok_or_else(|| Error::Usage("the scene has no lights".into()))?;
                let q = glam::Quat::from_rotation_y(yaw.to_radians()) * glam::Quat::from_rotation_x(pitch.to_radians());
                l.direction = q * l.direction;
                self.lights_changed(gpu)?;
            }
            Action::Move(d) => {
                let f = self.camera.forward();
                let right = f.cross(glam::Vec3::Y).normalize_or_zero();
                self.camera.position += right * d.x + glam::Vec3::Y * d.y + f * d.z;
            }
            Action::Look(yaw, pitch) => {
                self.camera.yaw += yaw;
                self.camera.pitch = (self.camera.pitch + pitch).clamp(-89.0, 89.0);
            }
            Action::Param(name, value) => self.set_param(gpu, &name, value)?,
            Action::Variant(k, o) => {
                let before = self.variants.clone();
                self.variants.retain(|(v, _)| *v != k);
                self.variants.push((k, o));
                if let Err(e) = self.rebuild(gpu, false) {
                    self.variants = before;
                    return Err(e);
                }
            }
            Action::Screenshot(path) => self.screenshot(gpu, &path)?,
            Action::SetLight(i, l) => {
                let slot = self
                    .scene
                    .lights
                    .get_mut(i)
                    .ok_or_else(|| Error::Usage(format!("there is no light {}", i + 1)))?;
                *slot = *l;
                self.lights_changed(gpu)?;
            }
            Action::AddLight(kind) => {
                let at = self.camera.position + self.camera.forward();
                let (c, f) = (glam::Vec3::ONE, self.camera.forward());
                self.scene.lights.push(match kind {
                    lightbench_compiler::ir::LightKind::Point => crate::scene::Light::point(at, c, 2.0, 5.0),
                    lightbench_compiler::ir::LightKind::Spot => {
                        crate::scene::Light::spot(self.camera.position, f, 20.0, 30.0, c, 4.0, 10.0)
                    }
                    lightbench_compiler::ir::LightKind::Directional => crate::scene::Light::directional(f, c, 1.0),
                    // Emissive meshes' lights are the scene's own (parsing refuses the kind).
                    lightbench_compiler::ir::LightKind::Area => return Err(Error::Usage("an area light is an emissive mesh's".into())),
                });
                self.light = self.scene.lights.len() - 1;
                self.rebuild(gpu, true)?;
            }
            Action::RemoveLight => {
                if self.light >= self.scene.lights.len() {
                    return Err(Error::Usage("no light is selected".into()));
                }
                self.scene.lights.remove(self.light);
                self.light = self.light.min(self.scene.lights.len().saturating_sub(1));
                self.rebuild(gpu, true)?;
            }
            Action::Effect(e, on) => {
                match on {
                    true => self.scene.effects.insert(e),
                    false => self.scene.effects.remove(&e),
                };
                self.rebuild(gpu, true)?;
            }
            Action::Trace(true) if self.traced.is_none() => self.traced = Some(super::traced::Traced::new(gpu, &self.scene)?),
            Action::Trace(true) => {}
            Action::Trace(false) => self.traced = None,
            Action::ToggleTrace => return self.apply_inner(gpu, Action::Trace(self.traced.is_none())),
        }
        Ok(())
    }
}

/// The script actions (`frames N` is the window's: render N frames).
pub const ACTIONS: [&str; 17] = [
    "next-view",
    "prev-view",
    "next-slice",
    "prev-slice",
    "view",
    "light",
    "toggle-light",
    "rotate-light",
    "move",
    "look",
    "param",
    "variant",
    "screenshot",
    "add-light",
    "remove-light",
    "effect",
    "trace",
];

/// Largest camera move or angle a script may give: beyond it a frame is all precision loss
/// (NaN, inf and 1e38 are refused, as scene files refuse them).
const MAX_SCRIPT_NUMBER: f32 = 1e6;

/// One `--script` line as an action: `next-view`, `prev-view`, `next-slice`, `prev-slice`,
/// `view NAME`, `light N` (1-based), `toggle-light`, `rotate-light YAW PITCH`,
/// `move X Y Z`, `look YAW PITCH`, `param NAME=VALUE`, `variant NAME=OPTION`,
/// `screenshot FILE`, `add-light Point|Spot|Directional`, `remove-light`, `effect NAME=true|false`,
/// `trace on|off` (the path-traced view in place of the raster output).
/// Without a `plan`, parameter values are not type-checked (the script's syntax, checked
/// before the window opens).
pub fn parse_action(line: &str, plan: Option<&lightbench_compiler::plan::Plan>) -> Result<Action> {
    let bad = |what: &str| Error::Usage(format!("script line `{line}`: {what}"));
    let mut words = line.split_whitespace();
    let cmd = words.next().ok_or_else(|| bad("empty"))?;
    let rest: Vec<&str> = words.collect();
    let num = |i: usize| match rest.get(i).map(|w| w.parse::<f32>()) {
        Some(Ok(v)) if v.is_finite() && v.abs() <= MAX_SCRIPT_NUMBER => Ok(v),
        Some(Ok(v)) => Err(bad(&format!("`{v}` is not a number within ±{MAX_SCRIPT_NUMBER:e}"))),
        _ => Err(bad(&format!("`{cmd}` takes a number as argument {}", i + 1))),
    };
    let word = |what: &str| rest.first().copied().ok_or_else(|| bad(&format!("`{cmd}` takes {what}")));
    let pair = || {
        word("NAME=VALUE")?
            .split_once('=')
            .ok_or_else(|| bad(&format!("`{cmd}` takes NAME=VALUE")))
    };
    Ok(match cmd {
        "next-view" => Action::NextView,
        "prev-view" => Action::PrevView,
        "next-slice" => Action::NextSlice,
        "prev-slice" => Action::PrevSlice,
        "view" => Action::View(word("a resource name")?.to_string()),
        "light" => Action::SelectLight((num(0)? as usize).checked_sub(1).ok_or_else(|| bad("lights count from 1"))?),
        "toggle-light" => Action::ToggleLight,
        "rotate-light" => Action::RotateLight(num(0)?, num(1)?),
        "move" => Action::Move(glam::vec3(num(0)?, num(1)?, num(2)?)),
        "look" => Action::Look(num(0)?, num(1)?),
        "param" => {
            let (k, v) = pair()?;
            let value = match plan {
                Some(plan) => ParamValues::parse_text(&plan.params, k, v).map_err(|e| bad(&e.to_string()))?,
                None => ParamValue::Enum(v.to_string()),
            };
            Action::Param(k.to_string(), value)
        }
        "variant" => {
            let (k, v) = pair()?;
            Action::Variant(k.to_string(), v.to_string())
        }
        "screenshot" => Action::Screenshot(PathBuf::from(word("a file name")?)),
        "add-light" => {
            let kind = word("Point, Spot or Directional")?;
            let kind = lightbench_compiler::ir::LightKind::from_name(kind).filter(|k| k.punctual());
            Action::AddLight(kind.ok_or_else(|| bad("expected Point, Spot or Directional"))?)
        }
        "remove-light" => Action::RemoveLight,
        "trace" => Action::Trace(match word("on or off")? {
            "on" => true,
            "off" => false,
            w => return Err(bad(&format!("`trace` takes on or off, not `{w}`"))),
        }),
        "effect" => {
            let (k, v) = pair()?;
            let e = lightbench_compiler::ir::Effect::from_name(k).ok_or_else(|| {
                bad(&format!(
                    "no effect `{k}`{}",
                    lightbench_compiler::diag::did_you_mean(k, lightbench_compiler::ir::Effect::NAMES)
                        .map(|m| format!("; did you mean `{m}`?"))
                        .unwrap_or_default()
                ))
            })?;
            Action::Effect(e, v.parse().map_err(|_| bad("`effect` takes NAME=true or NAME=false"))?)
        }
        _ => {
            let hint = lightbench_compiler::diag::did_you_mean(cmd, ACTIONS.iter().copied().chain(["frames"]))
                .map(|m| format!("; did you mean `{m}`?"))
                .unwrap_or_default();
            return Err(bad(&format!("no action `{cmd}`{hint} (see `lightbench view --help`)")));
        }
    })
}
