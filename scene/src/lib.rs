//! lightbench-scene, the scene stage shared by the executor and the reference (GPU-free):
//! meshes with materials, lights, a camera, the output size and the effects the scene calls
//! for, made from the compiler's scene description (built-in or a scene file) plus geometry
//! (built-in meshes, glTF models); images and files as every lightbench crate reads and
//! writes them; the error type they all return.

pub mod builtin;
pub mod emitter_lights;
pub mod error;
pub mod export;
pub mod files;
pub mod framing;
pub mod geometry;
pub mod gltf_load;
pub mod io;
pub mod light;
pub mod load;
pub mod math;
pub mod model_cache;
pub mod texture_cache;

pub use error::{Error, Result};
pub use light::{Animation, Light};
pub use load::{features_in, instantiate, load, load_in};
pub use texture_cache::TexelBytes;

use glam::{Mat4, Vec3};
pub use lightbench_compiler::abi::Vertex;
use lightbench_compiler::ir::{Effect, LightKind};
use lightbench_compiler::scene::{CameraAnimationDesc, CameraKey, SceneFeatures};
use std::collections::BTreeSet;

#[derive(Clone, Debug)]
pub struct Camera {
    pub position: Vec3,
    /// Degrees; 0 looks down -Z, positive turns left (towards -X).
    pub yaw: f32,
    /// Degrees; positive looks up.
    pub pitch: f32,
    /// Vertical field of view in degrees.
    pub fov: f32,
    pub near: f32,
    pub far: f32,
    /// Moves the camera over time (scene files' `animation`); see [`Camera::at`].
    pub animation: Option<CameraAnimationDesc>,
}

impl Camera {
    /// The camera at time `t` seconds: itself when it does not move.
    pub fn at(&self, t: f32) -> Camera {
        let mut c = self.clone();
        match &self.animation {
            Some(CameraAnimationDesc::Orbit { center, speed }) => {
                let center = Vec3::from(*center);
                let rot = glam::Quat::from_rotation_y((speed * t).to_radians());
                c.position = center + rot * (self.position - center);
                c.look_at(center);
            }
            Some(CameraAnimationDesc::Path(keys)) => {
                let k = path_at(keys, t);
                c.position = Vec3::from(k.position);
                (c.yaw, c.pitch) = (k.yaw, k.pitch);
            }
            None => {}
        }
        c
    }

    /// Turn to face `target` (yaw and pitch as [`Camera::forward`] reads them).
    pub fn look_at(&mut self, target: Vec3) {
        let d = (target - self.position).normalize_or_zero();
        if d != Vec3::ZERO {
            self.yaw = (-d.x).atan2(-d.z).to_degrees();
            self.pitch = d.y.clamp(-1.0, 1.0).asin().to_degrees();
        }
    }

    pub fn forward(&self) -> Vec3 {
        let (y, p) = (self.yaw.to_radians(), self.pitch.to_radians());
        Vec3::new(-y.sin() * p.cos(), p.sin(), -y.cos() * p.cos()).normalize()
    }
    pub fn view(&self) -> Mat4 {
        math::look_to(self.position, self.forward(), light::safe_up(self.forward()))
    }
    pub fn proj(&self, aspect: f32) -> Mat4 {
        math::perspective(self.fov.to_radians(), aspect, self.near, self.far)
    }
}

/// A keyframed path at `t`: linear between keys, held outside them (keys are checked to be
/// non-empty and increasing in time).
fn path_at(keys: &[CameraKey], t: f32) -> CameraKey {
    let lerp = |a: f32, b: f32, f: f32| a + (b - a) * f;
    let i = keys.iter().position(|k| k.time > t).unwrap_or(keys.len());
    match (i.checked_sub(1).and_then(|j| keys.get(j)), keys.get(i)) {
        (Some(a), Some(b)) => {
            let f = (t - a.time) / (b.time - a.time);
            CameraKey {
                time: t,
                position: std::array::from_fn(|n| lerp(a.position[n], b.position[n], f)),
                yaw: lerp(a.yaw, b.yaw, f),
                pitch: lerp(a.pitch, b.pitch, f),
            }
        }
        (Some(k), None) | (None, Some(k)) => k.clone(),
        (None, None) => CameraKey {
            time: t,
            position: [0.0; 3],
            yaw: 0.0,
            pitch: 0.0,
        },
    }
}

/// 8-bit RGBA texels; `srgb` for colour data (base colour, emission).
#[derive(Clone, Debug)]
pub struct ImageData {
    pub width: u32,
    pub height: u32,
    pub rgba: TexelBytes,
    pub srgb: bool,
}

/// How a material's alpha is used (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    Opaque,
    /// Cut out where alpha is below the cutoff.
    Mask(f32),
    /// Blended over what is behind (`draw: Transparent` passes, back to front).
    Blend,
}

/// Texture addressing of a material's sampler (glTF sampler wrap modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Wrap {
    Repeat,
    Clamp,
    Mirror,
}

/// A material's sampler (glTF sampler): wrap per axis, linear or nearest filtering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SamplerDesc {
    pub wrap: [Wrap; 2],
    pub mag_linear: bool,
    pub min_linear: bool,
    pub mip_linear: bool,
}

impl Default for SamplerDesc {
    fn default() -> Self {
        SamplerDesc {
            wrap: [Wrap::Repeat; 2],
            mag_linear: true,
            min_linear: true,
            mip_linear: true,
        }
    }
}

/// The identity UV transform.
pub const IDENTITY_UV: [[f32; 3]; 2] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

#[derive(Clone, Debug)]
pub struct Material {
    pub name: String,
    pub base_color: [f32; 4],
    pub base_color_texture: Option<usize>,
    pub metallic: f32,
    pub roughness: f32,
    pub metallic_roughness_texture: Option<usize>,
    pub emissive: [f32; 3],
    pub emissive_texture: Option<usize>,
    pub normal_texture: Option<usize>,
    pub normal_scale: f32,
    /// Ambient occlusion (glTF `occlusionTexture`, red channel) and how strongly it applies.
    pub occlusion_texture: Option<usize>,
    pub occlusion_strength: f32,
    /// UV transform (KHR_texture_transform) as the rows of a 2×3 affine matrix.
    pub uv_transform: [[f32; 3]; 2],
    pub alpha: AlphaMode,
    pub sampler: SamplerDesc,
    /// Bit k set: map k (base colour, metallic-roughness, normal, emissive, occlusion) reads
    /// TEXCOORD_1.
    pub uv_sets: u32,
    /// glTF `doubleSided`: seen from both sides (the back with its normal flipped). A
    /// single-sided surface is invisible from behind but, like every surface, still blocks
    /// light from both sides.
    pub double_sided: bool,
}

impl Material {
    pub fn color(name: &str, rgb: [f32; 3], roughness: f32) -> Self {
        Material {
            name: name.into(),
            base_color: [rgb[0], rgb[1], rgb[2], 1.0],
            base_color_texture: None,
            metallic: 0.0,
            roughness,
            metallic_roughness_texture: None,
            emissive: [0.0; 3],
            emissive_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            uv_transform: IDENTITY_UV,
            alpha: AlphaMode::Opaque,
            sampler: SamplerDesc::default(),
            uv_sets: 0,
            double_sided: false,
        }
    }
}

/// One drawable: geometry in object space, its placement and material.
#[derive(Clone, Debug)]
pub struct Mesh {
    pub name: String,
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub material: usize,
    pub transform: Mat4,
    /// Fraction of the triangles drawn (seed 000 §6.1: triangle-count experiments).
    pub triangle_fraction: f32,
    pub reflective: bool,
}

impl Mesh {
    /// A mesh drawn whole, placed by `transform`, of `materials[material]`.
    pub fn new(name: &str, vertices: Vec<Vertex>, indices: Vec<u32>, material: usize, transform: Mat4) -> Mesh {
        Mesh {
            name: name.into(),
            vertices,
            indices,
            material,
            transform,
            triangle_fraction: 1.0,
            reflective: false,
        }
    }

    /// Index count actually drawn: the fraction, rounded down to whole triangles.
    pub fn drawn_indices(&self) -> u32 {
        let tris = self.indices.len() / 3;
        let n = ((tris as f64) * self.triangle_fraction.clamp(0.0, 1.0) as f64).floor() as usize;
        (n * 3) as u32
    }
}

#[derive(Clone, Debug)]
pub struct Scene {
    pub name: String,
    pub size: (u32, u32),
    pub camera: Camera,
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub textures: Vec<ImageData>,
    pub lights: Vec<Light>,
    pub effects: BTreeSet<Effect>,
}

impl Scene {
    /// A scene from a host program's own geometry: `meshes` with `materials` (untextured) and
    /// `lights` (none: the default key and fill rig), rendered at `size`, the camera framing
    /// the meshes as a model shown on its own is framed (`framing`). Checked as a loaded model
    /// is: indices within the vertices, material indices within `materials`, finite
    /// positions, at least one triangle.
    pub fn from_meshes(name: &str, size: (u32, u32), meshes: Vec<Mesh>, materials: Vec<Material>, lights: Vec<Light>) -> Result<Scene> {
        for m in &meshes {
            let bad = |what: String| Err(Error::Scene(format!("mesh `{}`: {what}", m.name)));
            if m.indices.len() % 3 != 0 {
                return bad(format!("{} indices is not whole triangles", m.indices.len()));
            }
            if let Err(e) = geometry::check_indices(&m.indices, m.vertices.len()) {
                return bad(e);
            }
            if m.material >= materials.len() {
                return bad(format!("material {} of {}", m.material, materials.len()));
            }
            if m.vertices.iter().any(|v| !v.position.iter().all(|c| c.is_finite())) {
                return bad("a vertex position is not finite".into());
            }
        }
        if meshes.iter().all(|m| m.indices.is_empty()) {
            return Err(Error::Scene(format!("scene `{name}`: no triangles")));
        }
        if size.0 == 0 || size.1 == 0 {
            return Err(Error::Scene(format!("scene `{name}`: size {}×{}", size.0, size.1)));
        }
        let mut scene = Scene {
            name: name.into(),
            size,
            camera: Camera {
                position: Vec3::ZERO,
                yaw: 0.0,
                pitch: 0.0,
                fov: framing::FOV,
                near: 0.1,
                far: 100.0,
                animation: None,
            },
            meshes,
            materials,
            textures: vec![],
            lights: if lights.is_empty() { framing::default_rig() } else { lights },
            effects: BTreeSet::new(),
        };
        scene.camera = framing::frame(&scene);
        Ok(scene)
    }

    /// Axis-aligned bounds of every mesh in world space.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for m in &self.meshes {
            for v in &m.vertices {
                let p = m.transform.transform_point3(Vec3::from(v.position));
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        if lo.x > hi.x {
            return (Vec3::splat(-1.0), Vec3::splat(1.0));
        }
        (lo, hi)
    }

    /// Pixel (x right, y down) where the camera sees a world point, if it is in front.
    pub fn project(&self, p: Vec3) -> Option<(f32, f32)> {
        let (w, h) = self.size;
        let vp = self.camera.proj(w as f32 / h.max(1) as f32) * self.camera.view();
        let c = vp * p.extend(1.0);
        if c.w <= 0.0 {
            return None;
        }
        let ndc = c.truncate() / c.w;
        Some(((ndc.x + 1.0) * 0.5 * w as f32, (1.0 - ndc.y) * 0.5 * h as f32))
    }

    /// Lights that are on, in scene order: the light array the shaders index.
    pub fn active_lights(&self) -> Vec<&Light> {
        self.lights.iter().filter(|l| l.on).collect()
    }

    /// What the compiler needs to cull and size the plan.
    pub fn features(&self) -> SceneFeatures {
        let reflective = self.meshes.iter().any(|m| m.reflective);
        let mut f = SceneFeatures::new(&self.name, self.size, [], &self.effects, reflective)
            .with_order(self.light_array().iter().map(|l| (l.kind, l.shadows)));
        f.transparent = self
            .meshes
            .iter()
            .any(|m| self.materials.get(m.material).is_some_and(|mat| mat.alpha == AlphaMode::Blend));
        f
    }

    pub fn light_count(&self, kind: LightKind) -> usize {
        self.light_array().iter().filter(|l| l.kind == kind).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(time: f32, x: f32, yaw: f32) -> CameraKey {
        CameraKey {
            time,
            position: [x, 1.0, 0.0],
            yaw,
            pitch: 0.0,
        }
    }

    /// A path interpolates linearly between keys and holds outside them; an orbit keeps
    /// its radius and looks at its centre.
    #[test]
    fn camera_paths_and_orbits() {
        let cam = Camera {
            position: Vec3::new(0.0, 1.0, 4.0),
            yaw: 0.0,
            pitch: 0.0,
            fov: 45.0,
            near: 0.1,
            far: 10.0,
            animation: Some(CameraAnimationDesc::Path(vec![key(0.0, 0.0, 0.0), key(2.0, 4.0, 90.0)])),
        };
        let mid = cam.at(0.5);
        assert_eq!((mid.position.x, mid.yaw), (1.0, 22.5));
        assert_eq!(cam.at(-1.0).position.x, 0.0);
        assert_eq!(cam.at(5.0).position.x, 4.0);
        let orbit = Camera {
            animation: Some(CameraAnimationDesc::Orbit {
                center: [0.0, 1.0, 0.0],
                speed: 90.0,
            }),
            ..cam
        };
        let q = orbit.at(1.0);
        assert!((q.position - Vec3::new(4.0, 1.0, 0.0)).length() < 1e-4, "{:?}", q.position);
        assert!(
            (q.forward() - Vec3::NEG_X).length() < 1e-4,
            "looks at the centre: {:?}",
            q.forward()
        );
    }
}
