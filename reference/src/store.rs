//! Stage `store` of the reference renderer: a folder per reference — `TERM.exr` (linear
//! RGB), `TERM.variance.exr` (variance of each pixel's mean), `TERM.png` (a preview) and
//! `reference.json` — keyed by
//! a hash of the scene and the settings, so that a rerun, or a sweep asking again, reuses it.

use super::{Reference, Settings, Term, TermImage};
use crate::error::{Error, Result};
use lightbench_compiler::vfs;
use lightbench_scene::io::Image;
use lightbench_scene::Scene;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Bumped when the renderer's results change for the same inputs (old caches then miss).
// 2: sidedness (single-sided backs are not seen; glTF doubleSided).
// 3: emitters sampled as lights (MIS), one-sided emission; camera rays in f64.
// 4: nothing reflected towards a viewer below the shading normal's hemisphere.
const VERSION: u32 = 4;
const MANIFEST: &str = "reference.json";
/// Largest working set a reference may take (the machine this runs on has 24 GiB).
const MAX_BYTES: u64 = 8 << 30;

/// Which renderer made a reference: this crate's CPU path tracer, or the same integrator on
/// a GPU (`pipelines/pathtrace.lbp`) on the adapter named. A GPU's references are cached
/// apart from the CPU's (the key includes the adapter): equal within noise, not bit for bit.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Device {
    #[default]
    Cpu,
    Gpu(String),
}

#[derive(Serialize, Deserialize)]
struct Manifest {
    version: u32,
    key: String,
    #[serde(default)]
    device: Device,
    scene: String,
    size: (u32, u32),
    settings: Settings,
    spp: u32,
    seconds: f64,
    triangles: usize,
    /// Camera-ray samples per second over all terms (exact terms count once per pixel).
    samples_per_second: f64,
    terms: Vec<Term>,
    /// Samples per pixel behind each term (1 for a noise-free one).
    term_samples: Vec<u32>,
    /// A hash of each term's mean and variance values: an image swapped for another term's
    /// or another reference's is found out.
    term_hashes: Vec<String>,
    emitters: usize,
    reached: Option<super::Reached>,
}

/// Everything the images depend on, hashed: geometry, materials, textures, lights, camera,
/// size, settings and the renderer's version.
pub fn key(scene: &Scene, s: &Settings) -> String {
    key_on(scene, s, &Device::Cpu)
}

/// `key` of a reference made on `device` (the CPU's is `key`'s, so its caches stay valid).
pub fn key_on(scene: &Scene, s: &Settings, device: &Device) -> String {
    let mut h = lightbench_scene::io::Fnv1a::default();
    h.field(format!("v{VERSION} {:?} {:?} {:?}", scene.size, scene.camera, s).as_bytes());
    if let Device::Gpu(adapter) = device {
        h.field(format!("gpu {adapter}").as_bytes());
    }
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
    write_on(r, scene, (s, &Device::Cpu), dir)
}

/// `write` for a reference made on `device`.
pub fn write_on(r: &Reference, scene: &Scene, (s, device): (&Settings, &Device), dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    for t in &r.terms {
        t.mean.save(&dir.join(format!("{}.exr", t.term.name())))?;
        t.variance.save(&dir.join(format!("{}.variance.exr", t.term.name())))?;
        preview(t).save(&dir.join(format!("{}.png", t.term.name())))?;
    }
    let samples = r.terms.iter().map(|t| t.samples as u64).sum::<u64>() * (scene.size.0 * scene.size.1) as u64;
    let m = Manifest {
        version: VERSION,
        key: key_on(scene, s, device),
        device: device.clone(),
        scene: scene.name.clone(),
        size: scene.size,
        settings: s.clone(),
        spp: r.spp,
        seconds: r.seconds,
        triangles: r.triangles,
        samples_per_second: samples as f64 / r.seconds.max(1e-9),
        terms: r.terms.iter().map(|t| t.term).collect(),
        term_samples: r.terms.iter().map(|t| t.samples).collect(),
        term_hashes: r.terms.iter().map(image_hash).collect(),
        emitters: r.emitters,
        reached: r.reached,
    };
    let text = serde_json::to_string_pretty(&m).map_err(|e| Error::io(dir, e))?;
    Ok(lightbench_scene::io::write_atomic(&dir.join(MANIFEST), text.as_bytes())?)
}

/// A PNG to look at: radiance mapped by L/(1+L) (AO as it is).
fn preview(t: &TermImage) -> Image {
    if t.term == Term::Ao {
        t.mean.clone()
    } else {
        t.mean.tone_mapped()
    }
}

/// The reference in `dir` if it was made from the same scene and settings and every image
/// is whole: each term the settings ask for, at the scene's size, finite. Anything else (an
/// image cut short, replaced, or another term's) is a miss, rendered again.
pub fn load(scene: &Scene, s: &Settings, dir: &Path) -> Result<Option<Reference>> {
    load_on(scene, (s, &Device::Cpu), dir)
}

/// `load` of a reference made on `device`.
pub fn load_on(scene: &Scene, (s, device): (&Settings, &Device), dir: &Path) -> Result<Option<Reference>> {
    let read = vfs::read_bytes(&dir.join(MANIFEST), 1 << 20).and_then(vfs::utf8);
    let Ok(text) = read else {
        return Ok(None);
    };
    let Ok(m) = serde_json::from_str::<Manifest>(&text) else {
        return Ok(None);
    };
    let mut wanted = s.terms.clone();
    wanted.sort();
    wanted.dedup();
    let n = m.terms.len();
    if m.version != VERSION
        || m.key != key_on(scene, s, device)
        || m.device != *device
        || m.terms != wanted
        || m.term_samples.len() != n
        || m.term_hashes.len() != n
    {
        return Ok(None);
    }
    let mut terms = vec![];
    for ((&t, &samples), hash) in m.terms.iter().zip(&m.term_samples).zip(&m.term_hashes) {
        let read = |suffix: &str| load_exr(&dir.join(format!("{}{suffix}.exr", t.name())));
        let (Ok(mean), Ok(variance)) = (read(""), read(".variance")) else {
            return Ok(None);
        };
        let image = TermImage {
            term: t,
            samples,
            mean,
            variance,
        };
        if !whole(&image.mean, scene.size) || !whole(&image.variance, scene.size) || image_hash(&image) != *hash {
            return Ok(None);
        }
        terms.push(image);
    }
    Ok(Some(Reference {
        terms,
        spp: m.spp,
        seconds: m.seconds,
        triangles: m.triangles,
        emitters: m.emitters,
        reached: m.reached,
    }))
}

/// FNV-1a of a term's mean and variance values.
fn image_hash(t: &TermImage) -> String {
    let mut h = lightbench_scene::io::Fnv1a::default();
    h.field(bytemuck::cast_slice(&t.mean.rgba));
    h.field(bytemuck::cast_slice(&t.variance.rgba));
    format!("{:016x}", h.0)
}

/// An image of `size` whose every value is finite.
fn whole(img: &Image, size: (u32, u32)) -> bool {
    (img.width, img.height) == size && img.rgba.len() == (size.0 * size.1 * 4) as usize && img.rgba.iter().all(|v| v.is_finite())
}

/// The reference for `scene` and `s` from `dir`, rendered (and written there) if it is not
/// there yet. `true` with it: it was rendered now.
pub fn cached(scene: &Scene, s: &Settings, dir: &Path, progress: bool) -> Result<(Reference, bool)> {
    cached_on(scene, (s, &Device::Cpu), dir, || render_cpu(scene, s, progress))
}

/// The reference for `scene` and `s` made on `device` from `dir`, else made by `render`
/// (whose errors are the caller's type, which takes this crate's) and written there; `true`
/// with it: it was rendered now.
pub fn cached_on<E: From<Error>>(
    scene: &Scene,
    (s, device): (&Settings, &Device),
    dir: &Path,
    render: impl FnOnce() -> std::result::Result<Reference, E>,
) -> std::result::Result<(Reference, bool), E> {
    if let Some(r) = load_on(scene, (s, device), dir)? {
        return Ok((r, false));
    }
    let r = render()?;
    write_on(&r, scene, (s, device), dir)?;
    Ok((r, true))
}

/// The CPU path tracer's render, refused when its sums would not fit in memory.
fn render_cpu(scene: &Scene, s: &Settings, progress: bool) -> Result<Reference> {
    let need = super::memory_bytes(scene.size, s.terms.len());
    if need > MAX_BYTES {
        return Err(Error::TooLarge(format!(
            "a reference of {} term(s) at {}x{} needs {:.1} GiB of sums and images (at most {} GiB): render it smaller or with fewer terms",
            s.terms.len(),
            scene.size.0,
            scene.size.1,
            need as f64 / (1u64 << 30) as f64,
            MAX_BYTES >> 30
        )));
    }
    Ok(super::render(scene, s, progress))
}

/// A linear EXR as RGBA floats (a regular file of at most 4 GiB: a pipe or device put in
/// its place is refused, not waited on).
pub fn load_exr(path: &Path) -> Result<Image> {
    vfs::regular_file(path, 4 << 30).map_err(|e| Error::io(path, e))?;
    let img = image::open(path).map_err(|e| Error::io(path, e))?.to_rgba32f();
    Ok(Image {
        width: img.width(),
        height: img.height(),
        rgba: img.into_raw(),
        srgb: false,
    })
}
