//! `lightbench diff` as the README tells a user to run it: the structure of two cube-shadow
//! options, a one-constant shader edit found where it acts, the CI gate's exit codes, the
//! structure without any driver, and a self-contained HTML report.

use crate::cli_common;

use cli_common::{lightbench, root, scratch};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `lightbench diff ARGS --format json --out DIR`: (exit code, report, stderr).
fn diff_json(args: &[&str], out: &Path) -> (i32, Value, String) {
    let mut all: Vec<&str> = vec!["diff"];
    all.extend(args);
    let out_s = out.to_str().unwrap();
    all.extend(["--format", "json", "--out", out_s, "--size", "64x64", "--frames", "3"]);
    let (code, stdout, stderr) = lightbench(&all);
    let report = serde_json::from_str(&stdout).unwrap_or(Value::Null);
    (code, report, stderr)
}

fn names(v: &Value) -> Vec<String> {
    let mut n: Vec<String> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap().to_string())
        .collect();
    n.sort();
    n
}

/// The report's entry for a resource's first slice.
fn image<'a>(r: &'a Value, resource: &str) -> &'a Value {
    r["images"]
        .as_array()
        .unwrap()
        .iter()
        .find(|i| i["resource"] == resource)
        .unwrap_or_else(|| panic!("no image of {resource}"))
}

#[test]
fn cube_shadow_options_differ_in_exactly_the_swapped_passes() {
    let out = scratch("classic-instanced");
    let (code, r, err) = diff_json(
        &[
            "pipelines/deferred.ron@cube_shadow=classic",
            "pipelines/deferred.ron@cube_shadow=instanced",
        ],
        &out,
    );
    assert_eq!(code, 0, "{err}");
    let s = &r["structure"];
    assert_eq!(names(&s["passes_removed"]), ["shadow_cube_classic"]);
    assert_eq!(names(&s["passes_added"]), ["shadow_cube_atlas"]);
    // The point-light pass chooses its shader and shadow map by `cube_shadow`: one pass, changed.
    assert_eq!(names(&s["passes_changed"]), ["light_point"], "{}", s["passes_changed"]);
    assert_eq!(names(&s["resources"]), ["shadow.atlas", "shadow.cube"]);
    assert_eq!(names(&s["variants"]), ["cube_shadow"]);
    // 512² × 6 layers against 1536 × 1024, 4 bytes a texel: the same bytes.
    let cube = 512u64 * 512 * 6 * 4;
    let atlas = 1536u64 * 1024 * 4;
    let (ma, mb) = (s["memory"][0].as_u64().unwrap(), s["memory"][1].as_u64().unwrap());
    assert_eq!(ma as i64 - mb as i64, cube as i64 - atlas as i64);
    // The same image (bounds: the multiview/instanced agreement of the GPU tests).
    let ldr = image(&r, "ldr");
    assert_eq!(r["images"][0]["resource"], "ldr", "the output comes first");
    assert!(ldr["metrics"]["flip_mean"].as_f64().unwrap() < 0.01, "{ldr}");
    assert!(ldr["metrics"]["rmse"].as_f64().unwrap() < 0.02, "{ldr}");
    // Time: both sides' passes, the swapped ones on their side only.
    let passes = r["timing"]["passes"].as_array().unwrap();
    let row = |p: &str| passes.iter().find(|t| t["pass"] == p).unwrap_or_else(|| panic!("no row {p}"));
    assert!(row("gbuffer")["a_gpu_ms"]["median"].as_f64().unwrap() > 0.0);
    assert!(row("gbuffer")["ratio"].as_f64().is_some());
    assert!(row("shadow_cube_classic")["b_gpu_ms"].is_null() && row("shadow_cube_atlas")["a_gpu_ms"].is_null());
    assert!(out.join("ldr.side.png").is_file() && out.join("ldr.heat.png").is_file());
    assert!(out.join("report.json").is_file());
}

/// The repository's pipelines and shaders copied to `dir`, with `edit` applied to one shader.
fn project_with(dir: &Path, shader: &str, edit: impl Fn(&str) -> String) -> PathBuf {
    fn copy(from: &Path, to: &Path) {
        std::fs::create_dir_all(to).unwrap();
        for e in std::fs::read_dir(from).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                copy(&p, &to.join(p.file_name().unwrap()));
            } else {
                std::fs::copy(&p, to.join(p.file_name().unwrap())).unwrap();
            }
        }
    }
    copy(&root().join("pipelines"), &dir.join("pipelines"));
    copy(&root().join("shaders"), &dir.join("shaders"));
    let path = dir.join("shaders").join(shader);
    let text = std::fs::read_to_string(&path).unwrap();
    let edited = edit(&text);
    assert_ne!(edited, text, "the edit changed nothing");
    std::fs::write(&path, edited).unwrap();
    dir.join("pipelines/deferred.ron")
}

/// Pixels where the point light's cube shadow darkens the Cornell box (64×64): where a render
/// whose cube-shadow lookup always answers "lit" is brighter.
fn shadowed_pixels(dir: &Path) -> Vec<bool> {
    let unshadowed = project_with(&dir.join("unshadowed"), "lib/shadow.wgsl", |t| {
        t.replace(
            "        return textureSampleCompareLevel(map, cmp, dir, depth);",
            "        return 1.0;",
        )
    });
    let (lit, shadowed) = (dir.join("lit.exr"), dir.join("shadowed.exr"));
    for (p, f) in [(unshadowed.to_str().unwrap(), &lit), ("pipelines/deferred.ron", &shadowed)] {
        let (code, _, err) = lightbench(&["render", "--pipeline", p, "--size", "64x64", "--out", f.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
    }
    let read = |p: &Path| image::open(p).unwrap().to_rgba32f().into_raw();
    let (l, s) = (read(&lit), read(&shadowed));
    l.chunks(4)
        .zip(s.chunks(4))
        .map(|(a, b)| a[0] + a[1] + a[2] > (b[0] + b[1] + b[2]) * 1.05 + 1e-4)
        .collect()
}

/// Shadows at least half lit: one constant of the cube-shadow lookup changed (its floor, 0
/// → 0.5). The diff finds the output and `hdr` different exactly where shadows fall.
#[test]
fn a_one_constant_edit_is_found_where_it_acts_and_gates_ci() {
    let dir = scratch("edited");
    let edited = project_with(&dir.join("b"), "lib/shadow.wgsl", |t| {
        t.replace(
            "        return textureSampleCompareLevel(map, cmp, dir, depth);",
            "        return max(textureSampleCompareLevel(map, cmp, dir, depth), 0.5);",
        )
    });
    let out = dir.join("report");
    let (a, b) = ("pipelines/deferred.ron", edited.to_str().unwrap());
    let (code, r, err) = diff_json(&[a, b, "--fail-above", "flip=0.001"], &out);
    assert_eq!(code, 1, "the gate must trip: {err}");
    assert!(err.contains("a --fail-above limit was crossed"), "{err}");
    assert!(r["structure"]["passes_changed"].as_array().unwrap().is_empty(), "same structure");
    for res in ["ldr", "hdr"] {
        assert!(image(&r, res)["metrics"]["max_abs"].as_f64().unwrap() > 1e-3, "{res} must differ");
    }
    assert_eq!(
        image(&r, "gbuf.albedo")["metrics"]["max_abs"].as_f64(),
        Some(0.0),
        "the G-buffer is untouched"
    );
    // The heat-map of `hdr` is hot inside the shadows and cold outside them.
    let heat = image::open(out.join(image(&r, "hdr")["heat_map"].as_str().unwrap()))
        .unwrap()
        .to_rgb8();
    let shadowed = shadowed_pixels(&dir);
    let (mut hot_in, mut hot_out, mut inside) = (0, 0, 0);
    for (px, s) in heat.pixels().zip(&shadowed) {
        let hot = px.0.iter().map(|&c| c as u32).sum::<u32>() > 3 * 40;
        inside += *s as u32;
        match (hot, s) {
            (true, true) => hot_in += 1,
            (true, false) => hot_out += 1,
            _ => {}
        }
    }
    eprintln!("{inside} shadowed pixels; hot inside {hot_in}, hot outside {hot_out}");
    assert!(inside > 50 && hot_in as f32 > 0.8 * inside as f32, "hot where shadows fall");
    assert!(hot_out as f32 <= 0.05 * hot_in as f32, "cold elsewhere");
    // Region by region, B/A: blocks holding shadow brighter, none darker.
    let blocks = &image(&r, "hdr")["metrics"]["blocks"];
    let at = |k: &str| blocks[k].as_f64().unwrap();
    assert!(at("max") > 1.05 && at("min") > 0.999, "{blocks}");
    // The identical pair passes the gate.
    let (code, r, err) = diff_json(&[a, a, "--fail-above", "flip=0.001,rmse=0"], &dir.join("same"));
    assert_eq!(code, 0, "{err}");
    assert_eq!(r["thresholds"][0]["crossed"], false);
    assert_eq!(image(&r, "ldr")["metrics"]["flip_mean"].as_f64(), Some(0.0));
    let same = &image(&r, "hdr")["metrics"]["blocks"];
    assert_eq!((same["p10"].as_f64(), same["p90"].as_f64()), (Some(1.0), Some(1.0)), "{same}");
}

#[test]
fn structure_needs_no_driver() {
    let hidden = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_lightbench"))
            .args(args)
            .current_dir(root())
            // Every Vulkan ICD and EGL vendor (GL) hidden.
            .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
            .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
            .env("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent/egl.json")
            .env("LIBGL_DRIVERS_PATH", "/nonexistent")
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let out = scratch("no-driver");
    let (a, b) = (
        "pipelines/deferred.ron@cube_shadow=classic",
        "pipelines/deferred.ron@cube_shadow=instanced",
    );
    let (code, _, err) = hidden(&["diff", a, b, "--out", out.to_str().unwrap()]);
    assert_eq!(code, Some(1), "rendering must fail without a driver: {err}");
    assert!(err.contains("no GPU adapter"), "{err}");
    let (code, text, err) = hidden(&["diff", a, b, "--no-render", "--out", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    assert!(text.contains("## Structure") && text.contains("| shadow_cube_atlas |"), "{text}");
    assert!(!text.contains("## Pixels") && !text.contains("## Time"), "{text}");
    // What needs rendering cannot be asked for without it.
    let (code, _, err) = hidden(&["diff", a, b, "--no-render", "--fail-above", "flip=0.01"]);
    assert_eq!(code, Some(2), "{err}");
    let (code, _, err) = hidden(&[
        "diff",
        a,
        b,
        "--no-render",
        "--fail-above",
        "memory=1.0",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(0), "the same memory: {err}");
}

#[test]
fn the_html_report_embeds_every_image() {
    let out = scratch("html");
    let (code, _, err) = lightbench(&[
        "diff",
        "pipelines/deferred.ron",
        "pipelines/deferred.ron@exposure.ev=1,exposure.automatic=false",
        "--format",
        "html",
        "--size",
        "32x32",
        "--frames",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    assert!(html.contains("exposure.ev"), "the parameter change is reported");
    // Markdown becomes HTML, not literal marks: bold, code, escaped pipes.
    assert!(html.contains("<strong>A</strong>") && html.contains("<code>"), "{html}");
    let text: String = html.split("<img ").map(|p| p.split_once('>').map_or(p, |(_, rest)| rest)).collect();
    for raw in ["**", "\\|", "`"] {
        assert!(!text.contains(raw), "raw markdown `{raw}` in the HTML report");
    }
    let mut images = 0;
    for part in html.split("<img ").skip(1) {
        let src = part
            .split("src=\"")
            .nth(1)
            .and_then(|s| s.split('"').next())
            .expect("an img with src");
        let data = src
            .strip_prefix("data:image/png;base64,")
            .unwrap_or_else(|| panic!("not embedded: {src}"));
        use base64::Engine;
        let png = base64::engine::general_purpose::STANDARD.decode(data).expect("base64");
        assert!(png.starts_with(b"\x89PNG"), "a PNG");
        image::load_from_memory(&png).expect("a readable PNG");
        images += 1;
    }
    assert!(images >= 5, "{images} images");
    assert!(!html.contains("src=\"") || html.matches("src=\"data:").count() == html.matches("src=\"").count());
}

#[test]
fn bad_arguments_are_usage_errors() {
    for args in [
        vec!["diff", "pipelines/deferred.ron@cube_shadow", "pipelines/deferred.ron"],
        vec![
            "diff",
            "pipelines/deferred.ron",
            "pipelines/deferred.ron",
            "--fail-above",
            "fipl=0.1",
        ],
        vec!["diff", "pipelines/deferred.ron", "pipelines/deferred.ron", "--fail-above", "flip=x"],
        vec!["diff", "missing.ron", "pipelines/deferred.ron", "--no-render"],
        vec!["diff", "pipelines/deferred.ron", "pipelines/deferred.ron@no.such=1", "--no-render"],
    ] {
        let (code, _, err) = lightbench(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{err}");
    }
}

/// Two pipelines whose outputs have different names still have their outputs compared.
#[test]
fn outputs_are_compared_whatever_their_names() {
    let dir = scratch("renamed");
    let renamed = project_with(&dir.join("b"), "tonemap.wgsl", |t| format!("{t}\n"));
    let text = std::fs::read_to_string(&renamed).unwrap().replace("\"ldr\"", "\"final\"");
    std::fs::write(&renamed, text).unwrap();
    let (code, r, err) = diff_json(&["pipelines/deferred.ron", renamed.to_str().unwrap()], &dir.join("report"));
    assert_eq!(code, 0, "{err}");
    let out = &r["images"][0];
    assert_eq!(out["resource"], "ldr / final");
    assert_eq!(out["metrics"]["flip_mean"].as_f64(), Some(0.0));
    assert_eq!(names(&r["structure"]["resources"]), ["final", "ldr"]);
}

/// A side that does not compile: its diagnostics, located in the file, and exit 1.
#[test]
fn a_broken_side_reports_its_diagnostics() {
    let dir = scratch("broken");
    let broken = project_with(&dir.join("b"), "tonemap.wgsl", |t| t.replace("fn fs_main(", "fn fs_main(("));
    let (code, _, err) = lightbench(&["diff", "pipelines/deferred.ron", broken.to_str().unwrap(), "--no-render"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("error[") && err.contains("tonemap.wgsl:"), "{err}");
}

/// The README's first `diff` command, typed as written, in a project `init` wrote.
#[test]
fn the_readme_command_runs_as_typed() {
    let dir = scratch("readme");
    let (code, _, err) = cli_common::lightbench_in(&dir, &["init", "."]);
    assert_eq!(code, 0, "{err}");
    let (code, out, err) = cli_common::lightbench_in(
        &dir,
        &[
            "diff",
            "pipelines/deferred.ron@cube_shadow=classic",
            "pipelines/deferred.ron@cube_shadow=instanced",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(
        out.starts_with("# lightbench diff") && out.contains("| shadow_cube_atlas |") && out.contains("## Time"),
        "{out}"
    );
    assert!(dir.join("lightbench-diff/report.md").is_file() && dir.join("lightbench-diff/ldr.side.png").is_file());
}

/// The README's side syntax beyond options: a vector's numbers continue its key, a per-pass
/// value is set as `PASS.KEY`, and a path containing `@` ends with `@`.
#[test]
fn sides_set_vectors_pass_values_and_paths_with_at() {
    let dir = scratch("side-syntax");
    let b = "pipelines/deferred.ron@ambient.color=0.1,0.1,0.12,bloom_up.strength=0.5";
    let out = dir.join("report");
    let (code, text, err) = lightbench(&[
        "diff",
        "pipelines/deferred.ron",
        b,
        "--effect",
        "Bloom",
        "--no-render",
        "--format",
        "json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let r: Value = serde_json::from_str(&text).unwrap();
    let params = &r["structure"]["params"];
    let find = |name: &str| params.as_array().unwrap().iter().find(|p| p["name"] == name).cloned();
    assert_eq!(find("ambient.color").unwrap()["b"], "(0.1, 0.1, 0.12)", "{params}");
    assert_eq!(find("bloom_up.strength").unwrap()["b"], "0.5", "{params}");
    // A project in a folder whose name has `@`.
    let at = project_with(&dir.join("my@work"), "tonemap.wgsl", |t| format!("{t}\n"));
    let at = at.to_str().unwrap();
    let (code, _, err) = lightbench(&[
        "diff",
        "pipelines/deferred.ron",
        &format!("{at}@"),
        "--no-render",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = lightbench(&["diff", "pipelines/deferred.ron", at, "--no-render"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&format!("a path that contains `@` ends with `@`: `{at}@`")), "{err}");
}

/// A mip chain is compared level by level (and `render --dump` writes every level as
/// `NAME.mipK`): a lower bloom threshold on B shows in each level of `bloom`.
#[test]
fn mip_chains_are_dumped_and_compared_per_level() {
    let dir = scratch("mips");
    let b = "pipelines/deferred.ron@bloom.threshold=0.05";
    let (code, r, err) = diff_json(
        &["pipelines/deferred.ron", b, "--effect", "Bloom", "--resources", "bloom"],
        &dir.join("report"),
    );
    assert_eq!(code, 0, "{err}");
    let levels: Vec<&Value> = r["images"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|i| i["resource"] == "bloom")
        .collect();
    let mips: Vec<u64> = levels.iter().map(|i| i["mip"].as_u64().unwrap()).collect();
    assert_eq!(mips, [0, 1, 2, 3, 4], "{r}");
    for (k, level) in levels.iter().enumerate() {
        assert_eq!(level["size"][0].as_u64(), Some(32 >> k), "{level}");
        assert!(level["metrics"]["rmse"].as_f64().unwrap() > 0.0, "mip {k}: {level}");
        let side = level["side_by_side"].as_str().unwrap();
        assert_eq!(
            side,
            if k == 0 {
                "bloom.side.png".to_string()
            } else {
                format!("bloom.mip{k}.side.png")
            }
        );
        assert!(dir.join("report").join(side).is_file());
    }
    let dump = dir.join("dump");
    let (code, _, err) = lightbench(&[
        "render",
        "--effect",
        "Bloom",
        "--size",
        "64x64",
        "--out",
        dir.join("x.png").to_str().unwrap(),
        "--dump",
        "bloom",
        "--dump-dir",
        dump.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    for k in 0..5u32 {
        let name = if k == 0 {
            "bloom.exr".to_string()
        } else {
            format!("bloom.mip{k}.exr")
        };
        let img = image::open(dump.join(&name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(img.width(), 32 >> k, "{name}");
    }
}
