//! Lowering of scene files: tree -> `SceneFile`. Absent keys take their defaults from the
//! table (owners `Camera`, `Model`, `Light`, `Orbit`, `Rotate`); value ranges are checked
//! by `check::scene`, not here.

use super::{Lowerer, Obj, Res};
use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::ir::scene::{builtin, AnimationDesc, CameraAnimationDesc, CameraDesc, CameraKey, LightDesc, ModelDesc, SceneFile};
use crate::ir::{Effect, LightKind};
use crate::span::Spanned;
use crate::tree::{Node, Value};
use std::path::Path;

/// Lower a scene tree; model paths resolve against `dir`. `None` when it cannot be lowered.
pub fn scene(root: &Node, dir: &Path, diags: &mut Diagnostics) -> Option<SceneFile> {
    let before = diags.error_count();
    let s = Lowerer::new(diags).scene(root, dir);
    if diags.error_count() > before {
        return None;
    }
    s
}

const SCENE_KEYS: &[&str] = &["name", "size", "camera", "builtin", "builtin_lights", "models", "lights", "effects"];
const CAMERA_KEYS: &[&str] = &["position", "yaw", "pitch", "fov", "near", "far", "animation"];
const MODEL_KEYS: &[&str] = &[
    "path",
    "translation",
    "rotation",
    "scale",
    "triangles",
    "reflective",
    "double_sided",
];
const LIGHT_KEYS: &[&str] = &[
    "on",
    "color",
    "intensity",
    "shadows",
    "animation",
    "position",
    "direction",
    "inner",
    "outer",
    "range",
];

/// Keys a light kind has: every light has the first five; the rest by kind.
fn light_keys(kind: LightKind) -> Vec<&'static str> {
    let own: &[&str] = match kind {
        LightKind::Point => &["position", "range"],
        LightKind::Spot => &["position", "direction", "inner", "outer", "range"],
        LightKind::Directional => &["direction"],
        // Not written in scenes: one per emissive mesh.
        LightKind::Area => &[],
    };
    LIGHT_KEYS[..5].iter().chain(own).copied().collect()
}

impl Lowerer<'_> {
    fn scene(&mut self, root: &Node, dir: &Path) -> Res<SceneFile> {
        let mut o = self.obj(root, &["Scene"], "scene")?;
        let name = o.take("name").and_then(|n| self.string(&n)).map(|s| s.value);
        let size = o.take("size").and_then(|n| self.size_pair(&n));
        let camera = o.take("camera").and_then(|n| self.camera(&n));
        let builtin = o.take("builtin").and_then(|n| self.builtin_name(&n));
        let builtin_lights = match o.take("builtin_lights") {
            Some(n) => self.bool(&n),
            None => Some(true),
        };
        let models = o.take("models").map(|n| self.each(&n, |l, m| l.model(m, dir)));
        let lights = o.take("lights").map(|n| self.each(&n, |l, m| l.light(m)));
        let effects = o.take("effects").and_then(|n| self.effects(&n));
        self.finish(o, SCENE_KEYS, &[]);
        Some(SceneFile {
            name,
            size,
            camera,
            builtin,
            builtin_lights: builtin_lights?,
            models: models.unwrap_or_default(),
            lights: lights.unwrap_or_default(),
            effects: effects.unwrap_or_default(),
        })
    }

    /// Lower every item of a list, keeping those that lower.
    fn each<T>(&mut self, n: &Node, mut f: impl FnMut(&mut Self, &Node) -> Res<T>) -> Vec<T> {
        let items = self.list(n).map(<[Node]>::to_vec).unwrap_or_default();
        items.iter().filter_map(|i| f(self, i)).collect()
    }

    fn size_pair(&mut self, n: &Node) -> Res<Spanned<(u32, u32)>> {
        match &*n.value {
            Value::Tuple { name: None, items } if items.len() == 2 => {
                let (w, h) = (self.u32(&items[0])?, self.u32(&items[1])?);
                Some(Spanned::new((w.value, h.value), n.span))
            }
            _ => self.type_err("`(width, height)`", n),
        }
    }

    fn builtin_name(&mut self, n: &Node) -> Res<Spanned<String>> {
        let s = self.string(n)?;
        if builtin::by_name(&s.value).is_none() {
            self.err(
                Diagnostic::error(Code::UnknownValue, format!("unknown built-in scene `{}`", s.value), s.span)
                    .with_note(suggestion_note(&s.value, &builtin::NAMES)),
            );
            return None;
        }
        Some(s)
    }

    fn effects(&mut self, n: &Node) -> Res<std::collections::BTreeSet<Effect>> {
        let items = self.list(n)?.to_vec();
        let mut out = std::collections::BTreeSet::new();
        for it in &items {
            match &*it.value {
                Value::Ident(e) => match Effect::from_name(e) {
                    Some(e) => {
                        out.insert(e);
                    }
                    None => self.err(
                        Diagnostic::error(Code::UnknownEffect, format!("unknown effect `{e}`"), it.span)
                            .with_note(suggestion_note(e, &Effect::NAMES)),
                    ),
                },
                _ => return self.type_err("an effect name such as `Shadows`", it),
            }
        }
        Some(out)
    }

    fn camera(&mut self, n: &Node) -> Res<CameraDesc> {
        let mut o = self.obj(n, &["Camera"], "camera")?;
        let position = self.required(&mut o, "position").and_then(|n| self.vec3(&n));
        let yaw = self.num(&mut o, "yaw");
        let pitch = self.num(&mut o, "pitch");
        let fov = self.num(&mut o, "fov");
        let near = self.num(&mut o, "near");
        let far = self.num(&mut o, "far");
        let animation = match o.take("animation") {
            Some(a) => Some(self.camera_animation(&a)?),
            None => None,
        };
        let at = o.key_spans();
        self.finish(o, CAMERA_KEYS, &[]);
        Some(CameraDesc {
            position: position?,
            yaw: yaw?,
            pitch: pitch?,
            fov: fov?,
            near: near?,
            far: far?,
            animation,
            at,
        })
    }

    /// `Orbit(center, speed)` or `Path(keys: [(time, position, yaw, pitch), ...])`.
    fn camera_animation(&mut self, n: &Node) -> Res<CameraAnimationDesc> {
        let mut o = self.obj(n, &["Orbit", "Path"], "camera animation")?;
        if o.kind == "Orbit" {
            let center = self.required(&mut o, "center").and_then(|n| self.vec3(&n));
            let speed = self.required(&mut o, "speed").and_then(|n| self.f32(&n));
            self.finish(o, &["center", "speed"], &[]);
            return Some(CameraAnimationDesc::Orbit {
                center: center?,
                speed: speed?,
            });
        }
        let keys = self.required(&mut o, "keys").map(|n| self.each(&n, |l, k| l.camera_key(k)));
        self.finish(o, &["keys"], &[]);
        Some(CameraAnimationDesc::Path(keys?))
    }

    fn camera_key(&mut self, n: &Node) -> Res<CameraKey> {
        let mut o = self.obj(n, &["Key"], "camera key")?;
        let time = self.required(&mut o, "time").and_then(|n| self.f32(&n));
        let position = self.required(&mut o, "position").and_then(|n| self.vec3(&n));
        let yaw = o.take("yaw").map(|n| self.f32(&n)).unwrap_or(Some(0.0));
        let pitch = o.take("pitch").map(|n| self.f32(&n)).unwrap_or(Some(0.0));
        self.finish(o, &["time", "position", "yaw", "pitch"], &[]);
        Some(CameraKey {
            time: time?,
            position: position?,
            yaw: yaw?,
            pitch: pitch?,
        })
    }

    fn model(&mut self, n: &Node, dir: &Path) -> Res<ModelDesc> {
        let mut o = self.obj(n, &["Model"], "model")?;
        let path = self.required(&mut o, "path").and_then(|n| self.string(&n));
        if let Some(p) = &path {
            o.what = format!("model `{}`", p.value);
        }
        let translation = o.get("translation").and_then(|n| self.vec3(&n));
        let rotation = o.get("rotation").and_then(|n| self.vec3(&n));
        let scale = self.num(&mut o, "scale");
        let triangles = self.num(&mut o, "triangles");
        let reflective = o.get("reflective").and_then(|n| self.bool(&n));
        // No default: absent, each material keeps the glTF file's `doubleSided`.
        let double_sided = match o.take("double_sided") {
            Some(n) => self.bool(&n).map(Some),
            None => Some(None),
        };
        let at = o.key_spans();
        self.finish(o, MODEL_KEYS, &[]);
        let path = path?;
        Some(ModelDesc {
            file: crate::vfs::normalize(&dir.join(&path.value)),
            path,
            translation: translation?,
            rotation: rotation?,
            scale: scale?,
            triangles: triangles?,
            reflective: reflective?,
            double_sided: double_sided?,
            at,
        })
    }

    fn light(&mut self, n: &Node) -> Res<LightDesc> {
        let mut o = self.obj(n, &LightKind::PUNCTUAL_NAMES, "light")?;
        let kind = LightKind::from_name(&o.kind)?;
        o.what = format!("{} light", o.kind.to_lowercase());
        let on = o.get("on").and_then(|n| self.bool(&n));
        let color = o.get("color").and_then(|n| self.vec3(&n));
        let intensity = self.num(&mut o, "intensity");
        let position = o.get("position").and_then(|n| self.vec3(&n));
        let direction = o.get("direction").and_then(|n| self.vec3(&n));
        let inner = self.num(&mut o, "inner");
        let outer = self.num(&mut o, "outer");
        let range = self.num(&mut o, "range");
        let shadows = o.get("shadows").and_then(|n| self.bool(&n));
        let animation = match o.take("animation") {
            Some(a) => Some(self.animation(&a)?),
            None => None,
        };
        let at = o.key_spans();
        self.finish_light(o, kind);
        let range = if kind == LightKind::Directional {
            crate::ir::scene::DIRECTIONAL_RANGE
        } else {
            range?
        };
        Some(LightDesc {
            kind,
            on: on?,
            color: color?,
            intensity: intensity?,
            position: position?,
            direction: direction?,
            inner: inner?,
            outer: outer?,
            range,
            shadows: shadows?,
            animation,
            at,
        })
    }

    /// Keys of other light kinds are `misplaced`: taking them above marked them used, so
    /// they are reported here before `finish` sees the rest.
    fn finish_light(&mut self, o: Obj, kind: LightKind) {
        let own = light_keys(kind);
        for (k, span) in o.given() {
            if LIGHT_KEYS.contains(&k.as_str()) && !own.contains(&k.as_str()) {
                self.err(Diagnostic::error(
                    Code::Misplaced,
                    format!("`{k}` is not a property of {} lights", kind.name().to_lowercase()),
                    span,
                ));
            }
        }
        self.finish(o, LIGHT_KEYS, &[]);
    }

    fn animation(&mut self, n: &Node) -> Res<AnimationDesc> {
        let mut o = self.obj(n, &["Orbit", "Rotate"], "animation")?;
        let a = if o.kind == "Orbit" {
            let center = self.required(&mut o, "center").and_then(|n| self.vec3(&n));
            let radius = self.required(&mut o, "radius").and_then(|n| self.f32(&n));
            let speed = self.required(&mut o, "speed").and_then(|n| self.f32(&n));
            self.finish(o, &["center", "radius", "speed"], &[]);
            AnimationDesc::Orbit {
                center: center?,
                radius: radius?,
                speed: speed?,
            }
        } else {
            let speed = self.required(&mut o, "speed").and_then(|n| self.f32(&n));
            self.finish(o, &["speed"], &[]);
            AnimationDesc::Rotate { speed: speed? }
        };
        Some(a)
    }

    /// A number key, defaulted from the table.
    fn num(&mut self, o: &mut Obj, key: &str) -> Res<f32> {
        o.get(key).and_then(|n| self.f32(&n))
    }

    /// Numbers are stored as f32; one too large for f32 becomes infinite, which
    /// `check::scene` reports as non-finite.
    fn f32(&mut self, n: &Node) -> Res<f32> {
        self.number(n).map(|v| v as f32)
    }

    fn vec3(&mut self, n: &Node) -> Res<[f32; 3]> {
        match &*n.value {
            Value::Tuple { name: None, items } if items.len() == 3 => {
                Some([self.f32(&items[0])?, self.f32(&items[1])?, self.f32(&items[2])?])
            }
            _ => self.type_err("`(x, y, z)`", n),
        }
    }
}
