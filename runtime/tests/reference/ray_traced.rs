//! Ray-traced options (`shadows = rt`) against the reference: the raster's shadow rays trace
//! the same triangles the path tracer does, so its direct light should be the reference's.

use super::gpu_common;
use lightbench::io::Image;

/// `shadows = rt` with ambient 0 equals the reference's `direct` term: on the Cornell box, the
/// sun- and spot-lit boxes and every hard scene, ≥ 99% of values within 2% and lit where the
/// reference is lit (give or take edge pixels) — where shadow maps need per-scene exceptions.
/// `many_lights` is the one exception, as for shadow maps: its 100 lights are `shadows: false`,
/// which the raster honours and the reference (the truth it approximates) does not.
#[test]
fn ray_traced_shadows_equal_the_reference_direct_light() {
    let mut files: Vec<_> = std::fs::read_dir(gpu_common::root().join("scenes/hard"))
        .unwrap()
        .map(|e| e.unwrap().path().to_string_lossy().into_owned())
        .filter(|p| p.ends_with(".ron"))
        .collect();
    files.sort();
    assert!(files.len() >= 20, "{files:?}");
    let mut scenes = vec!["cornell".to_string()];
    for f in ["scenes/cornell_sun.ron", "scenes/cornell_spot.ron"] {
        scenes.push(gpu_common::root().join(f).to_string_lossy().into_owned());
    }
    scenes.extend(files);
    let mut failures = vec![];
    for name in &scenes {
        let s = lightbench::scene::load::load_sized(name, Some((64, 64)), &[]).unwrap();
        let (raster, reference) =
            gpu_common::raster_and_direct(&s, &gpu_common::deferred(), &[("shadows", "rt")], &[("ambient.color", "(0, 0, 0)")]);
        assert!(raster.rgba.iter().all(|v| v.is_finite()), "{}: NaN or Inf", s.name);
        let (share, median) = gpu_common::agreement(&raster, &reference, 0.02);
        let lit = |img: &Image| img.rgba.chunks_exact(4).filter(|p| p[0] + p[1] + p[2] > 0.01).count();
        let (a, b) = (lit(&reference), lit(&raster));
        let min_share = if s.name == "many_lights" { 0.7 } else { 0.99 };
        if share < min_share || median >= 0.005 || a.abs_diff(b) > b / 50 + 4 {
            failures.push(format!(
                "{}: {:.2}% within 2%, median {median:.4}, {a} vs {b} lit pixels",
                s.name,
                share * 100.0
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
