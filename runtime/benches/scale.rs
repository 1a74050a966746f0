//! `cargo bench -p lightbench --bench scale`: what a scene's size costs. Generated glTF
//! grids from 10 k to 16 M triangles in one mesh, then 1 M triangles in 1 to 1,000 meshes (one
//! grid instanced by that many nodes: each node is a mesh of the scene), each written to disk
//! with a scene file; then `lightbench plan --scene`, `render` (deferred.lbp, 64²) and
//! `reference` (16², 1 spp of `direct`) run on it as child processes, and their wall time,
//! CPU time and peak resident memory (the child's own, from wait4) are printed per triangle
//! beyond a two-triangle scene's, with the growth exponent fitted over the sizes from 640 k
//! (log-log least squares: 1.0 is linear). `render` splits its time into the scene's load and
//! the rest; `reference` into its BVH build with tracing (what it reports) and the rest (loading).
//! On the largest one-mesh grid, calling for every effect under a sun and a point light,
//! `verify` runs the bundled pipelines (every option once) and its configurations are printed.
//! Goals: render ≤ 150 B and reference ≤ 300 B per triangle, exponents ≤ 1.05, plan flat (its
//! memory does not grow with triangles), verify without problems. Linux only (wait4, /proc). Needs an adapter (lavapipe
//! is enough); `cargo test` runs it at its smallest (`Size::Smoke`).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

#[path = "common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::Size;

impl Size {
    /// (triangles, meshes) per point; the first is the baseline.
    fn points(self) -> Vec<(u64, u32)> {
        let one = [10_000, 40_000, 160_000, 640_000, 2_560_000, 10_240_000, 16_000_000];
        let many = [10, 100, 1000];
        match self {
            Size::Full => [(2, 1)]
                .into_iter()
                .chain(one.map(|t| (t, 1)))
                .chain(many.map(|m| (1_000_000, m)))
                .collect(),
            Size::Smoke => vec![(2, 1), (10_000, 1), (40_000, 4)],
        }
    }
}

/// What one child process took: wall and CPU seconds, peak resident bytes, its output.
struct Child {
    wall: f64,
    cpu: f64,
    peak: u64,
    out: String,
}

/// Run `lightbench ARGS` in the repository root and wait for it with wait4 (its own rusage).
// The child is reaped by wait4, not std's wait, which would keep its rusage from us.
#[allow(clippy::zombie_processes)]
fn lightbench(args: &[&str], dir: &Path) -> Child {
    let (out_path, err_path) = (dir.join("stdout.txt"), dir.join("stderr.txt"));
    let file = |p: &Path| Stdio::from(std::fs::File::create(p).expect("output file"));
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("repository root");
    let t = Instant::now();
    let child = Command::new(env!("CARGO_BIN_EXE_lightbench"))
        .args(args)
        .current_dir(root)
        .stdout(file(&out_path))
        .stderr(file(&err_path))
        .spawn()
        .expect("run lightbench");
    let mut status = 0;
    // SAFETY: rusage is plain data that wait4 fills; the pid is our unwaited child's.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    let wall = t.elapsed().as_secs_f64();
    let out = std::fs::read_to_string(&out_path).unwrap_or_default() + &std::fs::read_to_string(&err_path).unwrap_or_default();
    assert!(
        pid > 0 && libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "lightbench {args:?} failed: {out}"
    );
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    Child {
        wall,
        cpu: secs(usage.ru_utime) + secs(usage.ru_stime),
        peak: usage.ru_maxrss as u64 * 1024,
        out,
    }
}

/// A flat grid of `triangles` (rounded to a square of quads) as one mesh, instanced by
/// `meshes` nodes side by side, written as `dir/grid.gltf` + `grid.bin`, and a scene file
/// that frames it under a sun. The scene file's path and the triangle count.
fn write_scene(dir: &Path, triangles: u64, meshes: u32) -> (PathBuf, u64) {
    let per_mesh = (triangles / meshes as u64).max(2);
    let g = ((per_mesh as f64 / 2.0).sqrt().round() as u32).max(1);
    let n = g + 1;
    // Streamed to the file: this process stays small, and a child inherits its peak resident
    // set until exec (Linux counts it in the child's ru_maxrss).
    let mut bin = std::io::BufWriter::new(std::fs::File::create(dir.join("grid.bin")).expect("write buffer"));
    let mut put = |words: &[[u8; 4]]| words.iter().for_each(|w| bin.write_all(w).expect("write buffer"));
    for j in 0..n {
        for i in 0..n {
            put(&[i as f32 / g as f32, 0.0, j as f32 / g as f32].map(f32::to_le_bytes));
        }
    }
    for _ in 0..n * n {
        put(&[0.0f32, 1.0, 0.0].map(f32::to_le_bytes));
    }
    for j in 0..g {
        for i in 0..g {
            let a = j * n + i;
            put(&[a, a + n, a + 1, a + 1, a + n, a + n + 1].map(u32::to_le_bytes));
        }
    }
    bin.flush().expect("write buffer");
    drop(bin);
    let (normals_at, indices_at) = (n as u64 * n as u64 * 12, n as u64 * n as u64 * 24);
    let bin_len = indices_at + g as u64 * g as u64 * 24;
    let side = (meshes as f64).sqrt().ceil() as u32;
    let nodes: Vec<_> = (0..meshes)
        .map(|m| serde_json::json!({"mesh": 0, "translation": [(m % side) as f32 * 1.1, 0.0, (m / side) as f32 * 1.1]}))
        .collect();
    let (verts, count) = (n * n, g * g * 6);
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": (0..meshes).collect::<Vec<_>>()}], "nodes": nodes,
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": verts, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 0.0, 1.0]},
            {"bufferView": 1, "componentType": 5126, "count": verts, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": count, "type": "SCALAR"}
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": normals_at},
            {"buffer": 0, "byteOffset": normals_at, "byteLength": indices_at - normals_at},
            {"buffer": 0, "byteOffset": indices_at, "byteLength": bin_len - indices_at}
        ],
        "buffers": [{"byteLength": bin_len, "uri": "grid.bin"}]
    });
    std::fs::write(dir.join("grid.gltf"), serde_json::to_vec(&doc).expect("json")).expect("write model");
    let scene = dir.join("scene.ron");
    let text = "Scene(\n    size: (64, 64),\n    models: [(path: \"grid.gltf\")],\n    lights: [Directional(direction: (0.3, -1.0, 0.2), intensity: 2.0)],\n)\n";
    std::fs::write(&scene, text).expect("write scene");
    // The same grid calling for every effect, under a point light too: what `verify` runs.
    let every = text.replace(
        "    lights: [",
        "    effects: [Shadows, AmbientOcclusion, MultiViewAo, Ssr, IndirectDiffuse, IndirectSpecular, Bloom],\n    \
         lights: [Point(position: (0.5, 0.5, 0.5), intensity: 4.0, range: 3.0), ",
    );
    std::fs::write(dir.join("every_effect.ron"), every).expect("write scene");
    (scene, g as u64 * g as u64 * 2 * meshes as u64)
}

/// The three commands' figures at one size.
struct Figures {
    triangles: u64,
    meshes: u32,
    plan: Child,
    render: Child,
    /// The scene's load, in seconds, as `render --timings` prints it.
    render_load: f64,
    reference: Child,
    /// The reference's BVH build and tracing, in seconds, as it prints them.
    reference_trace: f64,
    /// `verify` of the bundled pipelines on the grid calling for every effect, where run.
    verify: Option<Child>,
}

/// `verify` of the bundled pipelines (every option once; at `Size::Smoke` deferred.lbp's
/// shadow and cube-shadow options) on `dir`'s grid calling for every effect: every pass that
/// reads the scene's per-triangle tables (ray-traced options, AO volumes, paraboloid shadows).
fn verify(dir: &Path, size: Size) -> Child {
    let scene = dir.join("every_effect.ron");
    let mut args = vec!["verify"];
    args.extend(match size {
        Size::Full => ["pipelines/deferred.lbp", "pipelines/deferred_gi.lbp"].as_slice(),
        Size::Smoke => ["pipelines/deferred.lbp", "--vary", "shadows,cube_shadow"].as_slice(),
    });
    let scene = scene.to_str().expect("utf-8 path");
    args.extend(["--scenes", scene, "--frames", "1", "--size", "64x64", "--format", "json"]);
    lightbench(&args, dir)
}

fn measure(dir: &Path, (triangles, meshes): (u64, u32), verify_at: Option<Size>) -> Figures {
    let (scene, triangles) = write_scene(dir, triangles, meshes);
    let scene = scene.to_str().expect("utf-8 path");
    let image = dir.join("frame.png");
    let refs = dir.join("refs");
    let _ = std::fs::remove_dir_all(&refs);
    let plan = lightbench(&["plan", "pipelines/deferred.lbp", "--scene", scene], dir);
    let render = lightbench(
        &[
            "render",
            "--pipeline",
            "pipelines/deferred.lbp",
            "--scene",
            scene,
            "--out",
            image.to_str().expect("utf-8"),
            "--timings",
        ],
        dir,
    );
    let render_load = number_after(&render.out, "scene load ") / 1e3;
    let reference = lightbench(
        &[
            "reference",
            "--scene",
            scene,
            "--size",
            "16x16",
            "--spp",
            "1",
            "--terms",
            "direct",
            "--quiet",
            "--out",
            refs.to_str().expect("utf-8"),
        ],
        dir,
    );
    let reference_trace = number_before(&reference.out, " s\n");
    let verify = verify_at.map(|size| verify(dir, size));
    Figures {
        triangles,
        meshes,
        plan,
        render,
        render_load,
        reference,
        reference_trace,
        verify,
    }
}

/// The number that follows `tag` in `text` (0 if none).
fn number_after(text: &str, tag: &str) -> f64 {
    let Some(at) = text.find(tag) else { return 0.0 };
    let rest = &text[at + tag.len()..];
    let end = rest.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(rest.len());
    rest[..end].parse().unwrap_or(0.0)
}

/// The number that ends just before `tag` in `text` (0 if none).
fn number_before(text: &str, tag: &str) -> f64 {
    let Some(at) = text.find(tag) else { return 0.0 };
    let head = &text[..at];
    let start = head.rfind(|c: char| !(c.is_ascii_digit() || c == '.')).map_or(0, |i| i + 1);
    head[start..].parse().unwrap_or(0.0)
}

/// The slope of log y against log x: the growth exponent (points with y ≤ 0 left out).
fn exponent(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().filter(|p| p.1 > 0.0).map(|&(x, y)| (x.ln(), y.ln())).collect();
    let n = logs.len() as f64;
    let (mx, my) = (logs.iter().map(|p| p.0).sum::<f64>() / n, logs.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    sxy / sxx
}

fn run(size: Size) {
    let dir = std::env::temp_dir().join(format!("lightbench-bench-scale-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let points = size.points();
    let largest = points.iter().rposition(|p| p.1 == 1);
    let figures: Vec<Figures> = (points.iter().enumerate())
        .map(|(i, &p)| measure(&dir, p, (Some(i) == largest).then_some(size)))
        .collect();
    let _ = std::fs::remove_dir_all(&dir);
    let base = &figures[0];
    let mib = |b: u64| b as f64 / (1 << 20) as f64;
    println!(
        "scale: generated flat grids (half a vertex per triangle); per triangle beyond the {}-triangle scene's figures",
        base.triangles
    );
    println!(
        "{:>10} {:>6} | {:>9} {:>9} | {:>9} {:>8} {:>8} {:>7} {:>8} | {:>9} {:>8} {:>8} {:>7} {:>8}",
        "triangles",
        "meshes",
        "plan MiB",
        "plan s",
        "render MiB",
        "B/tri",
        "load s",
        "rest s",
        "CPU µs/t",
        "ref MiB",
        "B/tri",
        "load s",
        "BVH s",
        "CPU µs/t"
    );
    let per = |x: f64, b: f64, t: u64| (x - b) / (t - base.triangles).max(1) as f64;
    for f in &figures {
        println!(
            "{:>10} {:>6} | {:>9.1} {:>9.3} | {:>10.1} {:>8.0} {:>8.3} {:>7.3} {:>8.3} | {:>9.1} {:>8.0} {:>8.3} {:>7.3} {:>8.3}",
            f.triangles,
            f.meshes,
            mib(f.plan.peak),
            f.plan.wall,
            mib(f.render.peak),
            per(f.render.peak as f64, base.render.peak as f64, f.triangles),
            f.render_load,
            f.render.wall - f.render_load,
            per(f.render.cpu, base.render.cpu, f.triangles) * 1e6,
            mib(f.reference.peak),
            per(f.reference.peak as f64, base.reference.peak as f64, f.triangles),
            f.reference.wall - f.reference_trace,
            f.reference_trace,
            per(f.reference.cpu, base.reference.cpu, f.triangles) * 1e6,
        );
    }
    let single: Vec<&Figures> = figures.iter().filter(|f| f.meshes == 1 && f.triangles >= 640_000).collect();
    if single.len() >= 2 {
        let fit = |y: &dyn Fn(&Figures) -> f64| exponent(&single.iter().map(|f| (f.triangles as f64, y(f))).collect::<Vec<_>>());
        let largest = single.last().expect("a point");
        println!(
            "growth exponents from 640 k (1.0: linear; goal ≤ 1.05): render memory {:.3}, time {:.3}; reference memory {:.3}, time {:.3}",
            fit(&|f| f.render.peak as f64 - base.render.peak as f64),
            fit(&|f| f.render.cpu - base.render.cpu),
            fit(&|f| f.reference.peak as f64 - base.reference.peak as f64),
            fit(&|f| f.reference.cpu - base.reference.cpu),
        );
        let plan = figures.iter().map(|f| mib(f.plan.peak));
        println!(
            "at {} triangles: render {:.0} B per triangle (goal ≤ 150), reference {:.0} (goal ≤ 300); plan's peak {:.1}–{:.1} MiB at every size (goal: flat)",
            largest.triangles,
            per(largest.render.peak as f64, base.render.peak as f64, largest.triangles),
            per(largest.reference.peak as f64, base.reference.peak as f64, largest.triangles),
            plan.clone().fold(f64::INFINITY, f64::min),
            plan.fold(0.0, f64::max),
        );
    }
    print_verify(&figures);
}

/// What `verify` found on the largest grid: its configurations, those with problems (it exits
/// 0 only with none, or the bench stops with its output), its time and peak memory.
fn print_verify(figures: &[Figures]) {
    for f in figures {
        let Some(v) = &f.verify else { continue };
        println!(
            "verify at {} triangles, every effect, a sun and a point light: {} configurations, {} with problems; {:.1} s, peak {:.0} MiB",
            f.triangles,
            number_after(&v.out, "\"configurations\":"),
            number_after(&v.out, "\"problems\":"),
            v.wall,
            v.peak as f64 / (1 << 20) as f64
        );
    }
}

fn main() {
    run(Size::from_args());
}
