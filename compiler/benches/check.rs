//! `cargo bench -p lightbench-compiler --bench check`: time `check` over every bundled
//! pipeline against naga alone parsing and validating the same shader files, in interleaved
//! rounds, and print the per-round ratio's median and quartiles (goal: ≤ 1.0× naga over the
//! distinct files); then, where valgrind is installed, the same two by instructions
//! (callgrind: the bench run again in a child process, each side alone), a figure the host's
//! load does not move. `cargo test` runs it at its smallest (one round, no callgrind).

use lightbench_compiler::profile::Profile;
use lightbench_compiler::shader::include::{self, ShaderFs};
use lightbench_compiler::span::SourceMap;
use lightbench_compiler::vfs::DiskVfs;
use lightbench_compiler::{pipeline_files, shader_root_for, Session, Workspace};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

#[path = "../../runtime/benches/common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::{load_line, Paired, Size};

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

/// The shader files the given pipelines reference, once each (a pipeline that uses another
/// references that one's too).
fn shader_files(files: &[PathBuf]) -> Vec<String> {
    let mut names = std::collections::BTreeSet::new();
    let mut todo: Vec<PathBuf> = files.to_vec();
    while let Some(f) = todo.pop() {
        let text = std::fs::read_to_string(&f).unwrap();
        // Outside and inside quotes in turn: piece 2i + 1 is the i-th quoted string.
        let pieces: Vec<&str> = text.split('"').collect();
        let quoted: Vec<&str> = pieces.iter().skip(1).step_by(2).copied().collect();
        for (i, cap) in quoted.iter().enumerate() {
            if cap.ends_with(".wgsl") || cap.ends_with(".frag") || cap.ends_with(".vert") || cap.ends_with(".comp") {
                names.insert(cap.to_string());
            }
            // `use "x.lbp"` / `use: "x.ron"`: the string after the word `use`.
            let before = pieces[2 * i];
            let word = before
                .trim_end()
                .trim_end_matches(':')
                .rsplit(|c: char| !c.is_alphanumeric() && c != '_')
                .next();
            if word == Some("use") {
                todo.push(f.parent().unwrap().join(cap));
            }
        }
    }
    names.into_iter().collect()
}

/// Shader files under a root on disk, for the baseline.
struct Disk<'a>(&'a Path);

impl ShaderFs for Disk<'_> {
    fn read(&self, path: &str) -> std::io::Result<String> {
        std::fs::read_to_string(self.0.join(path))
    }
}

/// Read each file from disk, splice in its includes (naga has no include mechanism, so the
/// baseline gets the same text and the same file reads as `check`), parse and validate.
fn naga_alone(root: &Path, shaders: &[String]) {
    let fs = Disk(root);
    for name in shaders {
        let mut sm = SourceMap::new();
        let id = sm.add(name.clone(), std::fs::read_to_string(root.join(name)).unwrap());
        let src = include::expand(&fs, &mut sm, id, name).unwrap().text;
        let module = if name.ends_with(".frag") {
            naga::front::glsl::Frontend::default()
                .parse(&naga::front::glsl::Options::from(naga::ShaderStage::Fragment), &src)
                .unwrap()
        } else {
            naga::front::wgsl::parse_str(&src).unwrap()
        };
        // The capabilities `check` validates with for the profile (ray queries included).
        let caps = lightbench_compiler::shader::capabilities(&Profile::vulkan().features);
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), caps)
            .validate(&module)
            .unwrap();
    }
}

fn check_all(files: &[PathBuf], profile: &Profile) {
    // As `lightbench check` does: one workspace (compiled-shader cache) for the run.
    let ws = Workspace::disk();
    for s in ws.check_files(files, None, profile, None) {
        assert!(!s.diags.has_errors(), "{}", s.render());
    }
}

fn main() {
    // `cargo bench` passes `--bench`; other arguments (filters) are ignored.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf();
    let files = pipeline_files(&root.join("pipelines")).unwrap();
    let shader_root = shader_root_for(&DiskVfs, &files[0], None);
    // Two baselines: naga over each pipeline's shader files (what running naga pipeline by
    // pipeline costs), and naga over the distinct files of all pipelines (no file twice).
    let per_pipeline: Vec<Vec<String>> = files.iter().map(|f| shader_files(std::slice::from_ref(f))).collect();
    let distinct = shader_files(&files);
    let profile = Profile::vulkan();
    let size = Size::from_args();
    let rounds = size.pick(40, 1);
    // `LB_CHECK_ONLY=1`: only `check`, 100 times or `LB_CHECK_ROUNDS` (for a profiler).
    if std::env::var("LB_CHECK_ONLY").is_ok() {
        let n = std::env::var("LB_CHECK_ROUNDS").ok().and_then(|n| n.parse().ok()).unwrap_or(100);
        for _ in 0..n {
            check_all(&files, &profile);
        }
        return;
    }
    // `LB_NAGA_ONLY=1`: only the baseline over distinct files, as many rounds.
    if std::env::var("LB_NAGA_ONLY").is_ok() {
        let n = std::env::var("LB_CHECK_ROUNDS").ok().and_then(|n| n.parse().ok()).unwrap_or(100);
        for _ in 0..n {
            naga_alone(&shader_root, &distinct);
        }
        return;
    }
    let naga_per_pipeline = |root: &Path| per_pipeline.iter().for_each(|list| naga_alone(root, list));
    for _ in 0..size.pick(5, 1) {
        naga_per_pipeline(&shader_root);
        naga_alone(&shader_root, &distinct);
        check_all(&files, &profile);
    }
    let (mut a, mut d, mut b) = (vec![], vec![], vec![]);
    // Interleave so that machine noise hits every side alike.
    for _ in 0..rounds {
        let t = Instant::now();
        naga_per_pipeline(&shader_root);
        a.push(t.elapsed());
        let t = Instant::now();
        naga_alone(&shader_root, &distinct);
        d.push(t.elapsed());
        let t = Instant::now();
        check_all(&files, &profile);
        b.push(t.elapsed());
    }
    if std::env::var("LB_BREAKDOWN").is_ok() {
        let f = &files[0];
        let (mut t_load, mut t_check, mut t_cfg) = (vec![], vec![], vec![]);
        for _ in 0..rounds {
            let mut s = Session::new();
            let t = Instant::now();
            let p = s.load_pipeline(f).unwrap();
            t_load.push(t.elapsed());
            let t = Instant::now();
            let c = s.check(p, &shader_root, &profile);
            t_check.push(t.elapsed());
            let t = Instant::now();
            s.check_configurations(&c, &profile, None);
            t_cfg.push(t.elapsed());
        }
        println!("load {:?} check {:?} configs {:?}", median(t_load), median(t_check), median(t_cfg));
        let text = std::fs::read_to_string(f).unwrap();
        let mut t_parse = vec![];
        for _ in 0..rounds {
            let t = Instant::now();
            let _ = lightbench_compiler::front::ron::parse::parse(0, &text);
            t_parse.push(t.elapsed());
        }
        println!("ron parse only {:?}", median(t_parse));
    }
    // Each round's ratio: the host's load drifts between rounds (naga alone ran 50–83 ms
    // here from one run to the next), and the sides of one round share its load.
    let secs = |v: &[Duration]| v.iter().map(Duration::as_secs_f64).collect::<Vec<f64>>();
    let per_round = Paired { a: secs(&d), b: secs(&b) }.ratio();
    let per_pipeline_round = Paired { a: secs(&a), b: secs(&b) }.ratio();
    let (na, nd, ch) = (median(a), median(d), median(b));
    let ms = |t: Duration| t.as_secs_f64() * 1e3;
    println!(
        "pipelines: {}, shader files per pipeline: {:?}, distinct: {}, rounds: {rounds} ({})",
        files.len(),
        per_pipeline.iter().map(|l| l.len()).collect::<Vec<_>>(),
        distinct.len(),
        load_line()
    );
    println!("naga alone, each pipeline's shaders: {:>8.3} ms (median)", ms(na));
    println!("naga alone, distinct shaders:        {:>8.3} ms (median)", ms(nd));
    println!("lightbench check (shared cache):     {:>8.3} ms (median)", ms(ch));
    println!(
        "ratio check / naga per pipeline, per round:   {:.3}x (quartiles {:.3}-{:.3}; goal <= 1.10x)",
        per_pipeline_round.1, per_pipeline_round.0, per_pipeline_round.2
    );
    println!(
        "ratio check / naga distinct files, per round: {:.3}x (quartiles {:.3}-{:.3}; goal <= 1.00x)",
        per_round.1, per_round.0, per_round.2
    );
    if size == Size::Full {
        instructions();
    }
    growth(&root, size.pick(&[5_000, 10_000, 20_000, 40_000][..], &[500, 1_000][..]));
}

/// `check` of `deferred.lbp` with `n` more parameters declared, for each `n`: CPU seconds
/// and the growth exponent between the two largest (1: linear in the file's size).
fn growth(root: &Path, counts: &[usize]) {
    let text = std::fs::read_to_string(root.join("pipelines/deferred.lbp")).unwrap();
    let dir = std::env::temp_dir().join(format!("lightbench-bench-growth-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // The data files the pipeline names, beside it.
    for e in std::fs::read_dir(root.join("pipelines")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "json") {
            std::fs::copy(&p, dir.join(p.file_name().unwrap())).unwrap();
        }
    }
    let shaders = root.join("shaders");
    let mut points = vec![];
    for &n in counts {
        let filler: String = (0..n).map(|i| format!("param filler.p{i}: Float = 1 in 0..2 \"f\"\n")).collect();
        let file = dir.join(format!("deferred_{n}.lbp"));
        std::fs::write(
            &file,
            text.replacen("param ambient.color", &format!("{filler}param ambient.color"), 1),
        )
        .unwrap();
        let t = Instant::now();
        for s in Workspace::disk().check_files(std::slice::from_ref(&file), Some(&shaders), &Profile::vulkan(), None) {
            assert!(!s.diags.has_errors(), "{}", s.render());
        }
        points.push((n as f64, t.elapsed().as_secs_f64()));
    }
    let line: Vec<String> = points.iter().map(|(n, t)| format!("{n} {:.3} s", t)).collect();
    let [.., (n0, t0), (n1, t1)] = points[..] else { return };
    println!(
        "check of deferred.lbp with more parameters: {}; growth exponent {:.2} (1: linear)",
        line.join(", "),
        (t1 / t0).ln() / (n1 / n0).ln()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Instructions of `rounds` rounds of one side, counted by callgrind in a child process
/// running this bench in that side's mode (`LB_CHECK_ONLY` or `LB_NAGA_ONLY`); with `inside`,
/// only those executed within the functions it names.
fn counted(mode: &str, rounds: u32, inside: Option<&str>) -> Result<u64, String> {
    common::count_self(&[(mode, "1".into()), ("LB_CHECK_ROUNDS", rounds.to_string())], inside)
}

/// Instructions per round of each side: the count of 3 rounds less that of 1, halved, so
/// that the process's start (reading the pipeline list, the first allocations) cancels. Then
/// what dominates `check`'s: its shader compilation (naga's parse and validation, and the
/// cache around them) against the rest (pipelines parsed, lowered and checked, every
/// configuration planned).
fn instructions() {
    let per_round = |mode: &str, inside: Option<&str>| -> Result<f64, String> {
        Ok((counted(mode, 3, inside)? as f64 - counted(mode, 1, inside)? as f64) / 2.0)
    };
    let compile = Some("*lightbench_compiler::shader::compile*");
    match (
        per_round("LB_CHECK_ONLY", None),
        per_round("LB_NAGA_ONLY", None),
        per_round("LB_CHECK_ONLY", compile),
    ) {
        (Ok(check), Ok(naga), Ok(shaders)) => {
            println!(
                "instructions per round (callgrind): check {:.1} M, naga distinct files {:.1} M, ratio {:.3}x (goal <= 1.00x)",
                check / 1e6,
                naga / 1e6,
                check / naga
            );
            println!(
                "  of check's: shader compilation {:.1} M ({:.3}x naga alone), the rest {:.1} M ({:.0}%: pipelines parsed and checked, configurations planned)",
                shaders / 1e6,
                shaders / naga,
                (check - shaders) / 1e6,
                100.0 * (check - shaders) / check
            );
        }
        (Err(e), _, _) | (_, Err(e), _) | (_, _, Err(e)) => println!("instructions not counted: {e}"),
    }
}
