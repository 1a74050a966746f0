//! Check stage `scene`: the values of a scene file. Every number finite, and each in the
//! range its meaning allows; a violation is an error at the key, naming the light or model
//! and the field. Nothing is clamped here: what the runtime clamps deliberately is listed
//! in the manual (docs/scenes.md, "Scene files").

use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::scene::{AnimationDesc, CameraAnimationDesc, CameraDesc, KeySpans, LightDesc, ModelDesc, SceneFile, MAX_SIZE};
use crate::ir::LightKind;

/// The smallest field of view, in degrees.
pub const MIN_FOV: f32 = 0.001;
/// The largest far / near ratio a camera may have.
pub const MAX_DEPTH_RATIO: f32 = 1e12;

pub fn scene(file: &SceneFile, diags: &mut Diagnostics) {
    if let Some(size) = &file.size {
        let (w, h) = size.value;
        if !(1..=MAX_SIZE).contains(&w) || !(1..=MAX_SIZE).contains(&h) {
            diags.push(Diagnostic::error(
                Code::ValueOutOfRange,
                format!("scene size ({w}, {h}) is out of range: width and height must be 1 to {MAX_SIZE}"),
                size.span,
            ));
        }
    }
    if let Some(c) = &file.camera {
        camera(c, diags);
    }
    for m in &file.models {
        model(m, diags);
    }
    for (i, l) in file.lights.iter().enumerate() {
        light(i + 1, l, diags);
    }
}

/// Largest camera angle (degrees) a scene may give.
const MAX_ANGLE: f32 = 1e6;

/// Reports against one item: `what` names it ("camera", "light 2 (spot)").
struct Item<'a> {
    what: String,
    at: &'a KeySpans,
    diags: &'a mut Diagnostics,
}

impl Item<'_> {
    /// Every component finite; false (after reporting) when not.
    fn finite(&mut self, key: &str, values: &[f32]) -> bool {
        if values.iter().all(|v| v.is_finite()) {
            return true;
        }
        let shown: Vec<String> = values.iter().map(|v| v.to_string()).collect();
        self.diags.push(
            Diagnostic::error(
                Code::NonFinite,
                format!("`{key}` of {} is not finite ({})", self.what, shown.join(", ")),
                self.at.of(key),
            )
            .with_note("numbers must be finite 32-bit floats (at most about 3.4e38 in size)"),
        );
        false
    }

    /// `ok` or an out-of-range error at `key`.
    fn require(&mut self, ok: bool, key: &str, rule: &str, value: f32) {
        if !ok {
            self.diags.push(Diagnostic::error(
                Code::ValueOutOfRange,
                format!("`{key}` of {} must be {rule} (it is {value})", self.what),
                self.at.of(key),
            ));
        }
    }
}

fn camera(c: &CameraDesc, diags: &mut Diagnostics) {
    let mut it = Item {
        what: "the camera".into(),
        at: &c.at,
        diags,
    };
    let scalars = [("yaw", c.yaw), ("pitch", c.pitch), ("fov", c.fov), ("near", c.near), ("far", c.far)];
    let finite = it.finite("position", &c.position) & scalars.iter().fold(true, |ok, (k, v)| it.finite(k, &[*v]) & ok);
    if !finite {
        return;
    }
    // A vanishing fov makes 1 / tan(fov / 2) overflow (fov 1e-30 gave NaN); 0.001° is a
    // telephoto far beyond any real lens.
    it.require(
        c.fov >= MIN_FOV && c.fov < 180.0,
        "fov",
        "at least 0.001 and below 180 degrees",
        c.fov,
    );
    // An angle of 3e38° is finite but all rounding: its sine and cosine are noise (a black
    // frame). Angles stay within ±1e6°.
    for (k, v) in [("yaw", c.yaw), ("pitch", c.pitch)] {
        it.require(v.abs() <= MAX_ANGLE, k, "within ±1e6 degrees", v);
    }
    it.require(c.near > 0.0, "near", "greater than 0", c.near);
    if c.near > 0.0 {
        let rule = format!("greater than `near` ({})", c.near);
        it.require(c.far > c.near, "far", &rule, c.far);
        // Beyond this the projection's f32 terms overflow (near 1e-20 gave NaN depth).
        let rule = format!(
            "at least `far` / {MAX_DEPTH_RATIO:e} ({:e}): a wider depth range has no precision left",
            c.far / MAX_DEPTH_RATIO
        );
        it.require(c.far / c.near <= MAX_DEPTH_RATIO, "near", &rule, c.near);
    }
    match &c.animation {
        Some(CameraAnimationDesc::Orbit { center, speed }) => {
            it.finite("animation", &[center[0], center[1], center[2], *speed]);
        }
        Some(CameraAnimationDesc::Path(keys)) => {
            let flat: Vec<f32> = keys
                .iter()
                .flat_map(|k| [k.time, k.position[0], k.position[1], k.position[2], k.yaw, k.pitch])
                .collect();
            if it.finite("animation", &flat) {
                path_order(keys, &mut it);
                if let Some(k) = keys.iter().find(|k| k.yaw.abs() > MAX_ANGLE || k.pitch.abs() > MAX_ANGLE) {
                    let v = if k.yaw.abs() > MAX_ANGLE { k.yaw } else { k.pitch };
                    it.require(false, "animation", "a path whose key angles are within ±1e6 degrees", v);
                }
            }
        }
        None => {}
    }
}

/// A camera path needs keys, at increasing times.
fn path_order(keys: &[crate::ir::scene::CameraKey], it: &mut Item) {
    let msg = match keys.windows(2).position(|w| w[1].time <= w[0].time) {
        _ if keys.is_empty() => "the camera's path has no keys".to_string(),
        Some(i) => format!(
            "the camera's path keys must be at increasing times: key {} at {} s follows {} s",
            i + 1,
            keys[i + 1].time,
            keys[i].time
        ),
        None => return,
    };
    it.diags.push(Diagnostic::error(Code::ValueOutOfRange, msg, it.at.of("animation")));
}

fn model(m: &ModelDesc, diags: &mut Diagnostics) {
    let mut it = Item {
        what: format!("model `{}`", m.path.value),
        at: &m.at,
        diags,
    };
    let finite = it.finite("translation", &m.translation)
        & it.finite("rotation", &m.rotation)
        & it.finite("scale", &[m.scale])
        & it.finite("triangles", &[m.triangles]);
    if !finite {
        return;
    }
    it.require(m.scale > 0.0, "scale", "greater than 0", m.scale);
    it.require(m.triangles > 0.0 && m.triangles <= 1.0, "triangles", "in (0, 1]", m.triangles);
    if m.path.value.trim().is_empty() {
        it.diags
            .push(Diagnostic::error(Code::ValueOutOfRange, "a model's `path` is empty", m.path.span));
    }
}

fn light(index: usize, l: &LightDesc, diags: &mut Diagnostics) {
    let mut it = Item {
        what: format!("light {index} ({})", l.kind.name().to_lowercase()),
        at: &l.at,
        diags,
    };
    let scalars = [
        ("intensity", l.intensity),
        ("inner", l.inner),
        ("outer", l.outer),
        ("range", l.range),
    ];
    let finite = it.finite("color", &l.color)
        & it.finite("position", &l.position)
        & it.finite("direction", &l.direction)
        & scalars.iter().fold(true, |ok, (k, v)| it.finite(k, &[*v]) & ok)
        & animation(&mut it, l.animation.as_ref());
    if !finite {
        return;
    }
    it.require(l.intensity >= 0.0, "intensity", "0 or more", l.intensity);
    let darkest = l.color.iter().copied().fold(f32::INFINITY, f32::min);
    it.require(darkest >= 0.0, "color", "0 or more in every component", darkest);
    if l.kind != LightKind::Directional {
        it.require(l.range > 0.0, "range", "greater than 0", l.range);
    }
    if l.kind != LightKind::Point && l.direction.iter().all(|v| v.abs() < 1e-6) {
        let msg = format!("`direction` of {} is the zero vector: the light must point somewhere", it.what);
        it.diags.push(Diagnostic::error(Code::ValueOutOfRange, msg, it.at.of("direction")));
    }
    if l.kind == LightKind::Spot {
        it.require(l.inner >= 0.0, "inner", "0 degrees or more", l.inner);
        it.require(
            l.outer > 0.0 && l.outer < 90.0,
            "outer",
            "between 0 and 90 degrees (exclusive)",
            l.outer,
        );
        let rule = format!("at most `outer` ({})", l.outer);
        it.require(l.inner <= l.outer, "inner", &rule, l.inner);
    }
}

fn animation(it: &mut Item, a: Option<&AnimationDesc>) -> bool {
    match a {
        None => true,
        Some(AnimationDesc::Orbit { center, radius, speed }) => {
            let ok = it.finite("animation", center) & it.finite("animation", &[*radius, *speed]);
            if ok {
                it.require(*radius >= 0.0, "animation", "an orbit of radius 0 or more; the radius", *radius);
            }
            ok
        }
        Some(AnimationDesc::Rotate { speed }) => it.finite("animation", &[*speed]),
    }
}
