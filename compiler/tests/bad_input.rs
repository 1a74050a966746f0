//! The bad-input catalogue: each case breaks a small valid project in one way and asserts
//! the diagnostic code, message and exact file:line:col (1-based, columns in characters).

mod common;

use common::*;
use lightbench_compiler::profile::Profile;

const PIPELINE: &str = r#"Pipeline(
    name: "t",
    params: {
        "post.exposure": Float(default: 1.0, min: 0.0, max: 8.0),
    },
    samplers: {
        "linear": Sampler(filter: Linear),
    },
    resources: {
        "color": Texture(format: Rgba16Float),
        "depth": Texture(format: Depth32Float),
        "out": Texture(format: Rgba8Unorm),
    },
    passes: [
        Raster(name: "scene", shader: "scene.wgsl", color: ["color"], depth: "depth"),
        Fullscreen(name: "post", shader: "post.wgsl", reads: ["color"], color: ["out"], params: ["post.exposure"]),
    ],
    output: "out",
)
"#;

const SCENE_WGSL: &str = r#"struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
};

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> VsOut {
    var out: VsOut;
    out.clip = vec4<f32>(position, 1.0);
    out.normal = normal;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.normal * 0.5 + 0.5, 1.0);
}
"#;

const POST_WGSL: &str = r#"struct Params {
    exposure: f32,
};

@group(0) @binding(0) var color: texture_2d<f32>;
@group(0) @binding(1) var linear: sampler;
@group(0) @binding(2) var<uniform> params: Params;

@fragment
fn fs_main(@location(0) uv: vec2<f32>) -> @location(0) vec4<f32> {
    return textureSample(color, linear, uv) * params.exposure;
}
"#;

struct Case<'a> {
    /// (from, to) replacements in the pipeline file; each `from` must occur.
    pipeline: &'a [(&'a str, &'a str)],
    /// (from, to) replacements in post.wgsl.
    post: &'a [(&'a str, &'a str)],
    /// Extra or replaced files.
    files: &'a [(&'a str, &'a str)],
    profile: &'a str,
}

const BASE: Case = Case {
    pipeline: &[],
    post: &[],
    files: &[],
    profile: "vulkan",
};

fn apply(text: &str, edits: &[(&str, &str)]) -> String {
    let mut t = text.to_string();
    for (from, to) in edits {
        assert!(t.contains(from), "edit target `{from}` not found");
        t = t.replacen(from, to, 1);
    }
    t
}

fn run(c: &Case) -> Outcome {
    let pipeline = apply(PIPELINE, c.pipeline);
    let post = apply(POST_WGSL, c.post);
    let mut files: Vec<(&str, &str)> = vec![
        ("pipelines/p.ron", &pipeline),
        ("shaders/scene.wgsl", SCENE_WGSL),
        ("shaders/post.wgsl", &post),
    ];
    files.retain(|(p, _)| !c.files.iter().any(|(q, _)| q == p));
    files.extend_from_slice(c.files);
    let dir = write_project("bad", &files);
    let profile = Profile::offline(c.profile).unwrap();
    check_project(&dir, "pipelines/p.ron", &profile, None)
}

/// Asserts a diagnostic with this code whose message contains `msg`, at file:line:col.
fn expect(c: Case, code: &str, msg: &str, file: &str, line: usize, col: usize) {
    let out = run(&c);
    let found = out.located();
    let hit = found
        .iter()
        .any(|(dc, dm, f, l, co)| dc == code && dm.contains(msg) && f == file && *l == line && *co == col);
    let got: Vec<String> = found.iter().map(|(c, m, f, l, co)| format!("[{c}] {f}:{l}:{co} {m}")).collect();
    assert!(
        hit,
        "expected [{code}] containing {msg:?} at {file}:{line}:{col}; got:\n{}\n{}",
        got.join("\n"),
        out.dump()
    );
}

#[test]
fn base_project_is_clean() {
    let out = run(&BASE);
    assert!(out.session.diags.list.is_empty(), "{}", out.dump());
}

#[test]
fn ron_syntax_error() {
    expect(
        Case {
            pipeline: &[("name: \"t\",", "name: \"t\"")],
            ..BASE
        },
        "ron-syntax",
        "expected `,` or `)` after field, found `p`",
        "pipelines/p.ron",
        3,
        5,
    );
}

#[test]
fn ron_unterminated_string() {
    expect(
        Case {
            pipeline: &[("output: \"out\",", "output: \"out,")],
            ..BASE
        },
        "ron-syntax",
        "unterminated string",
        "pipelines/p.ron",
        18,
        13,
    );
}

#[test]
fn unknown_key_with_suggestion() {
    expect(
        Case {
            pipeline: &[("samplers: {", "samplerz: {")],
            ..BASE
        },
        "unknown-key",
        "unknown key `samplerz` in pipeline",
        "pipelines/p.ron",
        6,
        5,
    );
    let out = run(&Case {
        pipeline: &[("samplers: {", "samplerz: {")],
        ..BASE
    });
    assert!(out.errors()[0].notes.iter().any(|n| n == "did you mean `samplers`?"));
}

#[test]
fn unknown_pass_key() {
    expect(
        Case {
            pipeline: &[("color: [\"out\"],", "colour: [\"out\"],")],
            ..BASE
        },
        "unknown-key",
        "unknown key `colour` in pass `post`",
        "pipelines/p.ron",
        16,
        73,
    );
}

#[test]
fn missing_required_key() {
    expect(
        Case {
            pipeline: &[("    output: \"out\",\n", "")],
            ..BASE
        },
        "missing-key",
        "pipeline is missing required key `output`",
        "pipelines/p.ron",
        1,
        1,
    );
}

#[test]
fn wrong_value_type() {
    expect(
        Case {
            pipeline: &[("name: \"t\"", "name: 5")],
            ..BASE
        },
        "type-mismatch",
        "expected a string, found an integer",
        "pipelines/p.ron",
        2,
        11,
    );
}

#[test]
fn unknown_format_with_suggestion() {
    expect(
        Case {
            pipeline: &[("Rgba16Float", "Rgba16Flaot")],
            ..BASE
        },
        "unknown-value",
        "unknown texture format `Rgba16Flaot`",
        "pipelines/p.ron",
        10,
        34,
    );
}

#[test]
fn duplicate_pass_name() {
    expect(
        Case {
            pipeline: &[("name: \"scene\"", "name: \"post\"")],
            ..BASE
        },
        "duplicate-name",
        "pass `post` is declared twice",
        "pipelines/p.ron",
        16,
        26,
    );
}

/// A per-pass value is addressed as `PASS.KEY`: a parameter of that name is a clash.
#[test]
fn pass_value_named_like_a_parameter() {
    expect(
        Case {
            pipeline: &[("params: [\"post.exposure\"]", "values: {\"exposure\": 2.0}")],
            ..BASE
        },
        "duplicate-name",
        "per-pass value `post.exposure` has the name of a parameter",
        "pipelines/p.ron",
        16,
        98,
    );
}

#[test]
fn missing_shader_file() {
    expect(
        Case {
            pipeline: &[("\"post.wgsl\"", "\"pots.wgsl\"")],
            ..BASE
        },
        "shader-not-found",
        "cannot read shader `pots.wgsl`",
        "pipelines/p.ron",
        16,
        42,
    );
}

#[test]
fn wgsl_parse_error() {
    expect(
        Case {
            post: &[("exposure: f32,", "exposure f32,")],
            ..BASE
        },
        "wgsl-parse",
        "expected `:`, found \"f32\"",
        "shaders/post.wgsl",
        2,
        14,
    );
}

#[test]
fn wgsl_validation_error() {
    expect(
        Case {
            post: &[("textureSample(color, linear, uv) * params.exposure", "params.exposure")],
            ..BASE
        },
        "shader-validation",
        "Entry point fs_main at Fragment is invalid",
        "shaders/post.wgsl",
        11,
        12,
    );
}

/// Two globals at one binding, one of them in an included file: the error names both and
/// points at the other's declaration in the lib file (naga says only "Bindings for [n]").
#[test]
fn binding_collision_names_both_globals() {
    let c = Case {
        post: &[
            ("struct Params {", "#include \"lib/extra.wgsl\"\nstruct Params {"),
            ("* params.exposure", "* params.exposure * textureLoad(extra_tex, vec2<i32>(0), 0).x"),
        ],
        files: &[("shaders/lib/extra.wgsl", "@group(0) @binding(1) var extra_tex: texture_2d<f32>;\n")],
        ..BASE
    };
    let out = run(&c);
    let d = &out.session.diags.list[0];
    assert_eq!(d.code, "shader-validation", "{}", out.dump());
    assert!(
        d.message == "`linear` and `extra_tex` both use @group(0) @binding(1)"
            || d.message == "`extra_tex` and `linear` both use @group(0) @binding(1)",
        "{}",
        out.dump()
    );
    let dump = out.dump();
    assert!(dump.contains("lib/extra.wgsl:1") || dump.contains("lib/extra.wgsl"), "{dump}");
    assert!(d.labels.iter().any(|l| l.message.ends_with("too")), "{dump}");
    assert!(d.notes.iter().all(|n| !n.starts_with("Bindings for")), "{:?}", d.notes);
}

/// docs/pipelines.md's table of the bindings each lib file takes is what the files declare,
/// and group 2 from binding 8 up is free, as it says.
#[test]
fn the_lib_files_bindings_are_as_documented() {
    let root = repo_root();
    let docs = std::fs::read_to_string(root.join("docs/pipelines.md")).unwrap();
    let mut files: Vec<_> = (std::fs::read_dir(root.join("shaders/lib")).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
        .collect();
    files.sort();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        let mut cells = vec![];
        for line in text.lines().map(str::trim).filter(|l| l.starts_with("@group(")) {
            let num = |key: &str| line.split(key).nth(1).and_then(|r| r.split(')').next()).unwrap().to_string();
            let (group, binding) = (num("@group("), num("@binding("));
            let after_var = line.split(" var").nth(1).unwrap();
            let after_var = after_var
                .split_once('>')
                .filter(|_| after_var.starts_with('<'))
                .map_or(after_var, |(_, r)| r);
            let name = after_var.trim().split(':').next().unwrap().trim();
            if group == "2" {
                assert!(binding.parse::<u32>().unwrap() < 8, "{}: group 2 binding {binding}", f.display());
            }
            cells.push(format!("{group}/{binding} `{name}`"));
        }
        if cells.is_empty() {
            continue;
        }
        let row = format!("| `lib/{}` | {} |", f.file_name().unwrap().to_str().unwrap(), cells.join(", "));
        assert!(docs.contains(&row), "docs/pipelines.md lacks the row\n{row}");
    }
}

/// GLSL entry-point errors naga gives no span are located in the shader's own text, never at
/// its `#version` line: two outputs at one location at the second, others at `void main`.
#[test]
fn glsl_entry_point_errors_are_located_in_the_shader() {
    let frag = "#version 450\nlayout(location = 0) out vec4 o;\nlayout(location = 0) out vec4 p;\nvoid main() {\n    o = vec4(1.0);\n    p = vec4(0.5);\n}\n";
    expect(
        Case {
            pipeline: &[("shader: \"post.wgsl\", reads: [\"color\"],", "shader: \"post.frag\",")],
            files: &[("shaders/post.frag", frag)],
            ..BASE
        },
        "shader-validation",
        "Entry point main at Fragment is invalid",
        "shaders/post.frag",
        3,
        1,
    );
}

/// An invalid type is named in WGSL and located where it is written (naga's headline was
/// "Type [2] '' is invalid", at 1:1).
#[test]
fn an_invalid_type_is_named_and_located() {
    let c = Case {
        post: &[(
            "@group(0) @binding(2) var<uniform> params: Params;",
            "@group(0) @binding(2) var<uniform> params: Params;\n@group(0) @binding(3) var<storage, read> xs: array<array<f32>, 2>;",
        )],
        ..BASE
    };
    expect(
        c,
        "shader-validation",
        "Type `array<array<f32>, 2>` is invalid",
        "shaders/post.wgsl",
        8,
        46,
    );
    let out = run(&Case {
        post: &[(
            "@group(0) @binding(2) var<uniform> params: Params;",
            "@group(0) @binding(2) var<uniform> params: Params;\n@group(0) @binding(3) var<storage, read> xs: array<array<f32>, 2>;",
        )],
        ..BASE
    });
    let d = &out.session.diags.list[0];
    assert_eq!(d.notes, ["Base type `array<f32>` for the array is invalid"], "{}", out.dump());
}

#[test]
fn glsl_error() {
    let frag = "#version 450\nlayout(location = 0) out vec4 o;\nvoid main() {\n    o = vec4(1.0) +;\n}\n";
    expect(
        Case {
            pipeline: &[("shader: \"post.wgsl\", reads: [\"color\"],", "shader: \"post.frag\",")],
            files: &[("shaders/post.frag", frag)],
            ..BASE
        },
        "glsl-parse",
        "",
        "shaders/post.frag",
        4,
        20,
    );
}

#[test]
fn missing_entry_point() {
    expect(
        Case {
            pipeline: &[("shader: \"post.wgsl\",", "shader: \"post.wgsl\", fragment: \"fs_mian\",")],
            ..BASE
        },
        "missing-entry-point",
        "has no entry point `fs_mian`",
        "pipelines/p.ron",
        16,
        65,
    );
}

#[test]
fn entry_point_of_wrong_stage() {
    expect(
        Case {
            pipeline: &[("shader: \"scene.wgsl\",", "shader: \"scene.wgsl\", vertex: \"fs_main\",")],
            ..BASE
        },
        "wrong-stage",
        "`fs_main` is a fragment entry point",
        "pipelines/p.ron",
        15,
        61,
    );
}

#[test]
fn binding_with_no_declared_resource() {
    expect(
        Case {
            post: &[
                (
                    "@group(0) @binding(2)",
                    "@group(0) @binding(3) var bloom: texture_2d<f32>;\n@group(0) @binding(2)",
                ),
                ("* params.exposure", "* params.exposure + textureLoad(bloom, vec2<i32>(0), 0)"),
            ],
            ..BASE
        },
        "binding-unsatisfied",
        "shader global `bloom` (@group(0) @binding(3)) is not bound by pass `post`",
        "shaders/post.wgsl",
        7,
        23,
    );
}

#[test]
fn texture_float_vs_depth() {
    expect(
        Case {
            post: &[
                ("var color: texture_2d<f32>;", "var color: texture_depth_2d;"),
                (
                    "textureSample(color, linear, uv)",
                    "vec4<f32>(textureLoad(color, vec2<i32>(uv), 0))",
                ),
            ],
            ..BASE
        },
        "texture-type",
        "`color` is `texture_depth_2d` but `color` has format Rgba16Float: a depth texture binding needs a depth format",
        "shaders/post.wgsl",
        5,
        23,
    );
}

/// A binding array is no mismatch with the resource: lightbench binds no such thing, and says
/// so (it said "an unsupported binding … but `color` is a Rgba16Float texture").
#[test]
fn a_binding_array_is_said_to_be_unbindable() {
    expect(
        Case {
            post: &[
                ("struct Params {", "enable wgpu_binding_array;\nstruct Params {"),
                ("var color: texture_2d<f32>;", "var color: binding_array<texture_2d<f32>, 2>;"),
                ("textureSample(color, linear, uv)", "textureSample(color[0], linear, uv)"),
            ],
            profile: "vulkan",
            ..BASE
        },
        "binding-type",
        "`color` is a `binding_array<texture_2d<f32>, 2>`, which lightbench does not bind",
        "shaders/post.wgsl",
        6,
        23,
    );
}

#[test]
fn texture_2d_vs_cube() {
    expect(
        Case {
            post: &[
                ("var color: texture_2d<f32>;", "var color: texture_cube<f32>;"),
                (
                    "textureSample(color, linear, uv)",
                    "textureSample(color, linear, vec3<f32>(uv, 1.0))",
                ),
            ],
            ..BASE
        },
        "texture-type",
        "`color` is `texture_cube<f32>` but `color` is declared with view D2 and 1 layer(s)",
        "shaders/post.wgsl",
        5,
        23,
    );
}

#[test]
fn fragment_output_count_mismatch() {
    expect(
        Case {
            pipeline: &[("color: [\"color\"]", "color: [\"color\", \"out\"]")],
            ..BASE
        },
        "fragment-outputs",
        "writes 1 color output(s) but pass `scene` has 2 color target(s)",
        "pipelines/p.ron",
        15,
        39,
    );
}

/// The secondary label points at the fragment entry point's declaration (its result
/// declares the outputs), not at an unrelated expression of its body.
#[test]
fn fragment_output_count_mismatch_points_at_the_entry_point() {
    let out = run(&Case {
        pipeline: &[("color: [\"color\"]", "color: [\"color\", \"out\"]")],
        ..BASE
    });
    let d = out
        .errors()
        .into_iter()
        .find(|d| d.code.as_str() == "fragment-outputs")
        .expect("a fragment-outputs error");
    let label = d
        .labels
        .iter()
        .find(|l| !l.primary && l.message.contains("entry point"))
        .expect("a label at the entry point");
    let f = out.session.sources.get(label.span.file);
    assert!(f.name.ends_with("shaders/scene.wgsl"), "{}", f.name);
    assert_eq!(f.line_col(label.span.start as usize), (15, 1));
    assert_eq!(&f.text[label.span.range()], "fn fs_main");
}

#[test]
fn fragment_output_kind_mismatch() {
    expect(
        Case {
            pipeline: &[("\"out\": Texture(format: Rgba8Unorm)", "\"out\": Texture(format: R32Uint)")],
            ..BASE
        },
        "fragment-output-kind",
        "@location(0) is `vec4<f32>` but target `out` has format R32Uint which needs u32 values",
        "pipelines/p.ron",
        16,
        81,
    );
}

#[test]
fn read_before_write() {
    expect(
        Case {
            pipeline: &[
                (
                    "\"out\": Texture",
                    "\"bloom\": Texture(format: Rgba16Float),\n        \"out\": Texture",
                ),
                ("reads: [\"color\"]", "reads: [\"color\", \"bloom\"]"),
            ],
            post: &[
                (
                    "@group(0) @binding(2)",
                    "@group(0) @binding(3) var bloom: texture_2d<f32>;\n@group(0) @binding(2)",
                ),
                ("* params.exposure", "* params.exposure + textureLoad(bloom, vec2<i32>(0), 0)"),
            ],
            ..BASE
        },
        "read-before-write",
        "`bloom` is read by pass `post` but no pass writes it first",
        "pipelines/p.ron",
        17,
        72,
    );
}

const TWO_PASS_CYCLE: &str = r#"
        Fullscreen(name: "a", shader: "copy.wgsl", reads: ["tmp_b"], color: ["tmp_a"]),
        Fullscreen(name: "b", shader: "copy.wgsl", bind: {"tmp_b": "tmp_a"}, reads: ["tmp_a"], color: ["tmp_b"]),
    ],"#;
const COPY_WGSL: &str = "@group(0) @binding(0) var tmp_b: texture_2d<f32>;\n@fragment\nfn fs_main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n    return textureLoad(tmp_b, vec2<i32>(p.xy), 0);\n}\n";

#[test]
fn cycle_between_passes() {
    expect(
        Case {
            pipeline: &[
                (
                    "\"out\": Texture",
                    "\"tmp_a\": Texture(format: Rgba16Float),\n        \"tmp_b\": Texture(format: Rgba16Float),\n        \"out\": Texture",
                ),
                ("reads: [\"color\"]", "reads: [\"color\", \"tmp_a\"]"),
                ("\n    ],", TWO_PASS_CYCLE),
            ],
            post: &[
                (
                    "@group(0) @binding(2)",
                    "@group(0) @binding(3) var tmp_a: texture_2d<f32>;\n@group(0) @binding(2)",
                ),
                ("* params.exposure", "* params.exposure + textureLoad(tmp_a, vec2<i32>(0), 0)"),
            ],
            files: &[("shaders/copy.wgsl", COPY_WGSL)],
            ..BASE
        },
        "cycle",
        "passes form a cycle: b -> a -> b",
        "pipelines/p.ron",
        20,
        86,
    );
}

#[test]
fn unordered_double_writer() {
    expect(
        Case {
            pipeline: &[("\n    ],", "\n        Fullscreen(name: \"post2\", shader: \"post.wgsl\", reads: [\"color\"], color: [\"out\"], params: [\"post.exposure\"]),\n    ],")],
            ..BASE
        },
        "double-writer",
        "passes `post` and `post2` both write `out` and nothing orders them",
        "pipelines/p.ron",
        17,
        82,
    );
}

#[test]
fn attachment_size_mismatch() {
    expect(
        Case {
            pipeline: &[(
                "\"depth\": Texture(format: Depth32Float)",
                "\"depth\": Texture(format: Depth32Float, size: Fixed(256, 256))",
            )],
            ..BASE
        },
        "attachment-size",
        "attachments of pass `scene` differ in size: `color` is viewport, `depth` is 256×256",
        "pipelines/p.ron",
        15,
        78,
    );
}

#[test]
fn depth_format_as_color_target() {
    expect(
        Case {
            pipeline: &[("color: [\"color\"], depth", "color: [\"depth\"], depth")],
            ..BASE
        },
        "depth-as-color",
        "`depth` has depth format Depth32Float and cannot be a color target",
        "pipelines/p.ron",
        15,
        61,
    );
}

#[test]
fn color_format_as_depth_target() {
    expect(
        Case {
            pipeline: &[("depth: \"depth\"", "depth: \"out\"")],
            ..BASE
        },
        "color-as-depth",
        "`out` has color format Rgba8Unorm and cannot be a depth target",
        "pipelines/p.ron",
        15,
        78,
    );
}

#[test]
fn blend_on_non_blendable_format() {
    expect(
        Case {
            pipeline: &[
                ("\"out\": Texture(format: Rgba8Unorm)", "\"out\": Texture(format: Rgba32Float)"),
                ("color: [\"out\"]", "color: [Target(resource: \"out\", blend: Add)]"),
            ],
            ..BASE
        },
        "blend-not-blendable",
        "format Rgba32Float of `out` is not blendable",
        "pipelines/p.ron",
        16,
        112,
    );
}

#[test]
fn too_many_color_attachments() {
    expect(
        Case { pipeline: &[("color: [\"color\"], depth", "color: [\"color\", \"c1\", \"c2\", \"c3\", \"c4\", \"c5\", \"c6\", \"c7\", \"c8\"], depth"), ("\"out\": Texture", "\"c1\": Texture(format: R8Unorm), \"c2\": Texture(format: R8Unorm), \"c3\": Texture(format: R8Unorm), \"c4\": Texture(format: R8Unorm),\n        \"c5\": Texture(format: R8Unorm), \"c6\": Texture(format: R8Unorm), \"c7\": Texture(format: R8Unorm), \"c8\": Texture(format: R8Unorm),\n        \"out\": Texture")], ..BASE },
        "limit-exceeded",
        "pass `scene` has too many color attachments: 9 exceeds 8",
        "pipelines/p.ron",
        17,
        112,
    );
}

#[test]
fn parameter_type_mismatch_between_file_and_shader() {
    expect(
        Case {
            post: &[
                ("exposure: f32,", "exposure: i32,"),
                ("* params.exposure", "* f32(params.exposure)"),
            ],
            ..BASE
        },
        "param-type-mismatch",
        "parameter `post.exposure` is Float but shader field `exposure` is `i32`",
        "pipelines/p.ron",
        16,
        98,
    );
}

#[test]
fn shader_field_without_parameter() {
    expect(
        Case {
            post: &[("exposure: f32,", "exposure: f32,\n    gamma: f32,")],
            ..BASE
        },
        "param-missing",
        "field `gamma` of parameter block `params` has no parameter in pass `post`",
        "shaders/post.wgsl",
        8,
        23,
    );
}

#[test]
fn default_out_of_range() {
    expect(
        Case {
            pipeline: &[("default: 1.0", "default: 9.5")],
            ..BASE
        },
        "default-out-of-range",
        "default 9.5 of `post.exposure` is above its max 8",
        "pipelines/p.ron",
        4,
        41,
    );
}

#[test]
fn unknown_variant_in_condition() {
    expect(
        Case {
            pipeline: &[(
                "params: [\"post.exposure\"])",
                "params: [\"post.exposure\"], when: Variant(\"tonemapp\", \"x\"))",
            )],
            ..BASE
        },
        "unknown-variant",
        "no variant named `tonemapp`",
        "pipelines/p.ron",
        16,
        130,
    );
}

const VARIANT_NO_FALLBACK: &str = r#"    variants: {
        "views": Variant(default: "multi", options: {
            "multi": (requires: [Multiview]),
            "single": (),
        }),
    },
    output: "out","#;

#[test]
fn variant_needs_unavailable_feature_without_fallback() {
    expect(
        Case {
            pipeline: &[("    output: \"out\",", VARIANT_NO_FALLBACK)],
            profile: "webgpu",
            ..BASE
        },
        "variant-unsupported",
        "variant `views` option `multi` needs feature Multiview, which profile `webgpu` lacks, and declares no fallback",
        "pipelines/p.ron",
        20,
        34,
    );
}

#[test]
fn geometry_shader_request() {
    expect(
        Case {
            pipeline: &[("shader: \"scene.wgsl\",", "shader: \"scene.wgsl\", geometry: \"layers.wgsl\",")],
            ..BASE
        },
        "geometry-shader",
        "geometry shaders are not supported",
        "pipelines/p.ron",
        15,
        53,
    );
    let out = run(&Case {
        pipeline: &[("shader: \"scene.wgsl\",", "shader: \"scene.wgsl\", geometry: \"layers.wgsl\",")],
        ..BASE
    });
    let note = &out.errors()[0].notes[0];
    assert!(note.contains("multiview") && note.contains("instanced atlas"), "{note}");
}

#[test]
fn geometry_shader_file() {
    expect(
        Case {
            pipeline: &[("shader: \"post.wgsl\",", "shader: \"post.geom\",")],
            files: &[("shaders/post.geom", "#version 450\nvoid main() {}\n")],
            ..BASE
        },
        "geometry-shader",
        "geometry shaders are not supported",
        "pipelines/p.ron",
        16,
        42,
    );
}

#[test]
fn unknown_effect_in_condition() {
    expect(
        Case {
            pipeline: &[("params: [\"post.exposure\"])", "params: [\"post.exposure\"], when: Effect(Bloomm))")],
            ..BASE
        },
        "unknown-effect",
        "unknown effect `Bloomm`",
        "pipelines/p.ron",
        16,
        129,
    );
}

#[test]
fn texture_over_the_size_limit() {
    expect(
        Case {
            pipeline: &[(
                "\"depth\": Texture(format: Depth32Float)",
                "\"depth\": Texture(format: Depth32Float, size: Fixed(16384, 16))",
            )],
            profile: "webgpu",
            ..BASE
        },
        "texture-too-large",
        "`depth` is 16384×16, over the 8192 texel limit of profile `webgpu`",
        "pipelines/p.ron",
        11,
        54,
    );
}

#[test]
fn include_cycle() {
    expect(
        Case {
            post: &[("struct Params", "#include \"lib/a.wgsl\"\nstruct Params")],
            files: &[
                ("shaders/lib/a.wgsl", "#include \"lib/b.wgsl\"\n"),
                ("shaders/lib/b.wgsl", "// b\n#include \"lib/a.wgsl\"\n"),
            ],
            ..BASE
        },
        "include-cycle",
        "include cycle: post.wgsl -> lib/a.wgsl -> lib/b.wgsl -> lib/a.wgsl",
        "shaders/lib/b.wgsl",
        2,
        1,
    );
}

#[test]
fn missing_include() {
    expect(
        Case {
            post: &[("struct Params", "#include \"lib/nope.wgsl\"\nstruct Params")],
            ..BASE
        },
        "include-not-found",
        "cannot read included file `lib/nope.wgsl`",
        "shaders/post.wgsl",
        1,
        1,
    );
}

#[test]
fn unknown_resource_with_suggestion() {
    expect(
        Case {
            pipeline: &[("reads: [\"color\"]", "reads: [\"colr\"]")],
            ..BASE
        },
        "unknown-resource",
        "no resource named `colr`",
        "pipelines/p.ron",
        16,
        63,
    );
}

#[test]
fn filtering_sampler_on_unfilterable_texture() {
    expect(
        Case {
            pipeline: &[("reads: [\"color\"]", "reads: [\"depth\"]"), ("depth: \"depth\"", "")],
            post: &[("var color:", "var depth:"), ("textureSample(color,", "textureSample(depth,")],
            ..BASE
        },
        "not-filterable",
        "`depth` (depth) is sampled with filtering sampler `linear`, but Depth32Float is not filterable",
        "shaders/post.wgsl",
        5,
        23,
    );
}

#[test]
fn comparison_sampler_mismatch() {
    expect(
        Case {
            post: &[
                ("var linear: sampler;", "var linear: sampler_comparison;"),
                ("var color: texture_2d<f32>;", "var color: texture_depth_2d;"),
                (
                    "textureSample(color, linear, uv)",
                    "vec4<f32>(textureSampleCompare(color, linear, uv, 0.5))",
                ),
            ],
            pipeline: &[
                ("reads: [\"color\"]", "reads: [\"depth\"]"),
                ("depth: \"depth\"", ""),
                ("\"post.wgsl\",", "\"post.wgsl\", bind: {\"color\": \"depth\"},"),
            ],
            ..BASE
        },
        "sampler-type",
        "`linear` is a `sampler_comparison` but sampler `linear` has no `compare`",
        "shaders/post.wgsl",
        6,
        23,
    );
}

#[test]
fn previous_frame_of_non_history_resource() {
    expect(
        Case {
            pipeline: &[("reads: [\"color\"]", "reads: [\"color\", Prev(\"out\")]")],
            ..BASE
        },
        "not-history",
        "`Prev(\"out\")` reads the previous frame, but `out` is not a history resource",
        "pipelines/p.ron",
        16,
        77,
    );
}

#[test]
fn per_light_resource_in_a_pass_that_is_not_per_light() {
    expect(
        Case {
            pipeline: &[(
                "\"color\": Texture(format: Rgba16Float)",
                "\"color\": Texture(format: Rgba16Float, per_light: [Spot])",
            )],
            ..BASE
        },
        "per-light-mismatch",
        "`color` has one instance per light, but pass `scene` does not run per light",
        "pipelines/p.ron",
        15,
        61,
    );
}

#[test]
fn output_resource_unknown() {
    expect(
        Case {
            pipeline: &[("output: \"out\"", "output: \"outt\"")],
            ..BASE
        },
        "unknown-resource",
        "no resource named `outt`",
        "pipelines/p.ron",
        18,
        13,
    );
}

#[test]
fn layer_all_needs_multiview() {
    expect(
        Case {
            pipeline: &[("depth: \"depth\"", "depth: Depth(resource: \"depth\", layer: All)")],
            ..BASE
        },
        "layer-select",
        "`layer: All` renders every layer at once and needs `multiview: N`",
        "pipelines/p.ron",
        15,
        78,
    );
}

#[test]
fn fragment_input_not_written_by_vertex_stage() {
    expect(
        Case {
            post: &[("@location(0) uv: vec2<f32>", "@location(1) uv: vec2<f32>")],
            ..BASE
        },
        "stage-io",
        "fragment input @location(1) `uv` is not written by vertex entry point `fullscreen_vs`",
        "pipelines/p.ron",
        16,
        42,
    );
}

#[test]
fn vertex_input_the_scene_does_not_provide() {
    let vs = SCENE_WGSL.replace(
        "@location(1) normal: vec3<f32>) -> VsOut",
        "@location(1) normal: vec3<f32>, @location(7) extra: f32) -> VsOut",
    );
    expect(
        Case {
            files: &[("shaders/scene.wgsl", Box::leak(vs.into_boxed_str()))],
            ..BASE
        },
        "vertex-input",
        "vertex input @location(7) is not provided by scene meshes",
        "pipelines/p.ron",
        15,
        39,
    );
}

#[test]
fn storage_write_declared_as_read() {
    expect(
        Case {
            pipeline: &[("\n    ],", "\n        Compute(name: \"fill\", shader: \"fill.wgsl\", reads: [\"color\"], dispatch: Groups(1, 1, 1)),\n    ],"), ("\"color\": Texture(format: Rgba16Float)", "\"color\": Texture(format: Rgba16Float, history: true)")],
            files: &[("shaders/fill.wgsl", "@group(0) @binding(0) var color: texture_storage_2d<rgba16float, write>;\n@compute @workgroup_size(8, 8, 1)\nfn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {\n    textureStore(color, id.xy, vec4<f32>(1.0));\n}\n")],
            ..BASE
        },
        "binding-access",
        "`color` is written by the shader but the pass lists `color` under `reads`",
        "shaders/fill.wgsl",
        1,
        23,
    );
}

#[test]
fn unused_read_is_a_warning() {
    let out = run(&Case {
        pipeline: &[("reads: [\"color\"]", "reads: [\"color\", \"depth\"]")],
        ..BASE
    });
    let d = out.session.diags.list.iter().find(|d| d.code == "unused-read").expect("warning");
    assert_eq!(d.severity, lightbench_compiler::diag::Severity::Warning);
    assert_eq!(d.message, "pass `post` reads `depth` but no entry point uses it");
    assert_eq!(d.location(&out.session.sources).map(|(_, l, c)| (l, c)), Some((16, 72)));
    assert!(!out.session.diags.has_errors(), "{}", out.dump());
}

#[test]
fn unknown_variant_option_as_default() {
    expect(
        Case {
            pipeline: &[(
                "    output: \"out\",",
                "    variants: {\"v\": Variant(default: \"b\", options: {\"a\": ()})},\n    output: \"out\",",
            )],
            ..BASE
        },
        "unknown-variant-option",
        "default `b` is not an option of variant `v`",
        "pipelines/p.ron",
        18,
        38,
    );
}

#[test]
fn format_not_renderable_on_profile() {
    expect(
        Case {
            pipeline: &[("\"out\": Texture(format: Rgba8Unorm)", "\"out\": Texture(format: Rg11b10Ufloat)")],
            profile: "webgpu",
            ..BASE
        },
        "format-not-renderable",
        "format Rg11b10Ufloat of `out` cannot be rendered to on profile `webgpu`",
        "pipelines/p.ron",
        16,
        81,
    );
}

#[test]
fn repeated_pass_clearing_a_shared_target_warns() {
    let out = run(&Case {
        pipeline: &[("params: [\"post.exposure\"])", "params: [\"post.exposure\"], per_light: [Point])")],
        ..BASE
    });
    let d = out.session.diags.list.iter().find(|d| d.code == "repeated-clear").expect("warning");
    assert_eq!(d.severity, lightbench_compiler::diag::Severity::Warning);
    assert_eq!(
        d.message,
        "pass `post` runs once per light and clears `out` each time: only the last repetition's output remains"
    );
    assert_eq!(d.location(&out.session.sources).map(|(_, l, c)| (l, c)), Some((16, 81)));
    assert!(!out.session.diags.has_errors(), "{}", out.dump());
}

#[test]
fn hdr_output_must_name_a_texture() {
    expect(
        Case {
            pipeline: &[("    output: \"out\",", "    hdr_output: \"colour\",\n    output: \"out\",")],
            ..BASE
        },
        "unknown-resource",
        "no resource named `colour`",
        "pipelines/p.ron",
        18,
        17,
    );
}

/// A `read_write` storage buffer listed under `reads` is a `binding-access` error and nothing
/// else: it is bound, so no `unused-read` warning as well.
#[test]
fn read_write_storage_under_reads_is_one_error_without_a_false_warning() {
    let out = run(&Case {
        pipeline: &[
            ("\n    ],", "\n        Compute(name: \"sum\", shader: \"sum.wgsl\", reads: [\"data\"], dispatch: Groups(1, 1, 1)),\n    ],"),
            ("\"out\": Texture(format: Rgba8Unorm),", "\"out\": Texture(format: Rgba8Unorm),\n        \"data\": Buffer(size: 64),"),
        ],
        files: &[("shaders/sum.wgsl", "@group(2) @binding(0) var<storage, read_write> data: array<u32>;\n@compute @workgroup_size(1)\nfn cs_main() {\n    data[0] = data[1];\n}\n")],
        ..BASE
    });
    let codes: Vec<String> = out.located().into_iter().map(|d| d.0).collect();
    assert!(codes.contains(&"binding-access".to_string()), "{}", out.dump());
    assert!(!codes.contains(&"unused-read".to_string()), "no false warning: {}", out.dump());
}

#[test]
fn per_pass_value_that_does_not_fit_its_field() {
    expect(
        Case {
            pipeline: &[(
                "params: [\"post.exposure\"])",
                "params: [\"post.exposure\"], values: {\"taps\": 2.5})",
            )],
            post: &[("exposure: f32,", "exposure: f32,\n    taps: u32,")],
            ..BASE
        },
        "value-type",
        "value for `taps`: `2.5` is not a whole number that fits `u32`",
        "pipelines/p.ron",
        16,
        133,
    );
}

#[test]
fn per_pass_value_naming_no_field() {
    expect(
        Case {
            pipeline: &[("params: [\"post.exposure\"])", "params: [\"post.exposure\"], values: {\"tap\": 2})")],
            post: &[("exposure: f32,", "exposure: f32,\n    taps: u32,")],
            ..BASE
        },
        "value-field",
        "parameter block `params` has no field `tap`",
        "pipelines/p.ron",
        16,
        125,
    );
}

/// Two parameters ending in the same segment: the message names the one that took the
/// field and how to bind the other.
#[test]
fn parameters_with_the_same_last_segment() {
    expect(
        Case {
            pipeline: &[
                (
                    "\"post.exposure\": Float(default: 1.0, min: 0.0, max: 8.0),",
                    "\"post.exposure\": Float(default: 1.0, min: 0.0, max: 8.0),\n        \"pre.exposure\": Float(default: 1.0),",
                ),
                ("params: [\"post.exposure\"])", "params: [\"post.exposure\", \"pre.exposure\"])"),
            ],
            ..BASE
        },
        "param-missing",
        "parameter `pre.exposure` has no field in shader block `params`: field `exposure` is taken by parameter `post.exposure`",
        "pipelines/p.ron",
        17,
        115,
    );
}

const COMPUTE_WGSL: &str = r#"@group(0) @binding(0) var color: texture_2d<f32>;
@group(0) @binding(1) var linear: sampler;
@group(0) @binding(2) var<storage, read_write> sums: array<vec4<f32>>;

@compute @workgroup_size(1)
fn cs_main() {
    sums[0] = textureSample(color, linear, vec2<f32>(0.5));
}
"#;

/// naga reports a stage-forbidden operation with no span: it is located at the operation.
#[test]
fn operation_forbidden_in_compute_is_located_at_the_call() {
    expect(
        Case {
            pipeline: &[
                ("    ],\n    output", "        Compute(name: \"sum\", shader: \"sum.wgsl\", reads: [\"color\"], writes: [\"sums\"], dispatch: Groups(1, 1, 1)),\n    ],\n    output"),
                ("\"out\": Texture(format: Rgba8Unorm),", "\"out\": Texture(format: Rgba8Unorm),\n        \"sums\": Buffer(size: 16),"),
            ],
            files: &[("shaders/sum.wgsl", COMPUTE_WGSL)],
            ..BASE
        },
        "shader-validation",
        "Entry point cs_main at Compute is invalid",
        "shaders/sum.wgsl",
        7,
        15,
    );
}

/// naga's validation messages name types in WGSL and expressions by their source text.
#[test]
fn validation_messages_speak_wgsl() {
    let c = Case {
        post: &[("    return textureSample(color, linear, uv) * params.exposure;", "    let m = mat4x4<f32>();\n    let v = vec3<f32>(1.0);\n    let bad = m * v;\n    return textureSample(color, linear, uv) * params.exposure;")],
        ..BASE
    };
    expect(
        Case { ..c },
        "shader-validation",
        "Entry point fs_main at Fragment is invalid",
        "shaders/post.wgsl",
        13,
        15,
    );
    let text = run(&c).dump();
    assert!(text.contains("= `m * v` is invalid"), "{text}");
    assert!(
        text.contains("(of type mat4x4<f32>) and `vec3<f32>(1.0)` (of type vec3<f32>)"),
        "{text}"
    );
    assert!(!text.contains("Scalar {") && !text.contains("Expression ["), "{text}");
}

/// One value that does not lower (an unknown effect) no longer hides the other problems of
/// the file: the shaders of the passes that did lower are still checked.
#[test]
fn an_unknown_value_does_not_hide_shader_errors() {
    let out = run(&Case {
        pipeline: &[("depth: \"depth\")", "depth: \"depth\", when: Effect(AmbientOclusion))")],
        post: &[(
            "return textureSample(color, linear, uv) * params.exposure;",
            "return textureSample(color, linear, uv) * params.exposure",
        )],
        ..BASE
    });
    let codes: Vec<String> = out.located().into_iter().map(|(c, _, f, l, _)| format!("{c} {f}:{l}")).collect();
    assert!(codes.contains(&"unknown-effect pipelines/p.ron:15".to_string()), "{codes:?}");
    assert!(codes.iter().any(|c| c.starts_with("wgsl-parse shaders/post.wgsl:")), "{codes:?}");
}

/// The same problem in two passes sharing a shader is reported once, with the second pass
/// as an "also here" label.
#[test]
fn a_problem_repeated_per_pass_is_reported_once() {
    let out = run(&Case {
        pipeline: &[
            ("\"out\": Texture(format: Rgba8Unorm),", "\"out\": Texture(format: Rgba8Unorm),\n        \"out2\": Texture(format: Rgba8Unorm),"),
            ("    ],\n    output: \"out\"", "        Fullscreen(name: \"post2\", shader: \"post.wgsl\", reads: [\"color\"], color: [\"out2\"], params: [\"post.exposure\"]),\n    ],\n    output: \"out\""),
        ],
        post: &[("exposure: f32,", "exposure: i32,"), ("* params.exposure", "* f32(params.exposure)")],
        ..BASE
    });
    let found: Vec<_> = out
        .errors()
        .into_iter()
        .filter(|d| d.code.as_str() == "param-type-mismatch")
        .collect();
    assert_eq!(found.len(), 1, "{}", out.dump());
    let also = found[0]
        .labels
        .iter()
        .find(|l| l.message == "also here")
        .expect("an `also here` label");
    let f = out.session.sources.get(also.span.file);
    assert_eq!(f.line_col(also.span.start as usize).0, 18, "{}", out.dump());
}

/// A texture sized by a parameter needs an Int parameter whose range keeps it plannable.
#[test]
fn texture_sized_by_a_parameter_without_a_range() {
    expect(
        Case {
            pipeline: &[
                (
                    "\"post.exposure\": Float(default: 1.0, min: 0.0, max: 8.0),",
                    "\"post.exposure\": Float(default: 1.0, min: 0.0, max: 8.0),\n        \"tile\": Int(default: 64),",
                ),
                (
                    "\"color\": Texture(format: Rgba16Float),",
                    "\"color\": Texture(format: Rgba16Float),\n        \"tiles\": Texture(format: Rgba16Float, size: Param(\"tile\")),",
                ),
            ],
            ..BASE
        },
        "value-out-of-range",
        "`tiles` is sized by `tile`: give it a range within 1..",
        "pipelines/p.ron",
        12,
        53,
    );
}

/// Two variants' presets for a pipeline: `q` sets the exposure, `r` sets it too (an overlap)
/// unless a case edits it.
const PRESETS: &str = "    variants: {\n        \"q\": Variant(default: \"lo\", options: {\"lo\": (params: {\"post.exposure\": 0.5}), \"hi\": (params: {\"post.exposure\": 4})}),\n        \"r\": Variant(default: \"x\", options: {\"x\": (params: {\"post.exposure\": 2.0})}),\n    },\n    output: \"out\",";

fn preset_case<'a>(edits: &'a [(&'a str, &'a str)]) -> Case<'a> {
    Case { pipeline: edits, ..BASE }
}

/// A preset naming no parameter is located at the name, with the nearest name suggested.
#[test]
fn preset_of_an_unknown_parameter() {
    let text = PRESETS
        .replace(
            "\"r\": Variant(default: \"x\", options: {\"x\": (params: {\"post.exposure\": 2.0})}),\n",
            "",
        )
        .replace(
            "\"lo\": (params: {\"post.exposure\": 0.5})",
            "\"lo\": (params: {\"post.exposur\": 0.5})",
        );
    let out = run(&preset_case(&[("    output: \"out\",", &text)]));
    let d = out
        .errors()
        .into_iter()
        .find(|d| d.code.as_str() == "unknown-param")
        .unwrap_or_else(|| panic!("{}", out.dump()));
    assert!(d.message.contains("`post.exposur`"), "{}", out.dump());
    assert!(d.notes.iter().any(|n| n.contains("post.exposure")), "{}", out.dump());
}

/// A preset value of the wrong type or outside the parameter's range is refused where it is
/// written.
#[test]
fn preset_values_are_typed_and_range_checked() {
    let one = PRESETS.replace(
        "\"r\": Variant(default: \"x\", options: {\"x\": (params: {\"post.exposure\": 2.0})}),\n",
        "",
    );
    let typed = one.replace("\"post.exposure\": 0.5", "\"post.exposure\": true");
    let out = run(&preset_case(&[("    output: \"out\",", &typed)]));
    assert!(
        out.errors()
            .iter()
            .any(|d| d.code.as_str() == "param-type" && d.message.contains("`post.exposure`")),
        "{}",
        out.dump()
    );
    let ranged = one.replace("\"post.exposure\": 4", "\"post.exposure\": 9");
    let out = run(&preset_case(&[("    output: \"out\",", &ranged)]));
    let d = out
        .errors()
        .into_iter()
        .find(|d| d.code.as_str() == "value-out-of-range")
        .unwrap_or_else(|| panic!("{}", out.dump()));
    assert!(d.message.contains("above the max 8"), "{}", d.message);
}

/// One parameter set by the presets of two variants is an error at the second, pointing
/// back at the first.
#[test]
fn preset_overlap_between_variants() {
    let out = run(&preset_case(&[("    output: \"out\",", PRESETS)]));
    let d = out
        .errors()
        .into_iter()
        .find(|d| d.code.as_str() == "preset-overlap")
        .unwrap_or_else(|| panic!("{}", out.dump()));
    assert!(d.message.contains("variants `q` and `r`"), "{}", d.message);
    assert!(
        d.labels.iter().any(|l| l.message.contains("set by variant `q` here")),
        "{}",
        out.dump()
    );
}

/// A viewport scaled by a parameter needs a Float parameter ranged within (0, 16].
#[test]
fn texture_scaled_by_a_parameter_needs_a_bounded_float() {
    for (param, why) in [
        ("\"half\": Int(default: 1, min: 1, max: 2),", "which must be a Float parameter"),
        ("\"half\": Float(default: 0.5),", "give it a range within (0, 16]"),
        (
            "\"half\": Float(default: 0.5, min: 0.0, max: 1.0),",
            "give it a range within (0, 16]",
        ),
    ] {
        let out = run(&Case {
            pipeline: &[
                (
                    "\"post.exposure\": Float(default: 1.0, min: 0.0, max: 8.0),",
                    &format!("\"post.exposure\": Float(default: 1.0, min: 0.0, max: 8.0),\n        {param}"),
                ),
                (
                    "\"color\": Texture(format: Rgba16Float),",
                    "\"color\": Texture(format: Rgba16Float),\n        \"small\": Texture(format: Rgba16Float, size: Viewport(Param(\"half\"))),",
                ),
            ],
            ..BASE
        });
        let d = out
            .errors()
            .into_iter()
            .find(|d| d.code.as_str() == "value-out-of-range")
            .unwrap_or_else(|| panic!("{}", out.dump()));
        assert!(d.message.contains(why), "{param}: {}", d.message);
    }
}

const VOLUME_WGSL: &str = r#"@group(0) @binding(0) var triangles: texture_2d_array<u32>;

@vertex
fn vs_main(@builtin(vertex_index) v: u32, @builtin(instance_index) t: u32) -> @builtin(position) vec4<f32> {
    let corner = bitcast<vec4<f32>>(textureLoad(triangles, vec2<u32>(3u * t + v % 3u, 0u), 0u, 0));
    return vec4<f32>(corner.xyz, 1.0);
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return vec4<f32>(1.0);
}
"#;

/// Vertex pulling over the scene (`draw: Triangles(n)`) with the standard `triangles` binding
/// checks clean; a zero vertex count, `instances`, or a `triangles` of the wrong type (a
/// storage buffer, not the table) do not.
#[test]
fn per_triangle_draws_and_the_triangles_binding() {
    let pass = |draw: &str| {
        format!("        Raster(name: \"vol\", shader: \"vol.wgsl\", {draw}, color: [Target(resource: \"color\", load: Load)]),\n    ],\n    output: \"out\"")
    };
    let case = |draw: &str, shader: &str| {
        let edit = pass(draw);
        let out = {
            let pipeline = [("    ],\n    output: \"out\"", edit.as_str())];
            run(&Case {
                pipeline: &pipeline,
                files: &[("shaders/vol.wgsl", shader)],
                ..BASE
            })
        };
        out
    };
    let ok = case("draw: Triangles(24)", VOLUME_WGSL);
    assert!(ok.errors().is_empty(), "{}", ok.dump());
    let zero = case("draw: Triangles(0)", VOLUME_WGSL);
    assert!(
        zero.errors().iter().any(|d| d.message == "a raster pass draws at least one vertex"),
        "{}",
        zero.dump()
    );
    let inst = case("draw: Triangles(24), instances: 2", VOLUME_WGSL);
    assert!(
        inst.errors().iter().any(|d| d.message.contains("takes no `instances`")),
        "{}",
        inst.dump()
    );
    // The table as the storage buffer it once was (what a shader written before it declares).
    let storage = VOLUME_WGSL
        .replace(
            "var triangles: texture_2d_array<u32>",
            "var<storage, read> triangles: array<vec4<f32>>",
        )
        .replace(
            "bitcast<vec4<f32>>(textureLoad(triangles, vec2<u32>(3u * t + v % 3u, 0u), 0u, 0))",
            "triangles[3u * t + v % 3u]",
        );
    let bad = case("draw: Triangles(24)", &storage);
    assert!(
        bad.errors().iter().any(|d| d.code.as_str() == "binding-type"
            && d.message.contains(
                "the scene's triangle array `triangles` must be a `texture_2d_array<u32>`, a table of texels (`shaders/lib/table.wgsl`)"
            )),
        "{}",
        bad.dump()
    );
}

/// `shadow_casters` only means something on a pass that runs per light.
#[test]
fn shadow_casters_without_per_light() {
    let out = run(&Case {
        pipeline: &[(
            "params: [\"post.exposure\"]),",
            "params: [\"post.exposure\"], shadow_casters: true),",
        )],
        ..BASE
    });
    let d = out
        .errors()
        .into_iter()
        .find(|d| d.code.as_str() == "casters-without-lights")
        .unwrap_or_else(|| panic!("{}", out.dump()));
    assert!(
        d.message
            .contains("pass `post` runs for shadow-casting lights only but not per light"),
        "{}",
        d.message
    );
}

const LIGHT_VOLUME_WGSL: &str = r#"@group(0) @binding(0) var<storage, read> light_volumes: array<vec4<f32>>;

@vertex
fn vs_main(@builtin(vertex_index) v: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(light_volumes[v].xyz, 1.0);
}

@fragment
fn fs_main() -> @location(0) vec4<f32> {
    return vec4<f32>(1.0);
}
"#;

/// `draw: LightVolume` with the standard `light_volumes` binding checks clean in a per-light
/// pass; outside one it is `volume-without-lights`, and a `light_volumes` of the wrong type
/// is `binding-type`.
#[test]
fn light_volume_draws_need_per_light_passes() {
    let case = |extra: &str, shader: &str| {
        let edit = format!(
            "        Raster(name: \"vol\", shader: \"vol.wgsl\", draw: LightVolume, cull: Front{extra}, color: [Target(resource: \"color\", load: Load)]),\n    ],\n    output: \"out\""
        );
        let pipeline = [("    ],\n    output: \"out\"", edit.as_str())];
        run(&Case {
            pipeline: &pipeline,
            files: &[("shaders/vol.wgsl", shader)],
            ..BASE
        })
    };
    let ok = case(", per_light: [Point, Spot]", LIGHT_VOLUME_WGSL);
    assert!(ok.errors().is_empty(), "{}", ok.dump());
    let bare = case("", LIGHT_VOLUME_WGSL);
    let d = bare
        .errors()
        .into_iter()
        .find(|d| d.code.as_str() == "volume-without-lights")
        .unwrap_or_else(|| panic!("{}", bare.dump()));
    assert!(
        d.message.contains("pass `vol` draws light volumes but does not run per light"),
        "{}",
        d.message
    );
    let uniform = LIGHT_VOLUME_WGSL.replace(
        "var<storage, read> light_volumes: array<vec4<f32>>",
        "var<uniform> light_volumes: array<vec4<f32>, 3>",
    );
    let bad = case(", per_light: [Point]", &uniform);
    assert!(
        bad.errors().iter().any(|d| d.code.as_str() == "binding-type"
            && d.message
                .contains("the light-volume meshes `light_volumes` must be `var<storage, read>`")),
        "{}",
        bad.dump()
    );
}

/// 1e39 is finite text but +inf as the f32 it becomes on the GPU: `non-finite` at the
/// number, for a parameter default as for any pipeline number.
#[test]
fn a_number_beyond_f32_is_non_finite() {
    expect(
        Case {
            pipeline: &[(
                "Float(default: 1.0, min: 0.0, max: 8.0)",
                "Float(default: 1e39, min: 0.0, max: 8.0)",
            )],
            ..BASE
        },
        "non-finite",
        "`1e39` is not a finite 32-bit float",
        "pipelines/p.ron",
        4,
        41,
    );
}

/// An entry-point error naga gives no span for is located at what it names — here the
/// argument whose builtin needs a capability the `webgpu` profile lacks — not at the file's
/// first byte, and the note names the feature to require.
#[test]
fn entry_point_errors_are_located_at_the_argument() {
    let case = Case {
        profile: "webgpu",
        post: &[
            ("struct Params", "enable primitive_index;\n\nstruct Params"),
            (
                "fn fs_main(@location(0) uv: vec2<f32>)",
                "fn fs_main(@location(0) uv: vec2<f32>, @builtin(primitive_index) p: u32)",
            ),
        ],
        ..BASE
    };
    let out = run(&case);
    let line = apply(POST_WGSL, case.post)
        .lines()
        .position(|l| l.starts_with("fn fs_main"))
        .unwrap()
        + 1;
    expect(
        case,
        "shader-validation",
        "Entry point fs_main at Fragment is invalid",
        "shaders/post.wgsl",
        line,
        40,
    );
    assert!(
        out.dump()
            .contains("PRIMITIVE_INDEX needs the wgpu feature `PRIMITIVE_INDEX`: add `PrimitiveIndex`"),
        "{}",
        out.dump()
    );
}

/// A capability a `requires` feature provides is named by that feature, as `requires` takes
/// it (f16 on a profile without `ShaderF16`).
#[test]
fn a_missing_capability_names_the_feature_to_require() {
    let case = Case {
        post: &[
            ("struct Params", "enable f16;\n\nstruct Params"),
            (
                "    return textureSample",
                "    let h: f16 = 1.0h;\n    return f32(h) * textureSample",
            ),
        ],
        profile: "gl",
        ..BASE
    };
    let out = run(&case);
    assert!(
        out.dump()
            .contains("FLOAT16 needs the wgpu feature `SHADER_F16`: add `ShaderF16` to the `requires`"),
        "{}",
        out.dump()
    );
}

/// An operation only fragment shaders may use, in a function the vertex stage calls, is
/// located at the statement (`discard`), not at the entry point.
#[test]
fn discard_outside_a_fragment_shader_is_located_at_the_statement() {
    let scene = SCENE_WGSL
        .replace(
            "@vertex",
            "fn clip(x: f32) -> f32 {\n    if x > 100.0 {\n        discard;\n    }\n    return x;\n}\n\n@vertex",
        )
        .replace("out.clip = vec4<f32>(position, 1.0);", "out.clip = vec4<f32>(position, clip(1.0));");
    let line = scene.lines().position(|l| l.trim() == "discard;").unwrap() + 1;
    expect(
        Case {
            files: &[("shaders/scene.wgsl", &scene)],
            ..BASE
        },
        "shader-validation",
        "Entry point vs_main at Vertex is invalid",
        "shaders/scene.wgsl",
        line,
        9,
    );
}

#[test]
fn layer_rep_needs_a_repeat_pass() {
    expect(
        Case {
            pipeline: &[("depth: \"depth\"", "depth: Depth(resource: \"depth\", layer: Rep(0))")],
            ..BASE
        },
        "layer-select",
        "`layer: Rep(..)` needs a pass with `repeat`",
        "pipelines/p.ron",
        15,
        78,
    );
}

#[test]
fn repeat_beyond_the_layers_it_writes() {
    expect(
        Case {
            pipeline: &[
                (
                    "\"depth\": Texture(format: Depth32Float)",
                    "\"depth\": Texture(format: Depth32Float, layers: 2, view: D2Array)",
                ),
                ("depth: \"depth\"", "depth: Depth(resource: \"depth\", layer: Rep(0)), repeat: 3"),
            ],
            ..BASE
        },
        "layer-select",
        "`repeat` runs 3 times, writing layers 0..=2 of `depth`, which has 2",
        "pipelines/p.ron",
        15,
        127,
    );
}

#[test]
fn repeat_by_a_parameter_that_is_not_an_int() {
    expect(
        Case {
            pipeline: &[
                (
                    "\"depth\": Texture(format: Depth32Float)",
                    "\"depth\": Texture(format: Depth32Float, layers: 2, view: D2Array)",
                ),
                (
                    "depth: \"depth\"",
                    "depth: Depth(resource: \"depth\", layer: Rep(0)), repeat: Param(\"post.exposure\")",
                ),
            ],
            ..BASE
        },
        "layer-select",
        "`repeat` needs an Int parameter; `post.exposure` is not one",
        "pipelines/p.ron",
        15,
        127,
    );
}

#[test]
fn a_repeat_pass_reading_the_layer_it_writes() {
    expect(
        Case {
            pipeline: &[
                (
                    "\"color\": Texture(format: Rgba16Float)",
                    "\"color\": Texture(format: Rgba16Float, layers: 2, view: D2Array)",
                ),
                (
                    "color: [\"color\"], depth: \"depth\"",
                    "reads: [Layer(\"color\", Rep(0))], color: [Target(resource: \"color\", layer: Rep(0))], depth: \"depth\", repeat: 2",
                ),
            ],
            ..BASE
        },
        "layer-select",
        "pass `scene` reads the layer of `color` it writes (`Rep(0)`)",
        "pipelines/p.ron",
        15,
        76,
    );
}

#[test]
fn a_per_pixel_buffer_takes_no_data() {
    expect(
        Case {
            pipeline: &[(
                "\"out\": Texture(format: Rgba8Unorm),",
                "\"out\": Texture(format: Rgba8Unorm),\n        \"lists\": Buffer(size: 16, per_pixel: true, data: U32([0, 0, 0, 0])),",
            )],
            ..BASE
        },
        "conflicting-keys",
        "`lists` is `per_pixel`: its size follows the viewport, so no `data` can fill it",
        "pipelines/p.ron",
        13,
        58,
    );
}

/// Two names that bind to one shader identifier (`.` becomes `_`) are ambiguous; the second
/// declared is the one located, the first named beside it.
#[test]
fn names_binding_to_one_shader_identifier() {
    expect(
        Case {
            pipeline: &[(
                "\"linear\": Sampler(filter: Linear),",
                "\"linear\": Sampler(filter: Linear),\n        \"post_exposure\": Sampler(filter: Linear),",
            )],
            ..BASE
        },
        "ambiguous-name",
        "`post_exposure` and `post.exposure` both bind to the shader name `post_exposure`",
        "pipelines/p.ron",
        4,
        9,
    );
}
