//! Scenes from their descriptions: the compiler's scene front end reads the built-in name
//! or scene file (syntax, values, `builtin:`); here the description gets its geometry —
//! built-in meshes and glTF models — and becomes a renderable [`Scene`].

use super::{builtin, framing, gltf_load, Animation, Camera, Light, Scene};
use crate::error::{Error, Result};
use crate::model_cache::ModelCache;
use glam::{EulerRot, Mat4, Quat, Vec3};
use lightbench_compiler::diag::{Code, Diagnostic, Diagnostics};
use lightbench_compiler::ir::{Effect, LightKind};
use lightbench_compiler::scene::{AnimationDesc, LightDesc, ModelDesc, SceneDesc, SceneFeatures};
use lightbench_compiler::Session;

/// A built-in scene by name, or a scene file; errors are the rendered diagnostics (warnings
/// are dropped: `load_in` keeps them in the session).
pub fn load(spec: &str) -> Result<Scene> {
    load_with(spec, &mut ModelCache::default())
}

/// `load`, its models taken from `models` where their files did not change since its last
/// load (`ModelCache::last` says how many).
pub fn load_with(spec: &str, models: &mut ModelCache) -> Result<Scene> {
    let mut s = Session::new();
    load_in_with(&mut s, spec, models).ok_or_else(|| Error::Scene(s.render()))
}

/// Load through a compilation session: diagnostics (syntax, values, models) go to it.
pub fn load_in(s: &mut Session, spec: &str) -> Option<Scene> {
    load_in_with(s, spec, &mut ModelCache::default())
}

/// `load_in`, its models taken from `models` where their files did not change since its last
/// load (and kept there when it is `ModelCache::keeping`).
pub fn load_in_with(s: &mut Session, spec: &str, models: &mut ModelCache) -> Option<Scene> {
    let desc = s.load_scene(spec)?;
    instantiate_with(&desc, &mut s.diags, models)
}

/// What a command loads: the scene `spec` names (built-in name, scene file or glTF model) at
/// the `size` asked for; its warnings are shown, its errors stop (rendered already:
/// `Error::Scene` is empty). A model shown on its own is framed for the size it is rendered at.
/// `effects` are added to those the scene calls for.
pub fn load_sized(spec: &str, size: Option<(u32, u32)>, effects: &[Effect]) -> Result<Scene> {
    load_sized_with(spec, size, effects, &mut ModelCache::default())
}

/// `load_sized`, its models kept in `models` (`ModelCache::keeping`) for loading it again.
pub fn load_sized_with(spec: &str, size: Option<(u32, u32)>, effects: &[Effect], models: &mut ModelCache) -> Result<Scene> {
    let mut s = Session::new();
    let loaded = load_in_with(&mut s, spec, models);
    eprint!("{}", s.render());
    let mut scene = loaded.ok_or_else(|| Error::Scene(String::new()))?;
    scene.effects.extend(effects.iter().copied());
    if let Some(sz) = size {
        scene.size = sz;
        if lightbench_compiler::scene::is_model(std::path::Path::new(spec)) {
            scene.camera = framing::frame(&scene);
        }
    }
    Ok(scene)
}

/// Every file the scene `spec` is read from: a scene file, each of its models and the files
/// they refer to (external buffers and images) — what a watcher of the scene watches. A
/// built-in scene has none; a description that does not load lists what it can.
pub fn files_of(spec: &str) -> Vec<std::path::PathBuf> {
    let mut out: Vec<std::path::PathBuf> = vec![];
    let path = std::path::Path::new(spec);
    if path.is_file() {
        out.push(path.to_path_buf());
    }
    let mut s = Session::new();
    if let Some(desc) = s.load_scene(spec) {
        for f in desc.models.iter().flat_map(|m| gltf_load::files(&m.file)) {
            if !out.contains(&f) {
                out.push(f);
            }
        }
    }
    out
}

/// What planning needs of the scene `spec` names — its features — read without its geometry
/// or textures: the description, its built-in meshes (small) and each model's JSON
/// (`gltf_load::outline`). Checking and planning read scenes so; a model that
/// cannot be read is an error at its path, as in `load_in`.
pub fn features_in(s: &mut Session, spec: &str) -> Option<SceneFeatures> {
    let desc = s.load_scene(spec)?;
    let mut scene = Scene::from_desc(&desc);
    let before = s.diags.error_count();
    let (mut reflective, mut blended) = (false, false);
    let mut emitters = scene.meshes.iter().filter(|m| crate::emitter_lights::emits(&scene, m)).count();
    for m in &desc.models {
        match gltf_load::outline(&m.file) {
            Ok(o) => {
                model_warnings(m, o.warnings, &mut s.diags);
                let transform = model_transform(m);
                scene.lights.extend(o.lights.into_iter().map(|l| placed(l, m, transform)));
                reflective |= o.draws && m.reflective;
                blended |= o.blended;
                emitters += o.emitters;
            }
            Err(e) => {
                let msg = format!("cannot load model `{}`: {e}", m.path.value);
                s.diags.push(Diagnostic::error(Code::ModelLoad, msg, m.path.span));
            }
        }
    }
    if s.diags.error_count() != before {
        return None;
    }
    if desc.framed_model && scene.lights.is_empty() {
        scene.lights = framing::default_rig();
    }
    // The light array as `Scene::light_array` makes it: the lights that are on, then one
    // light per emissive mesh (at most `MAX_EMITTER_LIGHTS`).
    let area = (LightKind::Area, false);
    let emitters = std::iter::repeat_n(area, emitters.min(crate::emitter_lights::MAX_EMITTER_LIGHTS));
    let order = scene
        .active_lights()
        .iter()
        .map(|l| (l.kind, l.shadows))
        .chain(emitters)
        .collect::<Vec<_>>();
    let mut f = scene.features().with_order(order);
    f.reflective |= reflective;
    f.transparent |= blended;
    Some(f)
}

/// The description with its geometry; a model that cannot be loaded is an error at its path.
pub fn instantiate(desc: &SceneDesc, diags: &mut Diagnostics) -> Option<Scene> {
    instantiate_with(desc, diags, &mut ModelCache::default())
}

/// `instantiate`, its models taken from `models` where their files did not change.
pub fn instantiate_with(desc: &SceneDesc, diags: &mut Diagnostics, models: &mut ModelCache) -> Option<Scene> {
    let mut scene = Scene::from_desc(desc);
    let before = diags.error_count();
    models.begin();
    for m in &desc.models {
        match models.model(&m.file).and_then(|loaded| add_model(&mut scene, m, loaded)) {
            Ok(warnings) => model_warnings(m, warnings, diags),
            Err(e) => {
                let msg = format!("cannot load model `{}`: {e}", m.path.value);
                diags.push(Diagnostic::error(Code::ModelLoad, msg, m.path.span));
            }
        }
    }
    models.end();
    if desc.framed_model && diags.error_count() == before {
        scene.camera = framing::frame(&scene);
        if scene.lights.is_empty() {
            scene.lights = framing::default_rig();
        }
    }
    (diags.error_count() == before).then_some(scene)
}

/// What was loaded of model `m` only in part, at its path.
fn model_warnings(m: &ModelDesc, warnings: Vec<String>, diags: &mut Diagnostics) {
    for w in warnings {
        let msg = format!("model `{}`: {w}", m.path.value);
        diags.push(Diagnostic::warning(Code::SkippedPrimitive, msg, m.path.span));
    }
}

impl Scene {
    /// The description's built-in geometry, camera and lights (models are added by
    /// [`instantiate`]).
    pub fn from_desc(desc: &SceneDesc) -> Scene {
        let (meshes, materials) = desc.geometry.as_deref().and_then(builtin::geometry).unwrap_or_default();
        let c = &desc.camera;
        Scene {
            name: desc.name.clone(),
            size: desc.size,
            camera: Camera {
                position: Vec3::from(c.position),
                yaw: c.yaw,
                pitch: c.pitch,
                fov: c.fov,
                near: c.near,
                far: c.far,
                animation: c.animation.clone(),
            },
            meshes,
            materials,
            textures: vec![],
            lights: desc.lights.iter().map(Light::from_desc).collect(),
            effects: desc.effects.clone(),
        }
    }
}

impl Light {
    pub fn from_desc(l: &LightDesc) -> Light {
        Light {
            kind: l.kind,
            on: l.on,
            color: Vec3::from(l.color),
            intensity: l.intensity,
            position: Vec3::from(l.position),
            direction: Vec3::from(l.direction),
            inner_angle: l.inner,
            outer_angle: l.outer,
            range: l.range,
            shadows: l.shadows,
            animation: l.animation.as_ref().map(|a| match a {
                AnimationDesc::Orbit { center, radius, speed } => Animation::Orbit {
                    center: Vec3::from(*center),
                    radius: *radius,
                    speed: *speed,
                },
                AnimationDesc::Rotate { speed } => Animation::Rotate { speed: *speed },
            }),
        }
    }
}

/// Place a loaded glTF model's meshes, materials, textures and lights in the scene as `m`
/// says; returns what was skipped.
fn add_model(scene: &mut Scene, m: &ModelDesc, loaded: std::sync::Arc<gltf_load::Loaded>) -> Result<Vec<String>> {
    // Moved when the scene is its only user; copied when a model cache keeps it too.
    let loaded = std::sync::Arc::try_unwrap(loaded).unwrap_or_else(|kept| (*kept).clone());
    let transform = model_transform(m);
    let mat_base = scene.materials.len();
    let tex_base = scene.textures.len();
    scene.textures.extend(loaded.textures);
    for mut mat in loaded.materials {
        for t in [
            &mut mat.base_color_texture,
            &mut mat.metallic_roughness_texture,
            &mut mat.emissive_texture,
            &mut mat.normal_texture,
            &mut mat.occlusion_texture,
        ] {
            *t = t.map(|i| i + tex_base);
        }
        if let Some(two) = m.double_sided {
            mat.double_sided = two;
        }
        scene.materials.push(mat);
    }
    for mut mesh in loaded.meshes {
        mesh.material += mat_base;
        mesh.transform = transform * mesh.transform;
        mesh.triangle_fraction = m.triangles;
        mesh.reflective = m.reflective;
        scene.meshes.push(mesh);
    }
    scene.lights.extend(loaded.lights.into_iter().map(|l| placed(l, m, transform)));
    Ok(loaded.warnings)
}

/// Where a model description places the model: scale, then rotation (yaw, pitch, roll in
/// degrees), then translation.
fn model_transform(m: &ModelDesc) -> Mat4 {
    let [y, p, r] = m.rotation.map(f32::to_radians);
    Mat4::from_scale_rotation_translation(
        Vec3::splat(m.scale),
        Quat::from_euler(EulerRot::YXZ, y, p, r),
        Vec3::from(m.translation),
    )
}

/// A model's light placed with the model. Lights scale with it: positions, ranges and
/// (inverse-square) intensities, so that a scaled model looks the same.
fn placed(mut l: Light, m: &ModelDesc, transform: Mat4) -> Light {
    l.position = transform.transform_point3(l.position);
    l.direction = transform.transform_vector3(l.direction);
    if l.kind != LightKind::Directional {
        l.range *= m.scale;
        l.intensity *= m.scale * m.scale;
    }
    l
}
