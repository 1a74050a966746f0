//! Structure: no module cycles — sibling modules (at any depth) of every crate must
//! depend on each other in one direction only, so that each stage can be read, tested and
//! replaced on its own (`check` must not use `plan`, front ends must not use checks...).
//! Dependencies are the `crate::` and `super::` paths each file names.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Module = Vec<String>;

/// Every module of a crate, by path (`lib.rs` is the root `[]`, `a/mod.rs` and `a.rs` are `[a]`).
fn modules(src: &Path) -> BTreeMap<Module, PathBuf> {
    let mut out = BTreeMap::new();
    let mut dirs = vec![src.to_path_buf()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
                continue;
            }
            if p.extension().and_then(|e| e.to_str()) != Some("rs") {
                continue;
            }
            let rel = p.strip_prefix(src).unwrap().with_extension("");
            let mut m: Module = rel.iter().map(|c| c.to_string_lossy().into_owned()).collect();
            if matches!(m.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                m.pop();
            }
            out.insert(m, p);
        }
    }
    out
}

/// Paths named in a file, resolved to absolute module paths (`super::` against `module`;
/// `crate::{a, b::c}` expanded one level).
fn references(text: &str, module: &Module) -> Vec<Module> {
    let code: String = text
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n");
    let mut out = vec![];
    // `super::` from module `a::b` is `a`, whether the file is `a/b.rs` or `a/b/mod.rs`.
    let parent = module[..module.len().saturating_sub(1)].to_vec();
    for (prefix, base) in [("crate::", vec![]), ("super::", parent)] {
        let mut rest = code.as_str();
        while let Some(i) = rest.find(prefix) {
            let before = rest[..i].chars().last();
            rest = &rest[i + prefix.len()..];
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            for path in expand(rest) {
                let mut full = base.clone();
                full.extend(path);
                out.push(full);
            }
        }
    }
    out
}

/// `a::b::c` or `{a::x, b}` at the start of `s`, as segment lists.
fn expand(s: &str) -> Vec<Module> {
    let ident = |s: &str| s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect::<String>();
    if let Some(inner) = s.strip_prefix('{') {
        let end = inner.find('}').unwrap_or(inner.len());
        return inner[..end]
            .split(',')
            .map(|part| part.trim().split("::").map(ident).take_while(|x| !x.is_empty()).collect())
            .collect();
    }
    let mut segs = vec![];
    let mut rest = s;
    loop {
        let id = ident(rest);
        if id.is_empty() {
            break;
        }
        rest = &rest[id.len()..];
        segs.push(id);
        match rest.strip_prefix("::") {
            Some(r) if !r.starts_with('{') => rest = r,
            Some(r) => {
                let mut group = expand(r);
                for g in &mut group {
                    let mut full = segs.clone();
                    full.append(g);
                    *g = full;
                }
                return group;
            }
            None => break,
        }
    }
    vec![segs]
}

/// Edges between sibling modules: `a::b` using `a::c::x` depends on `a::c`.
fn edges(src: &Path) -> BTreeMap<Module, BTreeSet<Module>> {
    let mods = modules(src);
    let mut out: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for (m, file) in &mods {
        let text = std::fs::read_to_string(file).unwrap();
        for r in references(&text, m) {
            let Some(i) = m.iter().zip(&r).position(|(a, b)| a != b) else {
                continue; // an ancestor or a descendant
            };
            let (from, to) = (m[..=i].to_vec(), r[..=i].to_vec());
            if mods.contains_key(&to) {
                out.entry(from).or_default().insert(to);
            }
        }
    }
    out
}

fn find_cycle(g: &BTreeMap<Module, BTreeSet<Module>>) -> Option<Vec<Module>> {
    fn visit(
        n: &Module,
        g: &BTreeMap<Module, BTreeSet<Module>>,
        stack: &mut Vec<Module>,
        done: &mut BTreeSet<Module>,
    ) -> Option<Vec<Module>> {
        if let Some(i) = stack.iter().position(|s| s == n) {
            let mut c = stack[i..].to_vec();
            c.push(n.clone());
            return Some(c);
        }
        if done.contains(n) {
            return None;
        }
        stack.push(n.clone());
        for next in g.get(n).into_iter().flatten() {
            if let Some(c) = visit(next, g, stack, done) {
                return Some(c);
            }
        }
        stack.pop();
        done.insert(n.clone());
        None
    }
    let mut done = BTreeSet::new();
    g.keys().find_map(|n| visit(n, g, &mut vec![], &mut done))
}

fn assert_acyclic(src: &Path) {
    let g = edges(src);
    assert!(!g.is_empty(), "no module dependencies found under {}", src.display());
    if let Some(c) = find_cycle(&g) {
        let names: Vec<String> = c.iter().map(|m| m.join("::")).collect();
        panic!("module cycle under {}: {}", src.display(), names.join(" -> "));
    }
}

#[test]
fn compiler_modules_form_no_cycle() {
    assert_acyclic(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"));
}

#[test]
fn runtime_modules_form_no_cycle() {
    for krate in ["scene", "executor", "reference", "runtime"] {
        assert_acyclic(&Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(krate).join("src"));
    }
}

#[test]
fn a_cycle_is_found() {
    // The detector itself: `check` using `plan` and `plan` using `check` is a cycle.
    let g: BTreeMap<Module, BTreeSet<Module>> = [
        (vec!["check".to_string()], [vec!["plan".to_string()]].into_iter().collect()),
        (vec!["plan".to_string()], [vec!["check".to_string()]].into_iter().collect()),
    ]
    .into_iter()
    .collect();
    assert!(find_cycle(&g).is_some());
    assert_eq!(
        expand("diag::{Code, Diagnostic}"),
        vec![
            vec!["diag".to_string(), "Code".to_string()],
            vec!["diag".to_string(), "Diagnostic".to_string()]
        ]
    );
    assert_eq!(
        references("use super::pool::Pool;", &vec!["gpu".into(), "executor".into()]),
        vec![vec!["gpu".to_string(), "pool".to_string(), "Pool".to_string()]]
    );
}

/// The normal (non-dev) dependencies of a workspace crate with its default features, as
/// `cargo tree` lists them.
fn dependency_names(krate: &str) -> BTreeSet<String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = std::process::Command::new(cargo)
        .args(["tree", "--offline", "-e", "normal", "--prefix", "none", "-p", krate])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "cargo tree -p {krate}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    text.lines()
        .filter_map(|l| l.split_whitespace().next())
        .map(str::to_string)
        .collect()
}

/// Crates by layer (README "Crates"): a host renderer embedding the executor, or a tool using
/// the reference, gets neither the application's command line, window, plots and editor
/// support, nor (for the executor) the path tracer and file watching unless it asks.
#[test]
fn library_crates_leave_out_the_applications_dependencies() {
    let app = [
        "clap",
        "winit",
        "egui",
        "egui-wgpu",
        "plotters",
        "nv-flip",
        "lsp-server",
        "indicatif",
    ];
    let executor = dependency_names("lightbench-executor");
    assert!(executor.contains("wgpu"), "{executor:?}");
    for name in app.iter().chain(&["obvhs", "notify", "lightbench-reference"]) {
        assert!(!executor.contains(*name), "lightbench-executor depends on {name}");
    }
    let reference = dependency_names("lightbench-reference");
    assert!(reference.contains("obvhs"), "{reference:?}");
    for name in app.iter().filter(|n| **n != "indicatif").chain(&["wgpu", "notify"]) {
        assert!(!reference.contains(*name), "lightbench-reference depends on {name}");
    }
    let scene = dependency_names("lightbench-scene");
    for name in ["wgpu", "obvhs", "clap", "winit", "egui"] {
        assert!(!scene.contains(name), "lightbench-scene depends on {name}");
    }
}

/// The library crates' documentation builds without a warning (broken links, bad HTML), as
/// `RUSTDOCFLAGS="-D warnings" cargo doc --no-deps` for each; in a target folder of its own, so
/// that it does not wait on the build running the tests.
#[test]
fn library_crates_document_without_warnings() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut cmd = std::process::Command::new(cargo);
    cmd.args(["doc", "--offline", "--no-deps", "--target-dir", "target/doc-check"]);
    for krate in [
        "lightbench-compiler",
        "lightbench-scene",
        "lightbench-executor",
        "lightbench-reference",
    ] {
        cmd.args(["-p", krate]);
    }
    let out = cmd.env("RUSTDOCFLAGS", "-D warnings").current_dir(root).output().unwrap();
    assert!(out.status.success(), "cargo doc: {}", String::from_utf8_lossy(&out.stderr));
}

/// Every bench of every crate is declared `test = true`, so that `cargo test` runs its smoke
/// run (a bench is run without `--bench` there) and a stale bench fails the tests, not a
/// reader.
#[test]
fn every_bench_runs_in_the_tests() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut missing = vec![];
    for krate in ["compiler", "scene", "reference", "executor", "runtime"] {
        let Ok(dir) = std::fs::read_dir(root.join(krate).join("benches")) else {
            continue;
        };
        let manifest = std::fs::read_to_string(root.join(krate).join("Cargo.toml")).unwrap();
        // Each `[[bench]]` table up to the next table.
        let tables: Vec<&str> = manifest
            .split("[[bench]]")
            .skip(1)
            .map(|t| t.split("\n[").next().unwrap_or(t))
            .collect();
        for e in dir {
            let p = e.unwrap().path();
            if p.extension().and_then(|e| e.to_str()) != Some("rs") {
                continue;
            }
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            let declared = tables
                .iter()
                .find(|t| t.lines().any(|l| l.replace(' ', "") == format!("name=\"{name}\"")));
            if !declared.is_some_and(|t| t.lines().any(|l| l.replace(' ', "") == "test=true")) {
                missing.push(format!("{krate}/benches/{name}.rs"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "benches without `test = true` in their crate's [[bench]] table: {missing:?}"
    );
}

/// `scripts/bench-figures.sh` as docs/benchmarks.md tells a reader to run it, in its test mode
/// (each bench's smoke run): every bench named has its output under its name, after the machine,
/// the day and the load, the file's other sections kept; a bench that does not exist is a usage
/// error that leaves the file as it was.
/// In a target folder of its own, so that it does not wait on the build running the tests.
#[test]
fn the_bench_figures_script_writes_each_bench_under_its_name() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let dir = std::env::temp_dir().join(format!("lightbench-bench-figures-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("figures.md");
    let run = |benches: &[&str]| {
        std::process::Command::new("bash")
            .arg(root.join("scripts/bench-figures.sh"))
            .args(benches)
            .env("LB_BENCH_MODE", "test")
            .env("LB_BENCH_OUT", &out)
            .env("CARGO_TARGET_DIR", root.join("target/bench-figures-check"))
            .output()
            .unwrap()
    };
    let done = run(&["memory"]);
    assert!(done.status.success(), "{}", String::from_utf8_lossy(&done.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("# Benchmark figures\n"), "{text}");
    let section = text.split("## memory\n").nth(1).expect("the memory bench's section");
    assert!(section.contains("Machine: ") && section.contains(" cores, "), "{section}");
    assert!(section.contains("load average before: "), "{section}");
    assert!(section.contains("deferred_gi.lbp  1920×1080, every effect: logical"), "{section}");
    // Another bench named: its section added, the memory section kept as it was.
    let more = run(&["tonemap"]);
    assert!(more.status.success(), "{}", String::from_utf8_lossy(&more.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains(&format!("## memory\n{section}")), "{text}");
    let tonemap = text.split("## tonemap\n").nth(1).expect("the tonemap bench's section");
    assert!(
        tonemap.contains("run on 20") && tonemap.contains("load average before: "),
        "{tonemap}"
    );
    let bad = run(&["no_such_bench"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("no bench 'no_such_bench'"));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text, "left as it was");
    // A mode that is neither `bench` nor `test`: a usage error too, the file left.
    let bad_mode = std::process::Command::new("bash")
        .arg(root.join("scripts/bench-figures.sh"))
        .arg("memory")
        .env("LB_BENCH_MODE", "run")
        .env("LB_BENCH_OUT", &out)
        .output()
        .unwrap();
    assert_eq!(bad_mode.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad_mode.stderr).contains("LB_BENCH_MODE must be bench or test, not 'run'"));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), text, "left as it was");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Errors by crate: each library crate defines its own error type (`src/error.rs`, re-exported
/// from its root) and re-exports no other crate's as its own; none of them says how a program
/// exits or what a usage error is — that mapping is the application's alone
/// (`runtime/src/error.rs`, `Error::exit_code`).
#[test]
fn each_library_crate_has_its_own_error_type_and_no_cli_wording() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for krate in ["scene", "executor", "reference"] {
        let src = root.join(krate).join("src");
        let error = std::fs::read_to_string(src.join("error.rs")).unwrap();
        assert!(error.contains("pub enum Error {"), "{krate}: no error type of its own");
        let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
        assert!(
            lib.contains("pub use error::{Error, Result};"),
            "{krate}: its root does not export its error type"
        );
        for line in lib.lines().filter(|l| l.starts_with("pub use lightbench_")) {
            assert!(!line.contains("Error"), "{krate} re-exports another crate's error type: {line}");
        }
        for (m, file) in modules(&src) {
            let text = std::fs::read_to_string(&file).unwrap();
            for (i, line) in text.lines().enumerate() {
                let l = line.to_lowercase();
                let said = ["exit code", "usage error", "exit 1", "exit 2", "(exit "]
                    .iter()
                    .find(|w| l.contains(*w));
                // Messages and docs say the library's calls, not the command line's options.
                let (code, doc) = l.split_once("//").unwrap_or((&l, ""));
                let doc = if doc.starts_with('/') || doc.starts_with('!') { doc } else { "" };
                let option = |text: &str| {
                    text.match_indices("--")
                        .any(|(at, _)| text[at + 2..].starts_with(|c: char| c.is_ascii_lowercase()))
                };
                let in_message = code.contains('"') && option(code);
                assert!(
                    !in_message && !option(doc),
                    "{krate}::{}:{}: a command-line option is the application's to say: {line}",
                    m.join("::"),
                    i + 1
                );
                assert!(
                    said.is_none(),
                    "{krate}::{}:{}: `{}` is the application's to say: {line}",
                    m.join("::"),
                    i + 1,
                    said.unwrap()
                );
            }
        }
    }
    let app = std::fs::read_to_string(root.join("runtime/src/error.rs")).unwrap();
    assert!(
        app.contains("pub fn exit_code(&self) -> i32"),
        "the application maps errors to exit codes"
    );
}
