//! Stage `spec` of `sweep`: a sweep file (RON) parsed, checked, and expanded into its points
//! in a fixed order (scenes, then sizes, then listed points, then the grid as written, last key
//! fastest),
//! so that every run, shard and merge numbers the points alike.

use crate::error::{Error, Result};
use crate::reference::Term;
use lightbench_compiler::vfs;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A setting's value as written: a number, a boolean, text (variant options, colours as
/// "(r, g, b)") or a list of numbers (a colour).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum Value {
    Bool(bool),
    Int(i64),
    Float(f64),
    Text(String),
    List(Vec<f64>),
}

impl Value {
    /// As `--param`/`@key=value` text.
    pub fn text(&self) -> String {
        match self {
            Value::Bool(b) => b.to_string(),
            Value::Int(i) => i.to_string(),
            Value::Float(f) => format!("{f:?}"),
            Value::Text(t) => t.clone(),
            Value::List(l) => format!("({})", l.iter().map(|v| format!("{v:?}")).collect::<Vec<_>>().join(", ")),
        }
    }
}

/// A map as written, in its order (grids vary their last key fastest).
#[derive(Clone, Debug, PartialEq)]
pub struct Ordered<V>(pub Vec<(String, V)>);

impl<V> Default for Ordered<V> {
    fn default() -> Self {
        Ordered(vec![])
    }
}

impl<V> Ordered<V> {
    pub fn iter(&self) -> impl Iterator<Item = &(String, V)> {
        self.0.iter()
    }
    pub fn contains_key(&self, k: &str) -> bool {
        self.0.iter().any(|(n, _)| n == k)
    }
}

impl<'de, V: Deserialize<'de>> Deserialize<'de> for Ordered<V> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Visit<V>(std::marker::PhantomData<V>);
        impl<'de, V: Deserialize<'de>> serde::de::Visitor<'de> for Visit<V> {
            type Value = Ordered<V>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a map of setting names to values")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut m: A) -> std::result::Result<Ordered<V>, A::Error> {
                let mut out: Vec<(String, V)> = vec![];
                while let Some((k, v)) = m.next_entry::<String, V>()? {
                    if out.iter().any(|(n, _)| *n == k) {
                        return Err(serde::de::Error::custom(format!("`{k}` is given twice")));
                    }
                    out.push((k, v));
                }
                Ok(Ordered(out))
            }
        }
        d.deserialize_map(Visit(std::marker::PhantomData))
    }
}

/// The reference a sweep measures against.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceSpec {
    pub term: Term,
    #[serde(default = "default_radius")]
    pub ao_radius: f32,
    #[serde(default)]
    pub ao_falloff: bool,
    #[serde(default = "default_spp")]
    pub spp: u32,
    #[serde(default)]
    pub seed: u64,
    /// Which renderer makes it: the CPU path tracer, or the same integrator on the sweep's
    /// GPU (`pipelines/pathtrace.lbp`; terms direct, ao, full).
    #[serde(default)]
    pub device: ReferenceDevice,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReferenceDevice {
    #[default]
    Cpu,
    Gpu,
}

fn default_radius() -> f32 {
    0.5
}
fn default_spp() -> u32 {
    64
}
fn default_warmup() -> u32 {
    2
}
fn default_frames() -> u32 {
    8
}

/// A sweep file as written.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename = "Sweep")]
pub struct Spec {
    /// Pipeline file, relative to the sweep file.
    pub pipeline: String,
    /// Built-in scenes or scene files (relative to the sweep file).
    pub scenes: Vec<String>,
    /// Sizes to render at (and to make references at); none: each scene's own.
    #[serde(default)]
    pub sizes: Vec<(u32, u32)>,
    /// Settings every point has: variant options and parameter values.
    #[serde(default)]
    pub set: Ordered<Value>,
    /// Explicit points (each a set of settings, and optionally `compare`: the resource that
    /// holds this point's estimate), each crossed with the grid.
    #[serde(default)]
    pub points: Vec<Ordered<Value>>,
    /// Every combination of these values.
    #[serde(default)]
    pub grid: Ordered<Vec<Value>>,
    /// The effect's passes: their GPU time is the effect's cost.
    pub effect: Vec<String>,
    /// The resource holding the effect's estimate, compared with the reference term.
    pub compare: String,
    pub reference: ReferenceSpec,
    #[serde(default = "default_warmup")]
    pub warmup: u32,
    #[serde(default = "default_frames")]
    pub frames: u32,
}

/// A sweep file loaded: the spec, where it is, and a fingerprint of how it measures.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub path: PathBuf,
    pub name: String,
    pub spec: Spec,
    pub text: String,
    pub fingerprint: String,
    /// Effects every scene of the sweep is to call for besides its own (`--effect`).
    pub effects: Vec<lightbench_compiler::ir::Effect>,
}

impl Loaded {
    /// Add effects to every scene the sweep renders. They change what is measured, so they
    /// are part of the fingerprint: rows measured without them are not mixed in.
    pub fn add_effects(&mut self, effects: &[lightbench_compiler::ir::Effect]) {
        let new: Vec<_> = effects.iter().filter(|e| !self.effects.contains(e)).copied().collect();
        if new.is_empty() {
            return;
        }
        self.effects.extend(new);
        let how = format!("{} effects {:?}", self.fingerprint, self.effects);
        self.fingerprint = format!("{:016x}", crate::io::fnv1a(how.as_bytes()));
    }

    pub fn dir(&self) -> &Path {
        self.path.parent().unwrap_or(Path::new("."))
    }
    pub fn pipeline(&self) -> PathBuf {
        self.dir().join(&self.spec.pipeline)
    }
    /// A scene as the loader takes it: a file beside the sweep file, else a built-in name.
    pub fn scene(&self, name: &str) -> String {
        let p = self.dir().join(name);
        if p.is_file() {
            p.display().to_string()
        } else {
            name.to_string()
        }
    }

    /// `file:line:col: message`, at the first place `needle` is written (else the file).
    pub fn error_at(&self, needle: &str, msg: impl std::fmt::Display) -> Error {
        self.error_in("", needle, msg)
    }

    /// `error_at` for the first `needle` after the field `section` (e.g. a key of `grid`).
    pub fn error_in(&self, section: &str, needle: &str, msg: impl std::fmt::Display) -> Error {
        let section_at = self.text.find(&format!("{section}:")).filter(|_| !section.is_empty());
        let from = section_at.unwrap_or(0);
        // Not written as searched for (a value spelled another way): at its section, else
        // at the top of the file — never without a place.
        let at = self.text[from..].find(needle).map(|i| i + from).or(section_at).unwrap_or(0);
        self.error_at_offset(at, msg)
    }

    /// `file:line:col: message` at byte `i` of the spec (columns in characters).
    pub fn error_at_offset(&self, i: usize, msg: impl std::fmt::Display) -> Error {
        let line = self.text[..i].matches('\n').count() + 1;
        let line_start = self.text[..i].rfind('\n').map_or(0, |n| n + 1);
        let col = self.text[line_start..i].chars().count() + 1;
        Error::Input(format!("{}:{line}:{col}: {msg}", self.path.display()))
    }
}

/// One measurement: a scene at a size with settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub index: usize,
    pub scene: String,
    pub size: Option<(u32, u32)>,
    /// Fixed settings first, then the point's own (the ones that vary), as key=value text.
    pub settings: Vec<(String, String)>,
    /// The settings that vary between points (the point's label).
    pub varying: Vec<(String, String)>,
    /// The resource compared: the spec's `compare`, or the point's own (a listed point's
    /// `compare` key, for options that leave their estimate elsewhere).
    pub compare: String,
}

impl Point {
    /// Stable identity across runs, shards and edits of the spec's lists: the scene, the
    /// size, the varying settings, and the compared resource where the point names its own.
    pub fn id(&self, default_compare: &str) -> String {
        let size = self.size.map(|(w, h)| format!("{w}x{h}")).unwrap_or_else(|| "scene-size".into());
        let mut id = format!("{} {size}", self.scene);
        for (k, v) in &self.varying {
            id.push_str(&format!(" {k}={v}"));
        }
        if self.compare != default_compare {
            id.push_str(&format!(" compare={}", self.compare));
        }
        id
    }
}

pub fn load(path: &Path) -> Result<Loaded> {
    // Through the guarded reader: a FIFO or /dev/zero named as a spec is refused, not read.
    let text = vfs::read_bytes(path, vfs::MAX_FILE_BYTES)
        .and_then(vfs::utf8)
        .map_err(|e| Error::io(path, e))?;
    let spec: Spec = ron::Options::default()
        .from_str(&text)
        .map_err(|e| Error::Input(format!("{}:{}:{}: {}", path.display(), e.span.start.line, e.span.start.col, e.code)))?;
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("sweep").to_string();
    // What decides how a point is measured; the lists of scenes, sizes, points and grid
    // values may change between runs (rows of points still listed are kept).
    let how = format!(
        "{:?} {:?} {:?} {:?} {:?} {} {}",
        spec.pipeline, spec.set, spec.effect, spec.compare, spec.reference, spec.warmup, spec.frames
    );
    let fingerprint = format!("{:016x}", crate::io::fnv1a(how.as_bytes()));
    let loaded = Loaded {
        path: path.to_path_buf(),
        name,
        spec,
        text,
        fingerprint,
        effects: vec![],
    };
    check(&loaded)?;
    Ok(loaded)
}

/// What the spec says that cannot work, wherever the pipeline is not needed to tell.
fn check(l: &Loaded) -> Result<()> {
    let s = &l.spec;
    if s.set.contains_key(COMPARE) || s.grid.contains_key(COMPARE) {
        return Err(l.error_at("\"compare\"", "`compare` may be given by a listed point, not in `set` or `grid`"));
    }
    if s.scenes.is_empty() {
        return Err(l.error_at("scenes", "`scenes` names no scene"));
    }
    if s.effect.is_empty() {
        return Err(l.error_at("effect", "`effect` names no pass: which passes are the effect's cost?"));
    }
    if s.frames == 0 {
        return Err(l.error_at("frames", "`frames` must be at least 1"));
    }
    if s.reference.spp == 0 {
        return Err(l.error_at("spp", "the reference needs at least 1 sample per pixel"));
    }
    if !(s.reference.ao_radius.is_finite() && s.reference.ao_radius > 0.0) {
        return Err(l.error_at("ao_radius", "`ao_radius` must be a positive number"));
    }
    if s.reference.device == ReferenceDevice::Gpu && !crate::gpu_reference::TERMS.contains(&s.reference.term) {
        return Err(l.error_at(
            "device",
            format!(
                "the GPU reference has no term `{}` (it renders direct, ao and full)",
                s.reference.term.name()
            ),
        ));
    }
    if s.sizes.is_empty() && l.text.contains("sizes:") {
        return Err(l.error_at("sizes", "`sizes` names no size (leave the key out to use each scene's own size)"));
    }
    let count = point_count(s);
    if count > MAX_POINTS as u128 {
        let msg = format!("the spec has {count} points (at most {MAX_POINTS}): split it, or sweep fewer values");
        // At the grid key with the most values, else at the listed points.
        return Err(match s.grid.iter().max_by_key(|(_, v)| v.len()) {
            Some((k, _)) => l.error_in("grid", &format!("\"{k}\""), msg),
            None => l.error_at("points", msg),
        });
    }
    if let Some(&(w, h)) = s.sizes.iter().find(|(w, h)| *w == 0 || *h == 0 || *w > 16384 || *h > 16384) {
        return Err(l.error_at("sizes", format!("size {w}x{h} is out of range (1..16384 each way)")));
    }
    for (k, values) in s.grid.iter() {
        if values.is_empty() {
            return Err(l.error_in("grid", &format!("\"{k}\""), format!("grid `{k}` has no values")));
        }
        if s.set.contains_key(k) {
            return Err(l.error_in("grid", &format!("\"{k}\""), format!("`{k}` is both in `set` and in `grid`")));
        }
    }
    for p in &s.points {
        for (k, _) in p.iter() {
            if s.set.contains_key(k) || s.grid.contains_key(k) {
                return Err(l.error_in(
                    "points",
                    &format!("\"{k}\""),
                    format!("`{k}` is set by a point and by `set` or `grid`"),
                ));
            }
        }
    }
    if !l.pipeline().is_file() {
        let msg = format!("no pipeline file `{}` (paths are relative to the spec)", l.pipeline().display());
        return Err(l.error_in("pipeline", &format!("{:?}", s.pipeline), msg));
    }
    Ok(())
}

/// The most points a spec may have: a grid written by mistake (8 million points) is refused
/// before anything is built, rather than exhausting memory listing them.
pub const MAX_POINTS: usize = 100_000;

/// How many points `points` would list, counted without listing them (saturating).
fn point_count(s: &Spec) -> u128 {
    let grid = s.grid.iter().fold(1u128, |n, (_, v)| n.saturating_mul(v.len() as u128));
    [s.scenes.len().max(1), s.sizes.len().max(1), s.points.len().max(1)]
        .iter()
        .fold(grid, |n, &k| n.saturating_mul(k as u128))
}

/// The key of a listed point that names its compared resource (not a setting).
const COMPARE: &str = "compare";

/// Every point, numbered.
pub fn points(l: &Loaded) -> Vec<Point> {
    let s = &l.spec;
    let fixed: Vec<(String, String)> = s.set.iter().map(|(k, v)| (k.clone(), v.text())).collect();
    let listed: Vec<(Vec<(String, String)>, String)> = if s.points.is_empty() {
        vec![(vec![], s.compare.clone())]
    } else {
        s.points
            .iter()
            .map(|p| {
                let compare = p.iter().find(|(k, _)| k == COMPARE).map_or(s.compare.clone(), |(_, v)| v.text());
                let own = p.iter().filter(|(k, _)| k != COMPARE).map(|(k, v)| (k.clone(), v.text())).collect();
                (own, compare)
            })
            .collect()
    };
    let mut combos: Vec<Vec<(String, String)>> = vec![vec![]];
    for (k, values) in s.grid.iter() {
        combos = combos
            .into_iter()
            .flat_map(|c| {
                values.iter().map(move |v| {
                    let mut c = c.clone();
                    c.push((k.clone(), v.text()));
                    c
                })
            })
            .collect();
    }
    let sizes: Vec<Option<(u32, u32)>> = if s.sizes.is_empty() {
        vec![None]
    } else {
        s.sizes.iter().copied().map(Some).collect()
    };
    let mut out = vec![];
    for scene in &s.scenes {
        for size in &sizes {
            for (own, compare) in &listed {
                for combo in &combos {
                    let varying: Vec<(String, String)> = own.iter().chain(combo).cloned().collect();
                    out.push(Point {
                        index: out.len(),
                        scene: scene.clone(),
                        size: *size,
                        settings: fixed.iter().chain(&varying).cloned().collect(),
                        varying,
                        compare: compare.clone(),
                    });
                }
            }
        }
    }
    out
}

/// `K/N`: this run measures the points whose index is K modulo N.
pub fn parse_shard(text: &str) -> Result<(usize, usize)> {
    let bad = || Error::Usage(format!("--shard `{text}`: expected K/N with 0 ≤ K < N (e.g. 0/4)"));
    let (k, n) = text.split_once('/').ok_or_else(bad)?;
    let (k, n): (usize, usize) = (k.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
    if n == 0 || k >= n {
        return Err(bad());
    }
    Ok((k, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn loaded(text: &str) -> Result<Loaded> {
        let dir = std::env::temp_dir().join(format!("lightbench-sweep-spec-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(format!("s{}.ron", crate::io::fnv1a(text.as_bytes())));
        std::fs::write(&p, text).unwrap();
        std::fs::write(dir.join("p.lbp"), "").unwrap(); // the spec's pipeline exists
        load(&p)
    }

    const BASE: &str = r#"Sweep(
    pipeline: "p.lbp",
    scenes: ["cornell"],
    sizes: [(32, 32)],
    set: {"ambient.color": "(0, 0, 0)"},
    grid: {"b": [1, 2], "a": [true, false]},
    effect: ["pass"],
    compare: "hdr",
    reference: (term: direct),
)"#;

    #[test]
    fn grids_expand_in_key_order_last_key_fastest() {
        let l = loaded(BASE).unwrap();
        let p = points(&l);
        let ids: Vec<String> = p.iter().map(|p| p.id("hdr")).collect();
        assert_eq!(
            ids,
            [
                "cornell 32x32 b=1 a=true",
                "cornell 32x32 b=1 a=false",
                "cornell 32x32 b=2 a=true",
                "cornell 32x32 b=2 a=false"
            ]
        );
        assert_eq!(p[3].settings[0], ("ambient.color".into(), "(0, 0, 0)".into()));
        assert_eq!((l.spec.warmup, l.spec.frames, l.spec.reference.spp), (2, 8, 64));
    }

    #[test]
    fn bad_specs_are_located() {
        let e = loaded(&BASE.replace("compare", "compar")).unwrap_err().to_string();
        assert!(e.contains(":7:") || e.contains(":8:"), "{e}");
        let e = loaded(&BASE.replace("\"a\": [true, false]", "\"ambient.color\": [1]"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(":6:") && e.contains("both in `set` and in `grid`"), "{e}");
        let e = loaded(&BASE.replace("[\"pass\"]", "[]")).unwrap_err().to_string();
        assert!(e.contains(":7:") && e.contains("names no pass"), "{e}");
        let e = loaded(&BASE.replace("term: direct", "term: shadows")).unwrap_err().to_string();
        assert!(e.contains(":9:"), "{e}");
        assert_eq!(parse_shard("1/3").unwrap(), (1, 3));
        for bad in ["3/3", "1", "a/b", "0/0"] {
            assert!(parse_shard(bad).is_err(), "{bad}");
        }
    }
}
