//! Hot reload without a window (`lightbench::reload`, what `render --watch` drives): real
//! files on disk, edited the ways editors save them, while the executor keeps rendering.

use crate::gpu_common;

use gpu_common::*;
use lightbench::gpu::{Executor, Gpu};
use lightbench::reload::{Outcome, Reloader};
use lightbench::scene::{builtin, Scene};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A project written out by `init` into a fresh scratch folder.
fn project(tag: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("hot-reload-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    lightbench::bundled::init(&d).unwrap();
    d
}

struct Running {
    reloader: Reloader,
    ex: Executor,
}

fn start(g: &Gpu, dir: &Path) -> Running {
    let mut scene: Scene = builtin::cornell();
    scene.size = (32, 32);
    let (reloader, exe) = Reloader::new(g, (&dir.join("pipelines/deferred.ron"), None), (&scene, None), &[]).unwrap();
    let ex = Executor::new(g, &exe, &scene).unwrap();
    Running { reloader, ex }
}

impl Running {
    fn frame(&mut self, g: &Gpu) -> f32 {
        let inputs = self.ex.inputs(0.0);
        self.ex.render_frame(g, &inputs).unwrap();
        output(g, &self.ex).mean_rgb(0, 0, 32, 32)
    }

    /// Render and poll until an outcome satisfies `done` (at most 10 s); every outcome seen.
    fn until(&mut self, g: &Gpu, done: impl Fn(&Outcome) -> bool) -> Vec<Outcome> {
        let deadline = Instant::now() + Duration::from_secs(10);
        let mut seen = vec![];
        while Instant::now() < deadline {
            self.frame(g);
            if let Some(o) = self.reloader.poll(g, &mut self.ex, Duration::from_millis(20)) {
                let stop = done(&o);
                seen.push(o);
                if stop {
                    return seen;
                }
            }
        }
        panic!("no such outcome within 10 s; saw {seen:?}");
    }
}

impl Running {
    fn hdr_mean(&mut self, g: &Gpu) -> f32 {
        self.frame(g);
        self.ex.read_texture(g, "hdr", 0, 0).unwrap().mean_rgb(0, 0, 32, 32)
    }

    /// Render and poll until nothing has arrived for 200 ms (at most 10 s).
    fn settle(&mut self, g: &Gpu) {
        let deadline = Instant::now() + Duration::from_secs(10);
        let mut idle = 0;
        while idle < 10 && Instant::now() < deadline {
            self.frame(g);
            match self.reloader.poll(g, &mut self.ex, Duration::from_millis(20)) {
                Some(_) => idle = 0,
                None => idle += 1,
            }
        }
    }
}

fn reloaded(o: &Outcome) -> bool {
    matches!(o, Outcome::Reloaded { .. })
}

/// The tone map's result scaled by `k` (a one-constant edit with a visible effect).
fn tonemap_scaled(k: &str) -> String {
    let text = std::fs::read_to_string(root().join("shaders/tonemap.wgsl")).unwrap();
    let edited = text.replace("vec3<f32>(1.0)), 1.0);", &format!("vec3<f32>(1.0)) * {k}, 1.0);"));
    assert_ne!(edited, text);
    edited
}

#[test]
fn an_edit_reloads_a_broken_save_keeps_the_last_good_plan_and_a_fix_recovers() {
    let g = gpu();
    let dir = project("edit");
    let mut r = start(&g, &dir);
    let before = r.frame(&g);
    let tonemap = dir.join("shaders/tonemap.wgsl");
    std::fs::write(&tonemap, tonemap_scaled("0.5")).unwrap();
    r.until(&g, reloaded);
    let darker = r.frame(&g);
    assert!(darker < before * 0.7, "{before} -> {darker}");
    std::fs::write(&tonemap, "@fragment fn fs_main( {").unwrap();
    let seen = r.until(&g, |o| matches!(o, Outcome::Failed { .. }));
    let Some(Outcome::Failed { message, files }) = seen.last() else {
        unreachable!()
    };
    assert!(message.contains("error[") && message.contains("tonemap.wgsl"), "{message}");
    assert!(files.iter().any(|f| f.ends_with("shaders/tonemap.wgsl")), "{files:?}");
    assert!(r.reloader.last_error.is_some());
    assert_eq!(r.frame(&g), darker, "the last good Plan keeps rendering");
    std::fs::write(&tonemap, tonemap_scaled("0.25")).unwrap();
    r.until(&g, reloaded);
    assert!(r.reloader.last_error.is_none());
    assert!(r.frame(&g) < darker * 0.7);
}

#[test]
fn every_way_editors_save_is_seen_and_includes_count() {
    let g = gpu();
    let dir = project("saves");
    let mut r = start(&g, &dir);
    let before = r.frame(&g);
    let tonemap = dir.join("shaders/tonemap.wgsl");
    // Write a temporary file, then rename it over.
    let tmp = dir.join("shaders/.tonemap.wgsl.swp");
    std::fs::write(&tmp, tonemap_scaled("0.5")).unwrap();
    std::fs::rename(&tmp, &tonemap).unwrap();
    r.until(&g, reloaded);
    let half = r.frame(&g);
    assert!(half < before * 0.7, "rename over: {before} -> {half}");
    // Delete, then create.
    std::fs::remove_file(&tonemap).unwrap();
    std::thread::sleep(Duration::from_millis(5));
    std::fs::write(&tonemap, tonemap_scaled("0.25")).unwrap();
    r.until(&g, reloaded);
    let quarter = r.frame(&g);
    assert!(quarter < half * 0.7, "delete and create: {half} -> {quarter}");
    // A half-written file, completed a moment later: whatever is seen in between, the
    // complete content ends up rendering.
    let full = tonemap_scaled("0.125");
    std::fs::write(&tonemap, &full[..full.len() / 2]).unwrap();
    std::thread::sleep(Duration::from_millis(2));
    std::fs::write(&tonemap, &full).unwrap();
    r.until(&g, reloaded);
    r.settle(&g);
    assert!(r.reloader.last_error.is_none(), "{:?}", r.reloader.last_error);
    let eighth = r.frame(&g);
    assert!(eighth < quarter * 0.7, "half-written then complete: {quarter} -> {eighth}");
    // An included helper file: every light pass includes lib/lighting.wgsl.
    let lit = r.hdr_mean(&g);
    let lighting = dir.join("shaders/lib/lighting.wgsl");
    let text = std::fs::read_to_string(&lighting).unwrap();
    std::fs::write(
        &lighting,
        text.replace("return (diffuse / 3.14159265 + spec_color * spec) * ndl;", "return vec3<f32>(0.0);"),
    )
    .unwrap();
    let seen = r.until(&g, reloaded);
    let Some(Outcome::Reloaded { files, .. }) = seen.last() else {
        unreachable!()
    };
    assert!(files.iter().any(|f| f.ends_with("lib/lighting.wgsl")), "{files:?}");
    // (Exposure adapts the output: the linear HDR image shows it.)
    let dark = r.hdr_mean(&g);
    assert!(dark < lit * 0.5, "no direct light any more: {lit} -> {dark}");
}

/// 200 rapid edits from a second thread, valid and invalid, the last one valid: no crash, and
/// the last content is what renders.
#[test]
fn a_hostile_burst_of_edits_ends_with_the_last_valid_content() {
    let g = gpu();
    let dir = project("hostile");
    let mut r = start(&g, &dir);
    let tonemap = dir.join("shaders/tonemap.wgsl");
    let contents: Vec<String> = (0..200)
        .map(|i| match i % 5 {
            0 => "fn broken(".to_string(),
            1 => String::new(),
            2 => tonemap_scaled("0.9")[..40].to_string(),
            _ => tonemap_scaled(&format!("{:.3}", 0.3 + (i % 7) as f32 * 0.1)),
        })
        .chain([tonemap_scaled("0.125")])
        .collect();
    let path = tonemap.clone();
    let writer = std::thread::spawn(move || {
        let mut seed = 12345u32;
        for c in contents {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            // Now in place, now through a rename, now with a pause.
            if seed.is_multiple_of(3) {
                let tmp = path.with_extension("tmp");
                std::fs::write(&tmp, &c).unwrap();
                std::fs::rename(&tmp, &path).unwrap();
            } else {
                std::fs::write(&path, &c).unwrap();
            }
            std::thread::sleep(Duration::from_micros((seed % 3000) as u64));
        }
    });
    while !writer.is_finished() {
        r.frame(&g);
        let _ = r.reloader.poll(&g, &mut r.ex, Duration::from_millis(1));
    }
    writer.join().unwrap();
    r.settle(&g);
    assert!(r.reloader.last_error.is_none(), "{:?}", r.reloader.last_error);
    let now = r.frame(&g);
    let fresh = start(&g, &dir).frame(&g);
    assert!((now - fresh).abs() < 1e-6, "running {now}, fresh {fresh}");
}

/// `start`, for the project's scene file `file` (watched with the pipeline).
fn start_scene(g: &Gpu, dir: &Path, file: &Path) -> Running {
    let mut scene = lightbench::scene::load(file.to_str().unwrap()).unwrap();
    scene.size = (32, 32);
    let (reloader, exe) = Reloader::new(g, (&dir.join("pipelines/deferred.ron"), None), (&scene, Some(file)), &[]).unwrap();
    let ex = Executor::new(g, &exe, &scene).unwrap();
    Running { reloader, ex }
}

/// The scene file is watched too: an edited light relights the running scene.
#[test]
fn an_edited_scene_file_reloads_the_scene() {
    let g = gpu();
    let dir = project("scene");
    let file = dir.join("scenes/sun_only.ron");
    let mut r = start_scene(&g, &dir, &file);
    let before = r.hdr_mean(&g);
    let text = std::fs::read_to_string(&file).unwrap();
    let brighter = text.replace("intensity: 3.0, shadows: true", "intensity: 9.0, shadows: true");
    assert_ne!(brighter, text);
    std::fs::write(&file, brighter).unwrap();
    r.until(&g, reloaded);
    let after = r.hdr_mean(&g);
    assert!(after > before * 1.5, "{before} -> {after}");
    // A broken scene file keeps the running scene.
    std::fs::write(&file, "Scene(name: ").unwrap();
    r.until(&g, |o| matches!(o, Outcome::Failed { .. }));
    assert_eq!(r.hdr_mean(&g), after);
}

/// A scene's models are watched too, and the files they refer to: a model edited in place
/// (here the ground's colour, darker) reloads the scene, keeping its unchanged meshes on the
/// GPU, and a model's external buffer is among the files watched.
#[test]
fn an_edited_model_reloads_the_scene() {
    let g = gpu();
    let dir = project("model");
    let file = dir.join("scenes/sun_only.ron");
    let watched = lightbench::scene::load::files_of(file.to_str().unwrap());
    let names: Vec<_> = watched.iter().filter_map(|f| f.file_name()?.to_str()).collect();
    assert_eq!(names, ["sun_only.ron", "ground.gltf", "chair.gltf"], "{watched:?}");
    let mut r = start_scene(&g, &dir, &file);
    let before = r.hdr_mean(&g);
    let ground = dir.join("scenes/ground.gltf");
    let mut doc: serde_json::Value = serde_json::from_slice(&std::fs::read(&ground).unwrap()).unwrap();
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = serde_json::json!([0.05, 0.05, 0.05, 1.0]);
    std::fs::write(&ground, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    let seen = r.until(&g, reloaded);
    assert_eq!(r.ex.scene_uploads(), 2, "the scene was loaded and uploaded again");
    // A material's colour changed, no geometry: every mesh's buffers stayed resident.
    let Some(Outcome::Reloaded { report, .. }) = seen.last() else {
        panic!()
    };
    let kept = report.scene_kept.expect("a scene reload says what it kept");
    assert!(kept.meshes.1 >= 2 && kept.meshes.0 == kept.meshes.1, "{kept:?}");
    let after = r.hdr_mean(&g);
    assert!(after < before * 0.9, "{before} -> {after}");

    // A model whose buffer is a file of its own: that file is watched too.
    use base64::Engine;
    let uri = doc["buffers"][0]["uri"].as_str().unwrap().to_string();
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(uri.split_once(',').unwrap().1)
        .unwrap();
    std::fs::write(dir.join("scenes/ground.bin"), bytes).unwrap();
    doc["buffers"][0]["uri"] = serde_json::json!("ground.bin");
    std::fs::write(&ground, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    let watched = lightbench::scene::load::files_of(file.to_str().unwrap());
    assert!(watched.iter().any(|f| f.ends_with("scenes/ground.bin")), "{watched:?}");
}

/// A pipeline that uses another reloads when the used file is edited: `deferred_gi.ron` uses
/// `deferred.ron`, whose ambient light is made ten times brighter.
#[test]
fn an_edit_of_a_used_pipeline_reloads_the_pipeline_that_uses_it() {
    let g = gpu();
    let dir = project("used");
    let mut scene: Scene = builtin::cornell();
    scene.size = (32, 32);
    let gi = dir.join("pipelines/deferred_gi.ron");
    let (reloader, exe) = Reloader::new(&g, (&gi, None), (&scene, None), &[]).unwrap();
    let ex = Executor::new(&g, &exe, &scene).unwrap();
    let mut r = Running { reloader, ex };
    let before = r.hdr_mean(&g);
    let used = dir.join("pipelines/deferred.ron");
    let text = std::fs::read_to_string(&used).unwrap();
    let brighter = text.replace("Color(default: (0.03, 0.03, 0.035)", "Color(default: (0.3, 0.3, 0.35)");
    assert_ne!(brighter, text);
    std::fs::write(&used, brighter).unwrap();
    r.until(&g, reloaded);
    let after = r.hdr_mean(&g);
    assert!(after > before * 1.5, "{before} -> {after}");
}

/// A copy of folder `from` at `to` (files and folders, recursively).
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &to.join(e.file_name()));
        } else {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

/// A watched folder replaced as `git checkout` and editors do (moved away and made again,
/// deleted and made again): it is watched anew, said so, and its files reload — and edits
/// in the new folder keep reloading.
#[test]
fn a_replaced_folder_is_watched_again() {
    let g = gpu();
    let dir = project("replaced");
    let mut r = start(&g, &dir);
    let before = r.frame(&g);
    let (shaders, old) = (dir.join("shaders"), dir.join("shaders.old"));
    // Moved away, and a copy with an edit made in its place.
    std::fs::rename(&shaders, &old).unwrap();
    copy_dir(&old, &shaders);
    std::fs::write(shaders.join("tonemap.wgsl"), tonemap_scaled("0.5")).unwrap();
    let seen = r.until(&g, |o| matches!(o, Outcome::Rewatched { .. }));
    let Some(Outcome::Rewatched { folders }) = seen.last() else {
        unreachable!()
    };
    assert!(folders.iter().any(|f| f.ends_with("shaders")), "{folders:?}");
    r.until(&g, reloaded);
    r.settle(&g);
    assert!(r.reloader.last_error.is_none(), "{:?}", r.reloader.last_error);
    let half = r.frame(&g);
    assert!(half < before * 0.7, "moved away and made again: {before} -> {half}");
    // An edit in the new folder is seen.
    std::fs::write(shaders.join("tonemap.wgsl"), tonemap_scaled("0.25")).unwrap();
    r.until(&g, reloaded);
    let quarter = r.frame(&g);
    assert!(quarter < half * 0.7, "an edit in the new folder: {half} -> {quarter}");
    // Deleted, and made again a moment later from the original files.
    std::fs::remove_dir_all(&shaders).unwrap();
    r.frame(&g);
    let _ = r.reloader.poll(&g, &mut r.ex, Duration::from_millis(20));
    copy_dir(&old, &shaders);
    r.until(&g, |o| matches!(o, Outcome::Rewatched { .. }));
    r.until(&g, reloaded);
    r.settle(&g);
    assert!(r.reloader.last_error.is_none(), "{:?}", r.reloader.last_error);
    assert_eq!(r.frame(&g), before, "deleted and made again from the original files");
    std::fs::write(shaders.join("tonemap.wgsl"), tonemap_scaled("0.5")).unwrap();
    r.until(&g, reloaded);
    assert!(r.frame(&g) < before * 0.7, "an edit after the folder came back");
}
