//! The bundled pipelines written with choices (`Match`), and `deferred_gi` built on `deferred`
//! (`use`), render what their copied passes rendered: the files as they were
//! (`compiler/tests/fixtures/before/`) against today's, on
//! the Cornell box at 64² lit by a spot and a point light, for 20 configurations.

use crate::cli_common;
use crate::gpu_common;

use gpu_common::*;
use lightbench::io::{rmse, Image};
use lightbench::scene::{builtin, Scene};
use std::path::PathBuf;

/// The old file beside the bundled data files it names.
fn before(file: &str) -> PathBuf {
    let d = cli_common::scratch(&format!("before-{file}"));
    std::fs::create_dir_all(d.join("pipelines")).unwrap();
    for f in std::fs::read_dir(root().join("pipelines")).unwrap().map(|e| e.unwrap().path()) {
        if f.extension().is_some_and(|e| e == "json") {
            std::fs::copy(&f, d.join("pipelines").join(f.file_name().unwrap())).unwrap();
        }
    }
    let to = d.join("pipelines").join(file);
    std::fs::copy(root().join("compiler/tests/fixtures/before").join(file), &to).unwrap();
    to
}

/// `scenes/cornell_spot.ron` with the built-in box's point light as well, every effect on.
fn scene() -> Scene {
    let mut s = lightbench::scene::load(root().join("scenes/cornell_spot.ron").to_str().unwrap()).unwrap();
    s.lights.extend(builtin::cornell().lights);
    s.effects.extend(builtin::cornell().effects);
    s.size = (64, 64);
    s
}

fn images(file: &str, old: bool, s: &Scene, variants: &[(&str, &str)]) -> (Image, Image) {
    let g = gpu();
    let path = if old { before(file) } else { root().join("pipelines").join(file) };
    let v: Vec<(String, String)> = variants.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    let shaders = root().join("shaders");
    let (exe, _) = lightbench::render::compile(&g, &path, Some(&shaders), s, &v).unwrap_or_else(|e| panic!("{e}"));
    let ex = lightbench::render::render(&g, &exe, s, 2).unwrap_or_else(|e| panic!("{e}"));
    (output(&g, &ex), ex.read_texture(&g, "hdr", 0, 0).unwrap())
}

fn same_images(file: &str, configs: &[&[(&str, &str)]]) {
    let s = scene();
    for variants in configs {
        let (old_out, old_hdr) = images(file, true, &s, variants);
        let (new_out, new_hdr) = images(file, false, &s, variants);
        let (out, hdr) = (rmse(&old_out, &new_out).unwrap(), rmse(&old_hdr, &new_hdr).unwrap());
        eprintln!("{file} {variants:?}: output RMSE {out:e}, hdr RMSE {hdr:e}");
        assert!(out <= 1e-6 && hdr <= 1e-6, "{file} {variants:?}: output {out}, hdr {hdr}");
        assert!(new_hdr.rgba.iter().all(|v| v.is_finite()) && new_hdr.rgba.iter().any(|v| *v > 0.0));
    }
}

#[test]
fn deferred_renders_as_its_copied_passes_did() {
    same_images(
        "deferred.ron",
        &[
            &[],
            &[("gbuffer", "fat")],
            &[("cube_shadow", "instanced")],
            &[("cube_shadow", "multiview")],
            &[("cube_shadow", "dual_paraboloid"), ("gbuffer", "fat")],
            &[("lighting", "deferred_volumes")],
            &[("lighting", "deferred_volumes"), ("gbuffer", "fat"), ("cube_shadow", "instanced")],
            &[("lighting", "deferred_volumes"), ("cube_shadow", "dual_paraboloid")],
            &[("lighting", "forward_multi"), ("cube_shadow", "instanced")],
            &[("lighting", "forward_multi"), ("cube_shadow", "dual_paraboloid")],
            &[("aa", "fxaa")],
            &[("aa", "taa"), ("gbuffer", "fat")],
        ],
    );
}

#[test]
fn deferred_gi_renders_as_its_copied_passes_did() {
    same_images(
        "deferred_gi.ron",
        &[
            &[],
            &[("indirect_diffuse", "fixed")],
            &[("indirect_diffuse", "temporal")],
            &[("indirect_diffuse", "off")],
            &[("cube_shadow", "instanced")],
            &[("cube_shadow", "instanced"), ("indirect_diffuse", "temporal")],
            &[("aa", "fxaa")],
            &[("aa", "taa"), ("indirect_diffuse", "fixed")],
        ],
    );
}
