//! Hostile input: files that are not files, too large or not UTF-8; includes that leave
//! the shader root; nesting deep enough to overflow a recursive parser; resource sizes and
//! dispatches a device would refuse. Each is one located error (or a clear unlocated one
//! for the file itself), never a panic, hang or read outside the project.

mod common;

use common::*;
use lightbench_compiler::profile::Profile;

const COMPUTE: &str = "@group(0) @binding(0) var<storage, read_write> data: array<u32>;\n\n@compute @workgroup_size(8, 8, 1)\nfn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {\n    data[id.x] = id.y;\n}\n";

const FILL: &str = "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0);\n}\n";

/// A project whose passes are a fill of `out` and `pass` (RON), with `resources` declared
/// (`out` too, unless they declare it); shaders: fill.wgsl, fill_data.wgsl plus `extra`.
fn project(resources: &str, pass: &str, extra: &[(&str, &str)]) -> std::path::PathBuf {
    let out = if resources.contains("\"out\":") {
        ""
    } else {
        "        \"out\": Texture(format: Rgba8Unorm),\n"
    };
    let pipeline = format!(
        "Pipeline(\n    name: \"h\",\n    resources: {{\n{out}{resources}    }},\n    passes: [\n        Fullscreen(name: \"f\", shader: \"fill.wgsl\", color: [\"out\"]),\n{pass}    ],\n    output: \"out\",\n)\n"
    );
    let mut files = vec![
        ("pipelines/p.ron", pipeline.as_str()),
        ("shaders/fill.wgsl", FILL),
        ("shaders/fill_data.wgsl", COMPUTE),
    ];
    files.extend_from_slice(extra);
    write_project("hostile", &files)
}

fn check(dir: &std::path::Path) -> Outcome {
    check_project(dir, "pipelines/p.ron", &Profile::offline("vulkan").unwrap(), None)
}

/// Asserts one error with `code` whose message contains `msg`, at `line:col` of `file`
/// (relative to the project) when given.
fn expect(out: &Outcome, code: &str, msg: &str, at: Option<(&str, usize, usize)>) {
    let found = out.located();
    let hit = found
        .iter()
        .any(|(c, m, f, l, co)| c == code && m.contains(msg) && at.is_none_or(|(af, al, ac)| f == af && *l == al && *co == ac));
    assert!(hit, "expected [{code}] {msg:?} at {at:?}; got {found:#?}");
}

#[test]
fn includes_stay_inside_the_shader_root() {
    for (include, msg) in [
        ("/etc/passwd", "`/etc/passwd` is absolute"),
        ("../pipelines/p.ron", "`../pipelines/p.ron` leaves the shader root"),
        ("lib/../../../../etc/passwd", "leaves the shader root"),
    ] {
        let shader = format!("#include \"{include}\"\n{FILL}");
        let dir = project("", "", &[("shaders/fill.wgsl", &shader)]);
        let out = check(&dir);
        expect(&out, "outside-root", msg, Some(("shaders/fill.wgsl", 1, 1)));
        assert!(!out.dump().contains("root:"), "nothing of /etc/passwd is shown: {}", out.dump());
    }
    // The same rule for a pass's own shader path.
    let dir = project(
        "",
        "        Fullscreen(name: \"g\", shader: \"/etc/passwd.wgsl\", color: [\"out\"]),\n",
        &[],
    );
    expect(
        &check(&dir),
        "outside-root",
        "`/etc/passwd.wgsl` is absolute",
        Some(("pipelines/p.ron", 8, 39)),
    );
}

#[cfg(unix)]
#[test]
fn only_regular_files_are_read() {
    let dir = project("", "", &[]);
    let shader = format!("#include \"lib/zero.wgsl\"\n{FILL}");
    std::fs::write(dir.join("shaders/fill.wgsl"), shader).unwrap();
    std::fs::create_dir_all(dir.join("shaders/lib")).unwrap();
    // A device (reads forever) and a FIFO (blocks forever) behind innocent names.
    std::os::unix::fs::symlink("/dev/zero", dir.join("shaders/lib/zero.wgsl")).unwrap();
    let out = check(&dir);
    expect(
        &out,
        "not-a-file",
        "cannot read included file `lib/zero.wgsl`: not a regular file",
        Some(("shaders/fill.wgsl", 1, 1)),
    );
    std::fs::remove_file(dir.join("shaders/lib/zero.wgsl")).unwrap();
    let made = std::process::Command::new("mkfifo")
        .arg(dir.join("shaders/lib/zero.wgsl"))
        .status()
        .unwrap();
    assert!(made.success());
    expect(&check(&dir), "not-a-file", "not a regular file", Some(("shaders/fill.wgsl", 1, 1)));
    // A directory where the pipeline should be.
    let mut s = lightbench_compiler::Session::new();
    assert!(s.load_pipeline(&dir.join("shaders")).is_none());
    assert_eq!(s.diags.list[0].code, "not-a-file");
}

#[test]
fn oversized_and_non_utf8_files_are_refused_with_the_reason() {
    let dir = project("", "", &[]);
    let big = std::fs::File::create(dir.join("shaders/fill.wgsl")).unwrap();
    big.set_len(lightbench_compiler::vfs::MAX_FILE_BYTES + 1).unwrap(); // sparse: costs no disk
    expect(
        &check(&dir),
        "file-too-large",
        "larger than the 16 MiB limit",
        Some(("pipelines/p.ron", 7, 39)),
    );
    let dir = project("", "", &[]);
    let mut bytes = std::fs::read(dir.join("pipelines/p.ron")).unwrap();
    bytes[11] = 0xFF; // inside `name: "h"`
    std::fs::write(dir.join("pipelines/p.ron"), bytes).unwrap();
    let out = check(&dir);
    // Located at the bad byte (line and column from the valid text before it), JSON too.
    expect(
        &out,
        "invalid-utf8",
        "not valid UTF-8 (invalid byte at offset 11, line 2, column 2)",
        Some(("pipelines/p.ron", 2, 2)),
    );
}

#[test]
fn includes_nest_at_most_32_deep() {
    let mut files: Vec<(String, String)> = (0..40)
        .map(|i| (format!("shaders/lib/n{i}.wgsl"), format!("#include \"lib/n{}.wgsl\"\n", i + 1)))
        .collect();
    files.push(("shaders/lib/n40.wgsl".into(), "\n".into()));
    let shader = format!("#include \"lib/n0.wgsl\"\n{FILL}");
    files.push(("shaders/fill.wgsl".into(), shader));
    let refs: Vec<(&str, &str)> = files.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
    let dir = project("", "", &refs);
    expect(
        &check(&dir),
        "nesting-too-deep",
        "includes nested more than 32 files deep",
        Some(("shaders/lib/n30.wgsl", 1, 1)),
    );
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    // 9,000 nested `not` aborted check, plan, convert and fmt with a stack overflow.
    let lbp = format!("pipeline p\ntexture out: Rgba8Unorm viewport\nfullscreen f \"fill.wgsl\" {{\n    color out\n    when {}reflective\n}}\noutput out\n", "not ".repeat(9000));
    let dir = write_project("nest", &[("pipelines/p.lbp", &lbp), ("shaders/fill.wgsl", FILL)]);
    let out = check_project(&dir, "pipelines/p.lbp", &Profile::offline("vulkan").unwrap(), None);
    expect(
        &out,
        "nesting-too-deep",
        "nested more than 64 levels deep",
        Some(("pipelines/p.lbp", 5, 262)),
    );
    let calls = format!("pipeline p\ntexture out: Rgba8Unorm viewport\nfullscreen f \"fill.wgsl\" {{\n    color out\n    when {}reflective{}\n}}\noutput out\n", "all(".repeat(5000), ")".repeat(5000));
    let dir = write_project("nest", &[("pipelines/p.lbp", &calls), ("shaders/fill.wgsl", FILL)]);
    let out = check_project(&dir, "pipelines/p.lbp", &Profile::offline("vulkan").unwrap(), None);
    expect(
        &out,
        "nesting-too-deep",
        "nested more than 64 levels deep",
        Some(("pipelines/p.lbp", 5, 265)),
    );
    let ron = format!(
        "Pipeline(name: \"p\", passes: [], output: {}1{})",
        "[".repeat(5000),
        "]".repeat(5000)
    );
    let dir = write_project("nest", &[("pipelines/p.ron", &ron)]);
    let out = check_project(&dir, "pipelines/p.ron", &Profile::offline("vulkan").unwrap(), None);
    expect(
        &out,
        "nesting-too-deep",
        "values nested more than 64 levels deep",
        Some(("pipelines/p.ron", 1, 104)),
    );
}

#[test]
fn dispatches_are_checked_against_the_profile() {
    let pass =
        |groups: &str| format!("        Compute(name: \"c\", shader: \"fill_data.wgsl\", writes: [\"data\"], dispatch: {groups}),\n");
    let data = "        \"data\": Buffer(size: 1024),\n";
    let dir = project(data, &pass("Groups(0, 1, 1)"), &[]);
    expect(
        &check(&dir),
        "value-out-of-range",
        "pass `c` dispatches Groups(0, 1, 1): every count must be at least 1",
        Some(("pipelines/p.ron", 9, 82)),
    );
    let dir = project(data, &pass("Groups(1, 70000, 1)"), &[]);
    expect(
        &check(&dir),
        "limit-exceeded",
        "pass `c` dispatches 70000 workgroups in one dimension: 70000 exceeds 65535",
        Some(("pipelines/p.ron", 9, 82)),
    );
}

#[test]
fn buffer_sizes_are_checked_against_the_profile() {
    let pass = "        Compute(name: \"c\", shader: \"fill_data.wgsl\", writes: [\"data\"], dispatch: Groups(1, 1, 1)),\n";
    let dir = project("        \"data\": Buffer(size: 300000000),\n", pass, &[]);
    expect(
        &check(&dir),
        "limit-exceeded",
        "buffer `data` has 300000000 bytes, over the 268435456-byte limit",
        Some(("pipelines/p.ron", 5, 30)),
    );
    let dir = project("        \"data\": Buffer(size: 200000000),\n", pass, &[]);
    expect(
        &check(&dir),
        "limit-exceeded",
        "buffer `data`, bound as storage by pass `c`, has 200000000 bytes: 200000000 exceeds 134217728",
        Some(("pipelines/p.ron", 5, 30)),
    );
}

#[test]
fn viewport_textures_are_checked_at_the_planned_size() {
    // 12 mips fit 2048 but not the 1280×720 `check` plans without a scene.
    let dir = project("        \"out\": Texture(format: Rgba8Unorm, mips: 12),\n", "", &[]);
    expect(
        &check(&dir),
        "mip-count",
        "`out` is 1280×720 at 1280×720, which allows at most 11 mip levels, not 12",
        Some(("pipelines/p.ron", 4, 50)),
    );
    let dir = project("        \"out\": Texture(format: Rgba8Unorm, size: Viewport(16.0)),\n", "", &[]);
    expect(
        &check(&dir),
        "texture-too-large",
        "`out` is 20480×11520 at 1280×720, over the 16384 texel limit",
        Some(("pipelines/p.ron", 4, 50)),
    );
}

/// Confinement after links: a symbolic link inside the shader root (or the pipeline's data
/// folder) to a file outside it is not read — `outside-root`, located where the path is
/// written, and nothing of the file shown — while a link that stays inside is followed.
#[cfg(unix)]
#[test]
fn links_out_of_the_roots_are_not_followed() {
    let dir = project("", "", &[]);
    let secret = dir.join("secret.wgsl");
    std::fs::write(&secret, format!("// SECRET-LINE\n{FILL}")).unwrap();
    std::fs::create_dir_all(dir.join("shaders/lib")).unwrap();
    std::os::unix::fs::symlink(&secret, dir.join("shaders/lib/evil.wgsl")).unwrap();
    std::os::unix::fs::symlink("../fill.wgsl", dir.join("shaders/lib/inside.wgsl")).unwrap();
    // An include through the link.
    std::fs::write(dir.join("shaders/fill.wgsl"), format!("#include \"lib/evil.wgsl\"\n{FILL}")).unwrap();
    let out = check(&dir);
    expect(&out, "outside-root", "through a symbolic link", Some(("shaders/fill.wgsl", 1, 1)));
    assert!(!out.dump().contains("SECRET-LINE"), "{}", out.dump());
    // A pass's own shader through the link.
    std::fs::write(dir.join("shaders/fill.wgsl"), FILL).unwrap();
    let pipeline = std::fs::read_to_string(dir.join("pipelines/p.ron")).unwrap();
    std::fs::write(dir.join("pipelines/p.ron"), pipeline.replace("\"fill.wgsl\"", "\"lib/evil.wgsl\"")).unwrap();
    let out = check(&dir);
    expect(&out, "outside-root", "through a symbolic link", Some(("pipelines/p.ron", 7, 39)));
    assert!(!out.dump().contains("SECRET-LINE"), "{}", out.dump());
    // A link that stays inside the root is followed.
    std::fs::write(
        dir.join("pipelines/p.ron"),
        pipeline.replace("\"fill.wgsl\"", "\"lib/inside.wgsl\""),
    )
    .unwrap();
    let out = check(&dir);
    assert!(out.located().is_empty(), "{:#?}", out.located());
}

/// The same for resource data: a link in the pipeline's folder to a file outside it.
#[cfg(unix)]
#[test]
fn data_links_out_of_the_pipeline_folder_are_not_followed() {
    let dir = project("        \"values\": Buffer(size: 8, data: File(\"values.json\")),\n", "", &[]);
    let secret = dir.join("secret.json");
    std::fs::write(&secret, "[1.0, 2.0]").unwrap();
    std::os::unix::fs::symlink(&secret, dir.join("pipelines/values.json")).unwrap();
    let out = check(&dir);
    expect(&out, "outside-root", "through a symbolic link", None);
    // The same file inside the folder is read (and fits).
    std::fs::remove_file(dir.join("pipelines/values.json")).unwrap();
    std::fs::copy(&secret, dir.join("pipelines/values.json")).unwrap();
    assert!(check(&dir).located().iter().all(|d| d.0 != "outside-root"));
}
