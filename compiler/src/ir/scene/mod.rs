//! The scene IR: what a scene file or built-in scene describes (camera, models, lights,
//! effects), with where each key was written, and the features a Plan is culled by.

pub mod builtin;

use crate::ir::{Effect, LightKind};
use crate::span::{Span, Spanned};
use serde::Serialize;
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

/// Where each key of an item was written, so value checks and later stages can point at it.
/// Keys left out (defaulted) are absent; `span` is then the whole item.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct KeySpans {
    pub span: Span,
    pub keys: BTreeMap<String, Span>,
}

impl KeySpans {
    /// Where `key` was written, else the item.
    pub fn of(&self, key: &str) -> Span {
        self.keys.get(key).copied().unwrap_or(self.span)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    pub position: [f32; 3],
    /// Degrees; 0 looks down -Z, positive turns left (towards -X).
    pub yaw: f32,
    /// Degrees; positive looks up.
    pub pitch: f32,
    /// Vertical field of view in degrees.
    pub fov: f32,
    pub near: f32,
    pub far: f32,
    /// Moves the camera over time (reprojection and temporal effects need motion).
    pub animation: Option<CameraAnimationDesc>,
    pub at: KeySpans,
}

#[derive(Clone, Debug, PartialEq)]
pub enum CameraAnimationDesc {
    /// Circle about the vertical axis through `center`, `speed` degrees per second, from the
    /// camera's position, always looking at `center`.
    Orbit { center: [f32; 3], speed: f32 },
    /// Keyframes, linearly interpolated; held before the first and after the last.
    Path(Vec<CameraKey>),
}

#[derive(Clone, Debug, PartialEq)]
pub struct CameraKey {
    /// Seconds.
    pub time: f32,
    pub position: [f32; 3],
    pub yaw: f32,
    pub pitch: f32,
}

#[derive(Clone, Debug, PartialEq)]
pub enum AnimationDesc {
    /// Circle around `center` (in the XZ plane) at `radius`, `speed` degrees per second.
    Orbit { center: [f32; 3], radius: f32, speed: f32 },
    /// Turn the direction about the Y axis, `speed` degrees per second.
    Rotate { speed: f32 },
}

#[derive(Clone, Debug, PartialEq)]
pub struct LightDesc {
    pub kind: LightKind,
    pub on: bool,
    /// Linear RGB.
    pub color: [f32; 3],
    pub intensity: f32,
    pub position: [f32; 3],
    /// Where the light points (directional, spot).
    pub direction: [f32; 3],
    /// Spot cone half-angles in degrees: full intensity inside `inner`, none outside `outer`.
    pub inner: f32,
    pub outer: f32,
    /// Attenuation range (seed 003 eq. 3.5): contribution reaches 0 here.
    pub range: f32,
    pub shadows: bool,
    pub animation: Option<AnimationDesc>,
    pub at: KeySpans,
}

impl LightDesc {
    pub fn point(position: [f32; 3], color: [f32; 3], intensity: f32, range: f32) -> Self {
        LightDesc {
            kind: LightKind::Point,
            on: true,
            color,
            intensity,
            position,
            direction: [0.0, -1.0, 0.0],
            inner: 25.0,
            outer: 35.0,
            range,
            shadows: true,
            animation: None,
            at: KeySpans::default(),
        }
    }
    pub fn spot(position: [f32; 3], direction: [f32; 3], cone: (f32, f32), color: [f32; 3], intensity: f32, range: f32) -> Self {
        LightDesc {
            kind: LightKind::Spot,
            direction,
            inner: cone.0,
            outer: cone.1,
            ..Self::point(position, color, intensity, range)
        }
    }
    pub fn directional(direction: [f32; 3], color: [f32; 3], intensity: f32) -> Self {
        LightDesc {
            kind: LightKind::Directional,
            direction,
            ..Self::point([0.0; 3], color, intensity, DIRECTIONAL_RANGE)
        }
    }
}

/// Directional lights do not attenuate: their range is this (and not written in files).
pub const DIRECTIONAL_RANGE: f32 = 1e6;

/// A glTF model placed in the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelDesc {
    /// As written (relative to the scene file).
    pub path: Spanned<String>,
    /// The file to load: `path` resolved against the scene file's directory.
    pub file: PathBuf,
    pub translation: [f32; 3],
    /// Yaw, pitch, roll in degrees.
    pub rotation: [f32; 3],
    pub scale: f32,
    /// Fraction of each mesh's triangles drawn, in (0, 1].
    pub triangles: f32,
    pub reflective: bool,
    /// Overrides glTF `doubleSided` for every material of the model (`None`: as the file says).
    pub double_sided: Option<bool>,
    pub at: KeySpans,
}

/// A scene as every command sees it: the built-in geometry it starts from (if any), models,
/// lights (built-in ones first), camera, size and the effects it calls for.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneDesc {
    pub name: String,
    /// The built-in scene whose meshes the runtime adds (`cornell`, `colonnade`, `many_lights`).
    pub geometry: Option<String>,
    pub size: (u32, u32),
    pub camera: CameraDesc,
    pub models: Vec<ModelDesc>,
    pub lights: Vec<LightDesc>,
    pub effects: BTreeSet<Effect>,
    /// The scene file, when read from one.
    pub file: Option<PathBuf>,
    /// A model given as the scene (`--scene model.glb`): once its geometry is loaded, the
    /// camera frames its bounds and, if it brings no lights, the default rig lights it.
    pub framed_model: bool,
}

/// Size of a scene that names none and starts from no built-in scene.
pub const DEFAULT_SIZE: (u32, u32) = (128, 128);
/// Largest width or height a scene (or `--size`) may ask for.
pub const MAX_SIZE: u32 = 16384;

impl SceneDesc {
    /// A scene with nothing in it: what a file without `builtin:` starts from.
    pub fn empty(name: &str) -> Self {
        SceneDesc {
            name: name.into(),
            geometry: None,
            size: DEFAULT_SIZE,
            camera: CameraDesc {
                position: [0.0, 1.0, 4.0],
                yaw: 0.0,
                pitch: 0.0,
                fov: 45.0,
                near: 0.05,
                far: 100.0,
                animation: None,
                at: KeySpans::default(),
            },
            models: vec![],
            lights: vec![],
            effects: BTreeSet::new(),
            file: None,
            framed_model: false,
        }
    }

    /// What the compiler needs to cull and size a Plan, counting `extra` lights too (the
    /// KHR lights of glTF models, which only the runtime reads).
    pub fn features(&self, extra: impl IntoIterator<Item = LightKind>) -> SceneFeatures {
        let reflective = self.models.iter().any(|m| m.reflective);
        // Models' KHR lights cast shadows (glTF cannot say otherwise).
        let order = self.lights.iter().filter(|l| l.on).map(|l| (l.kind, l.shadows));
        let extra = extra.into_iter().map(|k| (k, true));
        let mut f = SceneFeatures::new(&self.name, self.size, [], &self.effects, reflective).with_order(order.chain(extra));
        // Only loading a model shows whether it has blended materials: assume it may.
        f.transparent = !self.models.is_empty();
        f
    }
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneFeatures {
    pub name: String,
    /// Lights that are on, by kind.
    pub lights: BTreeMap<LightKind, u32>,
    /// Of those, the ones that cast shadows.
    pub casters: BTreeMap<LightKind, u32>,
    pub effects: BTreeSet<Effect>,
    pub reflective: bool,
    /// Some mesh blends (glTF alphaMode BLEND): `draw: Transparent` passes have work.
    pub transparent: bool,
    pub size: (u32, u32),
    /// Every light that is on, in the order of the light array a frame binds, and whether it
    /// casts shadows (`with_order`); empty when only counts are known.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub order: Vec<(LightKind, bool)>,
}

impl SceneFeatures {
    /// Features from the kinds of the lights that are on (one entry per light).
    pub fn new(
        name: &str,
        size: (u32, u32),
        lights_on: impl IntoIterator<Item = LightKind>,
        effects: &BTreeSet<Effect>,
        reflective: bool,
    ) -> Self {
        let mut lights = BTreeMap::new();
        for k in lights_on {
            *lights.entry(k).or_insert(0u32) += 1;
        }
        SceneFeatures {
            name: name.into(),
            casters: lights.clone(),
            lights,
            effects: effects.clone(),
            reflective,
            transparent: false,
            size,
            order: vec![],
        }
    }

    /// Used when no scene is given: every light kind once (the punctual ones casting shadows),
    /// every effect, reflective materials; so that nothing is culled for lack of scene content.
    pub fn everything() -> Self {
        SceneFeatures {
            name: "<all features>".into(),
            lights: LightKind::ALL.into_iter().map(|k| (k, 1)).collect(),
            casters: LightKind::ALL.into_iter().filter(|k| k.punctual()).map(|k| (k, 1)).collect(),
            effects: Effect::ALL.into_iter().collect(),
            reflective: true,
            transparent: true,
            size: (1280, 720),
            order: vec![],
        }
    }

    pub fn light_count(&self, kinds: &[LightKind]) -> u32 {
        kinds.iter().map(|k| self.lights.get(k).copied().unwrap_or(0)).sum()
    }

    /// The lights of these kinds that cast shadows.
    pub fn caster_count(&self, kinds: &[LightKind]) -> u32 {
        kinds.iter().map(|k| self.casters.get(k).copied().unwrap_or(0)).sum()
    }

    /// How many times a per-light pass over `kinds` repeats (`casters`: shadow casters only).
    pub fn repeats_for(&self, kinds: &[LightKind], casters: bool) -> u32 {
        if casters {
            self.caster_count(kinds)
        } else {
            self.light_count(kinds)
        }
    }

    /// The lights in the light array's order, each with whether it casts shadows; the counts
    /// follow. A Plan's repetitions name lights by their index in it.
    pub fn with_order(mut self, lights: impl IntoIterator<Item = (LightKind, bool)>) -> Self {
        self.order = lights.into_iter().collect();
        self.lights.clear();
        self.casters.clear();
        for &(k, casts) in &self.order {
            *self.lights.entry(k).or_insert(0u32) += 1;
            if casts {
                *self.casters.entry(k).or_insert(0u32) += 1;
            }
        }
        self
    }

    /// The lights in the light array's order with whether each casts shadows: as given
    /// (`with_order`), else made from the counts (kinds in `LightKind::ALL` order, the first
    /// lights of a kind the casting ones).
    pub fn light_order(&self) -> Vec<(LightKind, bool)> {
        if !self.order.is_empty() {
            return self.order.clone();
        }
        let mut out = vec![];
        for k in LightKind::ALL {
            let (n, casting) = (
                self.lights.get(&k).copied().unwrap_or(0),
                self.casters.get(&k).copied().unwrap_or(0),
            );
            out.extend((0..n).map(|i| (k, i < casting)));
        }
        out
    }
}

/// A scene file as written, lowered from the tree: what it sets, before it is merged with
/// its `builtin:` base. Absent top-level keys are `None`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneFile {
    pub name: Option<String>,
    pub size: Option<Spanned<(u32, u32)>>,
    pub camera: Option<CameraDesc>,
    pub builtin: Option<Spanned<String>>,
    /// `builtin_lights: false`: the base's lights are dropped (the file's own replace them).
    pub builtin_lights: bool,
    pub models: Vec<ModelDesc>,
    pub lights: Vec<LightDesc>,
    pub effects: BTreeSet<Effect>,
}
