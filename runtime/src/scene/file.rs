//! Scene files (RON). Errors name the file and line:col; unknown keys are rejected.
//!
//! ```ron
//! Scene(
//!     name: "room",
//!     size: (256, 256),
//!     camera: (position: (0.0, 1.0, 3.6), yaw: 0.0, pitch: 0.0, fov: 40.0, near: 0.05, far: 20.0),
//!     builtin: "cornell",                 // start from a built-in scene (optional)
//!     models: [(path: "chair.gltf", translation: (0.3, 0.0, 0.0), rotation: (45.0, 0.0, 0.0), scale: 0.5, triangles: 1.0)],
//!     lights: [Point(position: (0.0, 1.8, 0.0), color: (1.0, 1.0, 1.0), intensity: 4.0, range: 6.0,
//!                    animation: Orbit(center: (0.0, 1.8, 0.0), radius: 0.5, speed: 30.0))],
//!     effects: [Shadows],
//! )
//! ```

use super::{builtin, gltf_load, Animation, Camera, Light, Scene};
use crate::error::{Error, Result};
use glam::{EulerRot, Mat4, Quat, Vec3};
use lightbench_compiler::ir::{Effect, LightKind};
use serde::Deserialize;
use std::path::Path;

fn one() -> f32 {
    1.0
}
fn yes() -> bool {
    true
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct CameraFile {
    position: (f32, f32, f32),
    #[serde(default)]
    yaw: f32,
    #[serde(default)]
    pitch: f32,
    #[serde(default = "default_fov")]
    fov: f32,
    #[serde(default = "default_near")]
    near: f32,
    #[serde(default = "default_far")]
    far: f32,
}
fn default_fov() -> f32 {
    45.0
}
fn default_near() -> f32 {
    0.05
}
fn default_far() -> f32 {
    100.0
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ModelFile {
    /// glTF file, relative to the scene file.
    path: String,
    #[serde(default)]
    translation: (f32, f32, f32),
    /// Yaw, pitch, roll in degrees.
    #[serde(default)]
    rotation: (f32, f32, f32),
    #[serde(default = "one")]
    scale: f32,
    /// Fraction of each mesh's triangles to draw.
    #[serde(default = "one")]
    triangles: f32,
    #[serde(default)]
    reflective: bool,
}

#[derive(Deserialize, Debug)]
enum AnimationFile {
    Orbit { center: (f32, f32, f32), radius: f32, speed: f32 },
    Rotate { speed: f32 },
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct LightFields {
    #[serde(default = "yes")]
    on: bool,
    #[serde(default = "white")]
    color: (f32, f32, f32),
    #[serde(default = "one")]
    intensity: f32,
    #[serde(default)]
    position: (f32, f32, f32),
    #[serde(default = "down")]
    direction: (f32, f32, f32),
    #[serde(default = "inner")]
    inner: f32,
    #[serde(default = "outer")]
    outer: f32,
    #[serde(default = "range")]
    range: f32,
    #[serde(default = "yes")]
    shadows: bool,
    #[serde(default)]
    animation: Option<AnimationFile>,
}
fn white() -> (f32, f32, f32) {
    (1.0, 1.0, 1.0)
}
fn down() -> (f32, f32, f32) {
    (0.0, -1.0, 0.0)
}
fn inner() -> f32 {
    25.0
}
fn outer() -> f32 {
    35.0
}
fn range() -> f32 {
    10.0
}

#[derive(Deserialize, Debug)]
enum LightFile {
    Directional(LightFields),
    Spot(LightFields),
    Point(LightFields),
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields, rename = "Scene")]
struct SceneFile {
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    size: Option<(u32, u32)>,
    #[serde(default)]
    camera: Option<CameraFile>,
    #[serde(default)]
    builtin: Option<String>,
    #[serde(default)]
    models: Vec<ModelFile>,
    #[serde(default)]
    lights: Vec<LightFile>,
    #[serde(default)]
    effects: Vec<Effect>,
}

fn v3(t: (f32, f32, f32)) -> Vec3 {
    Vec3::new(t.0, t.1, t.2)
}

/// A built-in scene by name, or a scene file.
pub fn load(spec: &str) -> Result<Scene> {
    if let Some(s) = builtin::by_name(spec) {
        return Ok(s);
    }
    let path = Path::new(spec);
    if !path.exists() {
        return Err(Error::Scene(format!(
            "`{spec}` is neither a scene file nor a built-in scene ({})",
            builtin::NAMES.join(", ")
        )));
    }
    load_file(path)
}

pub fn load_file(path: &Path) -> Result<Scene> {
    let bad = |msg: String| Error::Scene(format!("{}: {msg}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| bad(e.to_string()))?;
    // Optional fields are written plainly (`name: "x"`, not `name: Some("x")`).
    let options = ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let f: SceneFile = options
        .from_str(&text)
        .map_err(|e| Error::Scene(format!("{}:{}:{}: {}", path.display(), e.span.start.line, e.span.start.col, e.code)))?;
    let mut scene = match &f.builtin {
        Some(b) => builtin::by_name(b).ok_or_else(|| {
            bad(format!(
                "unknown built-in scene `{b}` (expected one of {})",
                builtin::NAMES.join(", ")
            ))
        })?,
        None => Scene {
            name: String::new(),
            size: (128, 128),
            camera: Camera {
                position: Vec3::new(0.0, 1.0, 4.0),
                yaw: 0.0,
                pitch: 0.0,
                fov: 45.0,
                near: 0.05,
                far: 100.0,
            },
            meshes: vec![],
            materials: vec![],
            textures: vec![],
            lights: vec![],
            effects: Default::default(),
        },
    };
    scene.name = f
        .name
        .clone()
        .unwrap_or_else(|| path.file_stem().and_then(|s| s.to_str()).unwrap_or("scene").to_string());
    if let Some((w, h)) = f.size {
        if w == 0 || h == 0 || w > 16384 || h > 16384 {
            return Err(bad(format!("size ({w}, {h}) out of range 1..=16384")));
        }
        scene.size = (w, h);
    }
    if let Some(c) = &f.camera {
        // Written so that NaN fails too.
        let valid = c.fov > 0.0 && c.fov < 180.0 && c.near > 0.0 && c.far > c.near;
        if !valid {
            return Err(bad("camera needs 0 < fov < 180 and 0 < near < far".into()));
        }
        scene.camera = Camera {
            position: v3(c.position),
            yaw: c.yaw,
            pitch: c.pitch,
            fov: c.fov,
            near: c.near,
            far: c.far,
        };
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    for m in &f.models {
        let (y, p, r) = m.rotation;
        let transform = Mat4::from_scale_rotation_translation(
            Vec3::splat(m.scale),
            Quat::from_euler(EulerRot::YXZ, y.to_radians(), p.to_radians(), r.to_radians()),
            v3(m.translation),
        );
        let loaded = gltf_load::load(&dir.join(&m.path))?;
        let mat_base = scene.materials.len();
        let tex_base = scene.textures.len();
        scene.textures.extend(loaded.textures);
        for mut mat in loaded.materials {
            for t in [
                &mut mat.base_color_texture,
                &mut mat.metallic_roughness_texture,
                &mut mat.emissive_texture,
                &mut mat.normal_texture,
            ] {
                *t = t.map(|i| i + tex_base);
            }
            scene.materials.push(mat);
        }
        for mut mesh in loaded.meshes {
            mesh.material += mat_base;
            mesh.transform = transform * mesh.transform;
            mesh.triangle_fraction = m.triangles.clamp(0.0, 1.0);
            mesh.reflective = m.reflective;
            scene.meshes.push(mesh);
        }
        for mut l in loaded.lights {
            l.position = transform.transform_point3(l.position);
            l.direction = transform.transform_vector3(l.direction);
            scene.lights.push(l);
        }
    }
    for lf in &f.lights {
        let (kind, lf) = match lf {
            LightFile::Directional(l) => (LightKind::Directional, l),
            LightFile::Spot(l) => (LightKind::Spot, l),
            LightFile::Point(l) => (LightKind::Point, l),
        };
        let valid = lf.range > 0.0 && lf.intensity >= 0.0 && lf.inner <= lf.outer;
        if !valid {
            return Err(bad("a light needs range > 0, intensity >= 0 and inner <= outer".into()));
        }
        scene.lights.push(Light {
            kind,
            on: lf.on,
            color: v3(lf.color),
            intensity: lf.intensity,
            position: v3(lf.position),
            direction: v3(lf.direction),
            inner_angle: lf.inner,
            outer_angle: lf.outer,
            range: lf.range,
            shadows: lf.shadows,
            animation: lf.animation.as_ref().map(|a| match a {
                AnimationFile::Orbit { center, radius, speed } => Animation::Orbit {
                    center: v3(*center),
                    radius: *radius,
                    speed: *speed,
                },
                AnimationFile::Rotate { speed } => Animation::Rotate { speed: *speed },
            }),
        });
    }
    scene.effects.extend(f.effects.iter().copied());
    Ok(scene)
}
