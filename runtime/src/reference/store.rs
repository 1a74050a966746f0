//! Stage `store` of the reference renderer: a folder per reference — `TERM.exr` (linear
//! RGB), `TERM.variance.exr` (variance of each pixel's mean), `TERM.png` (a preview) and
//! `reference.json` — keyed by
//! a hash of the scene and the settings, so that a rerun, or a sweep asking again, reuses it.

use super::{Reference, Settings, Term, TermImage};
use crate::error::{Error, Result};
use crate::io::Image;
use crate::scene::Scene;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Bumped when the renderer's results change for the same inputs (old caches then miss).
// 2: sidedness (single-sided backs are not seen; glTF doubleSided).
const VERSION: u32 = 2;
const MANIFEST: &str = "reference.json";
/// Largest working set a reference may take (the machine this runs on has 24 GiB).
const MAX_BYTES: u64 = 8 << 30;

#[derive(Serialize, Deserialize)]
struct Manifest {
    version: u32,
    key: String,
    scene: String,
    size: (u32, u32),
    settings: Settings,
    spp: u32,
    seconds: f64,
    triangles: usize,
    /// Camera-ray samples per second over all terms (exact terms count once per pixel).
    samples_per_second: f64,
    terms: Vec<Term>,
}

/// Everything the images depend on, hashed: geometry, materials, textures, lights, camera,
/// size, settings and the renderer's version.
pub fn key(scene: &Scene, s: &Settings) -> String {
    let mut h = crate::render::Fnv1a::default();
    h.field(format!("v{VERSION} {:?} {:?} {:?}", scene.size, scene.camera, s).as_bytes());
    for m in &scene.meshes {
        h.field(bytemuck::cast_slice(&m.vertices));
        h.field(bytemuck::cast_slice(
            &m.indices[..(m.drawn_indices() as usize).min(m.indices.len())],
        ));
        h.field(format!("{} {:?}", m.material, m.transform).as_bytes());
    }
    for m in &scene.materials {
        h.field(format!("{m:?}").as_bytes());
    }
    for t in &scene.textures {
        h.field(format!("{} {} {}", t.width, t.height, t.srgb).as_bytes());
        h.field(&t.rgba);
    }
    for l in scene.active_lights() {
        h.field(format!("{:?}", l.at(0.0)).as_bytes());
    }
    format!("{:016x}", h.0)
}

/// Write the reference's images and manifest into `dir` (each file atomically; the manifest
/// last, so a folder with a manifest is complete).
pub fn write(r: &Reference, scene: &Scene, s: &Settings, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    for t in &r.terms {
        t.mean.save(&dir.join(format!("{}.exr", t.term.name())))?;
        t.variance.save(&dir.join(format!("{}.variance.exr", t.term.name())))?;
        preview(t).save(&dir.join(format!("{}.png", t.term.name())))?;
    }
    let samples = r.terms.iter().map(|t| if t.term.exact() { 1 } else { r.spp as u64 }).sum::<u64>() * (scene.size.0 * scene.size.1) as u64;
    let m = Manifest {
        version: VERSION,
        key: key(scene, s),
        scene: scene.name.clone(),
        size: scene.size,
        settings: s.clone(),
        spp: r.spp,
        seconds: r.seconds,
        triangles: r.triangles,
        samples_per_second: samples as f64 / r.seconds.max(1e-9),
        terms: r.terms.iter().map(|t| t.term).collect(),
    };
    let text = serde_json::to_string_pretty(&m).map_err(|e| Error::io(dir, e))?;
    crate::io::write_atomic(&dir.join(MANIFEST), text.as_bytes())
}

/// A PNG to look at: radiance mapped by L/(1+L) (AO as it is).
fn preview(t: &TermImage) -> Image {
    if t.term == Term::Ao {
        t.mean.clone()
    } else {
        t.mean.tone_mapped()
    }
}

/// The reference in `dir` if it was made from the same scene and settings.
pub fn load(scene: &Scene, s: &Settings, dir: &Path) -> Result<Option<Reference>> {
    let Ok(text) = std::fs::read_to_string(dir.join(MANIFEST)) else {
        return Ok(None);
    };
    let Ok(m) = serde_json::from_str::<Manifest>(&text) else {
        return Ok(None);
    };
    if m.version != VERSION || m.key != key(scene, s) {
        return Ok(None);
    }
    let mut terms = vec![];
    for t in m.terms {
        let read = |suffix: &str| load_exr(&dir.join(format!("{}{suffix}.exr", t.name())));
        match (read(""), read(".variance")) {
            (Ok(mean), Ok(variance)) => terms.push(TermImage { term: t, mean, variance }),
            _ => return Ok(None),
        }
    }
    Ok(Some(Reference {
        terms,
        spp: m.spp,
        seconds: m.seconds,
        triangles: m.triangles,
    }))
}

/// The reference for `scene` and `s` from `dir`, rendered (and written there) if it is not
/// there yet. `true` with it: it was rendered now.
pub fn cached(scene: &Scene, s: &Settings, dir: &Path, progress: bool) -> Result<(Reference, bool)> {
    if let Some(r) = load(scene, s, dir)? {
        return Ok((r, false));
    }
    let need = super::memory_bytes(scene.size, s.terms.len());
    if need > MAX_BYTES {
        return Err(Error::Usage(format!(
            "a reference of {} term(s) at {}x{} needs {:.1} GiB of sums and images (at most {} GiB): render it smaller or with fewer terms",
            s.terms.len(),
            scene.size.0,
            scene.size.1,
            need as f64 / (1u64 << 30) as f64,
            MAX_BYTES >> 30
        )));
    }
    let r = super::render(scene, s, progress);
    write(&r, scene, s, dir)?;
    Ok((r, true))
}

/// A linear EXR as RGBA floats.
pub fn load_exr(path: &Path) -> Result<Image> {
    let img = image::open(path).map_err(|e| Error::io(path, e))?.to_rgba32f();
    Ok(Image {
        width: img.width(),
        height: img.height(),
        rgba: img.into_raw(),
        srgb: false,
    })
}
