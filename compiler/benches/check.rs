//! `cargo bench -p lightbench-compiler`: time `check` over every bundled pipeline against
//! naga alone parsing and validating the same shader files, in one run, and print the ratio
//! (goal: <= 1.10×). Not a test: figures depend on the machine.

use lightbench_compiler::profile::Profile;
use lightbench_compiler::shader::include::{self, DiskFs};
use lightbench_compiler::span::SourceMap;
use lightbench_compiler::{pipeline_files, shader_root_for, Session};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

/// Every shader file the bundled pipelines reference.
fn shader_files(files: &[PathBuf]) -> Vec<String> {
    let mut names = std::collections::BTreeSet::new();
    for f in files {
        let text = std::fs::read_to_string(f).unwrap();
        for cap in text.split('"').skip(1).step_by(2) {
            if cap.ends_with(".wgsl") || cap.ends_with(".frag") || cap.ends_with(".vert") || cap.ends_with(".comp") {
                names.insert(cap.to_string());
            }
        }
    }
    names.into_iter().collect()
}

/// Read each file from disk, splice in its includes (naga has no include mechanism, so the
/// baseline gets the same text and the same file reads as `check`), parse and validate.
fn naga_alone(root: &Path, shaders: &[String]) {
    let fs = DiskFs { root };
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
        let caps = naga::valid::Capabilities::default() | naga::valid::Capabilities::MULTIVIEW | naga::valid::Capabilities::CLIP_DISTANCES;
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), caps)
            .validate(&module)
            .unwrap();
    }
}

fn check_all(files: &[PathBuf], profile: &Profile) {
    for f in files {
        let mut s = Session::new();
        s.check_file(f, None, profile, None);
        assert!(!s.diags.has_errors(), "{}", s.render());
    }
}

fn main() {
    // `cargo bench` passes `--bench`; other arguments (filters) are ignored.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf();
    let files = pipeline_files(&root.join("pipelines")).unwrap();
    let shader_root = shader_root_for(&files[0], None);
    let sources = shader_files(&files);
    let profile = Profile::vulkan();
    let rounds = 40;
    for _ in 0..5 {
        naga_alone(&shader_root, &sources);
        check_all(&files, &profile);
    }
    let (mut a, mut b) = (vec![], vec![]);
    // Interleave so that machine noise hits both sides alike.
    for _ in 0..rounds {
        let t = Instant::now();
        naga_alone(&shader_root, &sources);
        a.push(t.elapsed());
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
            let _ = lightbench_compiler::front::ron::value::parse(0, &text);
            t_parse.push(t.elapsed());
        }
        println!("ron parse only {:?}", median(t_parse));
    }
    let (na, ch) = (median(a), median(b));
    println!("pipelines: {}, shader files: {}, rounds: {rounds}", files.len(), sources.len());
    println!("naga parse+validate alone: {:>9.3} ms (median)", na.as_secs_f64() * 1e3);
    println!("lightbench check:          {:>9.3} ms (median)", ch.as_secs_f64() * 1e3);
    println!(
        "ratio check / naga:        {:>9.3}x (goal <= 1.10x)",
        ch.as_secs_f64() / na.as_secs_f64()
    );
}
