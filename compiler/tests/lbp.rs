//! The LBP language: same IR as RON for the bundled pipelines, lossless conversion both ways,
//! an idempotent formatter that keeps comments, located errors, and no panics on any input.

mod common;

use common::*;
use lightbench_compiler::front::{lbp, ron};
use lightbench_compiler::ir::Pipeline;
use lightbench_compiler::Session;

fn parse(name: &str, text: &str) -> (Option<Pipeline>, Session) {
    let mut s = Session::new();
    let p = s.parse_pipeline(name, text.to_string());
    (p, s)
}

fn parse_ok(name: &str, text: &str) -> Pipeline {
    let (p, s) = parse(name, text);
    assert!(!s.diags.has_errors(), "{}\n{text}", s.render());
    p.expect("pipeline")
}

#[test]
fn bundled_pipelines_ron_and_lbp_give_the_same_ir() {
    let dir = repo_root().join("pipelines");
    let mut pairs = 0;
    for f in lightbench_compiler::pipeline_files(&dir).unwrap() {
        if f.extension().and_then(|e| e.to_str()) != Some("ron") {
            continue;
        }
        let lbp_path = f.with_extension("lbp");
        assert!(lbp_path.is_file(), "{} has no .lbp twin", f.display());
        let ron_text = std::fs::read_to_string(&f).unwrap();
        let lbp_text = std::fs::read_to_string(&lbp_path).unwrap();
        // By their paths: a pipeline that uses another finds it beside itself.
        let (ron_name, lbp_name) = (f.display().to_string(), lbp_path.display().to_string());
        let from_ron = parse_ok(&ron_name, &ron_text);
        let from_lbp = parse_ok(&lbp_name, &lbp_text);
        assert!(from_ron.same_as(&from_lbp), "{}: RON and LBP differ", f.display());
        // RON -> LBP -> RON -> IR is the same IR.
        let as_lbp = lbp::print::print(&from_ron, Some(&ron_text));
        let back = ron::print::print(&parse_ok(&lbp_name, &as_lbp), Some(&as_lbp));
        assert!(
            parse_ok(&ron_name, &back).same_as(&from_ron),
            "RON -> LBP -> RON changed the IR:\n{back}"
        );
        // The shipped .lbp is in canonical form, and formatting is idempotent.
        assert_eq!(
            lbp::print::print(&from_lbp, Some(&lbp_text)),
            lbp_text,
            "{} is not formatted",
            lbp_path.display()
        );
        pairs += 1;
    }
    assert!(pairs >= 1);
}

#[test]
fn formatting_keeps_comments_and_is_idempotent() {
    let src = "// top\npipeline p // trailing\n/* block\n   two */\ntexture out: Rgba8Unorm viewport\nfullscreen f \"f.wgsl\" {\n  // inside\n  color out\n}\n// before output\noutput out\n// last\n";
    let once = lbp::print::print(&parse_ok("p.lbp", src), Some(src));
    for c in [
        "// top",
        "// trailing",
        "// block",
        "// two",
        "    // inside",
        "// before output",
        "// last",
    ] {
        assert!(once.contains(c), "lost `{c}`:\n{once}");
    }
    let twice = lbp::print::print(&parse_ok("p.lbp", &once), Some(&once));
    assert_eq!(once, twice);
}

/// A comment stays with the item it was written before when the printer puts that item
/// elsewhere: a `let` written before the parameters is printed after the resources, in LBP and
/// in RON's `lets`, its comment with it (it went to the first parameter).
#[test]
fn a_moved_items_comment_moves_with_it() {
    let src = "pipeline t\n\n// The let's comment.\nlet fancy = variant(q, b)\n\n// The parameter's.\nparam x: Float = 1\n\n\
texture out: Rgba8Unorm viewport\n\nfullscreen f \"f.wgsl\" {\n    color out\n    when fancy\n}\n\n\
variant q = a {\n    option a\n    option b\n}\n\noutput out\n";
    let p = parse_ok("t.lbp", src);
    let printed = lbp::print::print(&p, Some(src));
    assert!(
        printed.contains("// The parameter's.\nparam x: Float = 1\n")
            && printed.contains("\n// The let's comment.\nlet fancy = variant(q, b)\n"),
        "{printed}"
    );
    let as_ron = ron::print::print(&p, Some(src));
    assert!(
        as_ron.contains("    lets: {\n        // The let's comment.\n        \"fancy\"")
            && as_ron.contains("    params: {\n        // The parameter's.\n        \"x\""),
        "{as_ron}"
    );
    assert_eq!(lbp::print::print(&parse_ok("t.lbp", &printed), Some(&printed)), printed);
}

/// A comment inside a pass body stays inside it through LBP -> RON -> LBP, and the text
/// comes back identical.
#[test]
fn comments_inside_a_pass_survive_conversion() {
    let src = std::fs::read_to_string(repo_root().join("pipelines/deferred.lbp")).unwrap();
    assert!(
        src.contains("{\n    // The normal in the layout's target, then albedo and emitted light."),
        "the bundled pipeline has a comment in a pass body"
    );
    let as_ron = ron::print::print(&parse_ok("p.lbp", &src), Some(&src));
    assert!(
        as_ron.contains("        Raster(\n            // The normal in the layout's target, then albedo and emitted light."),
        "the comment is inside the RON pass:\n{as_ron}"
    );
    let back = lbp::print::print(&parse_ok("p.ron", &as_ron), Some(&as_ron));
    assert_eq!(back, src, "LBP -> RON -> LBP is the identity");
}

#[test]
fn names_that_are_not_identifiers_are_quoted() {
    let src = "pipeline \"my pipe\"\n\ntexture \"out put\": Rgba8Unorm viewport\ntexture \"none\": R8Unorm 4x4\n\nfullscreen f \"f.wgsl\" {\n    reads \"none\"\n    color \"out put\"\n}\n\noutput \"out put\"\n";
    let p = parse_ok("p.lbp", src);
    assert_eq!(p.name.value, "my pipe");
    assert_eq!(lbp::print::print(&p, Some(src)), src);
}

/// (source, code, message fragment, line, column)
const BAD: &[(&str, &str, &str, usize, usize)] = &[
    (
        "pipeline p\ntexture out Rgba8Unorm viewport\noutput out\n",
        "lbp-syntax",
        "expected",
        2,
        13,
    ),
    (
        "pipeline p\ntexure out: Rgba8Unorm viewport\noutput out\n",
        "lbp-syntax",
        "expected end of file or `param`",
        2,
        1,
    ),
    (
        "pipeline p\nparam doc: Float = 1 \"unterminated\noutput out\n",
        "lbp-syntax",
        "expected",
        2,
        22,
    ),
    (
        "pipeline p\ntexture out: Rgba8Unorm viewport\ntexture out: R8Unorm 4x4\noutput out\n",
        "duplicate-name",
        "resource `out` is declared twice",
        3,
        9,
    ),
    (
        "pipeline p\nparam x: Int = 1.5\noutput out\n",
        "param-type",
        "Int parameter: expected a whole number, found the number 1.5",
        2,
        16,
    ),
    (
        "pipeline p\ntexture t: R8Unorm 99999999999x4\noutput t\n",
        "bad-number",
        "`99999999999` is not a 32-bit whole number",
        2,
        20,
    ),
    (
        "pipeline p\ntexture t: Rgba8Unrom viewport\noutput t\n",
        "unknown-value",
        "unknown texture format `Rgba8Unrom`",
        2,
        12,
    ),
    ("pipeline p\noption a\noutput out\n", "lbp-syntax", "expected", 2, 1),
    (
        "pipeline p\ncompute c \"c.wgsl\" {\n    color out\n    dispatch groups(1, 1, 1)\n    cull None\n}\noutput out\n",
        "misplaced",
        "`cull` is not a property of compute passes",
        5,
        5,
    ),
    (
        "pipeline p\nfullscreen f \"f.wgsl\" {\n    color out\n    color out\n}\noutput out\n",
        "duplicate-key",
        "`color` is given twice in pass `f`",
        4,
        5,
    ),
    (
        "pipeline p\nfullscreen f \"f.wgsl\" {\n    color out\n    when effect(Bloomm)\n}\noutput out\n",
        "unknown-effect",
        "unknown effect `Bloomm`",
        4,
        17,
    ),
    (
        "pipeline p\nfullscreen f \"f.wgsl\" {\n    color out\n    when lite(Point)\n}\noutput out\n",
        "unknown-kind",
        "unknown condition `lite`",
        4,
        10,
    ),
    (
        "pipeline p\ntexture out: Rgba8Unorm viewport\n",
        "missing-key",
        "pipeline is missing required key `output`",
        3,
        1,
    ),
    (
        "pipeline p\ncompute c \"c.wgsl\" {\n    writes out\n}\noutput out\n",
        "missing-key",
        "pass `c` is missing required key `dispatch`",
        2,
        9,
    ),
    (
        "pipeline p\nvariant v = a {\n    option a requires(Multiveiw)\n}\noutput out\n",
        "unknown-value",
        "unknown feature `Multiveiw`",
        3,
        23,
    ),
    (
        "pipeline p\nparam s: Float = 1 \"bad \\q escape\"\noutput out\n",
        "lbp-syntax",
        "unknown escape `\\q`",
        2,
        20,
    ),
    (
        "pipeline p\nfullscreen f \"f.wgsl\" {\n    color out compare Less\n}\noutput out\n",
        "misplaced",
        "`compare` does not apply to a color target",
        3,
        15,
    ),
    (
        "pipeline p\nparam m: enum(a, b) = c\noutput out\n",
        "unknown-value",
        "`c` is not an option of this Enum",
        2,
        23,
    ),
    (
        "pipeline p\ntexture t: R8Unorm viewport*0\noutput t\n",
        "value-out-of-range",
        "viewport scale must be in (0, 16]",
        2,
        20,
    ),
    (
        "pipeline p\ntexture d: Depth32Float viewport\nfullscreen f \"f.wgsl\" {\n    depth d clear(2)\n}\noutput d\n",
        "value-out-of-range",
        "depth clear value `2` is outside 0..1",
        4,
        19,
    ),
    ("", "lbp-syntax", "expected `pipeline NAME`", 1, 1),
];

#[test]
fn bad_lbp_inputs_are_located() {
    let mut failures = vec![];
    for (i, (src, code, msg, line, col)) in BAD.iter().enumerate() {
        // Parsing and the declarations check: what needs no shader.
        let (p, mut s) = parse("bad.lbp", src);
        if let Some(p) = &p {
            lightbench_compiler::check::declarations::check(p, &lightbench_compiler::profile::Profile::vulkan(), &mut s.diags);
        }
        let hit = s.diags.list.iter().any(|d| {
            let loc = d.location(&s.sources).map(|(_, l, c)| (l, c));
            d.code == *code && d.message.contains(msg) && loc == Some((*line, *col))
        });
        if !hit {
            let got: Vec<String> = s
                .diags
                .list
                .iter()
                .map(|d| {
                    let (_, l, c) = d.location(&s.sources).unwrap_or_default();
                    format!("[{}] {l}:{c} {}", d.code, d.message)
                })
                .collect();
            failures.push(format!("case {i}: expected [{code}] {msg:?} at {line}:{col}, got {got:?}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(BAD.len() >= 12);
}

#[test]
fn semantic_errors_point_into_lbp_files() {
    // The same checks as for RON, located in the .lbp text.
    let dir = write_project(
        "lbp-sem",
        &[
            ("pipelines/p.lbp", "pipeline p\ntexture out: Rgba8Unorm viewport\nfullscreen f \"fill.wgsl\" {\n    reads missing\n    color out\n}\noutput out\n"),
            ("shaders/fill.wgsl", "@fragment\nfn fs_main() -> @location(0) vec4<f32> {\n    return vec4<f32>(1.0);\n}\n"),
        ],
    );
    let out = check_project(&dir, "pipelines/p.lbp", &lightbench_compiler::profile::Profile::vulkan(), None);
    let found = out.located();
    assert!(
        found.iter().any(|(c, m, f, l, co)| c == "unknown-resource"
            && m == "no resource named `missing`"
            && f == "pipelines/p.lbp"
            && (*l, *co) == (4, 11)),
        "{found:?}"
    );
}

mod generated {
    //! Random valid IRs: print as LBP (and RON), parse, same IR; the formatter is idempotent.

    use super::*;
    use lightbench_compiler::format::TextureFormat;
    use lightbench_compiler::ir::*;
    use lightbench_compiler::profile::{Feature, Limits};
    use lightbench_compiler::span::{Span, Spanned};
    use proptest::prelude::*;

    fn sp<T>(v: T) -> Spanned<T> {
        Spanned::new(v, Span::default())
    }

    fn ident() -> impl Strategy<Value = String> {
        "[a-z_][a-z0-9_]{0,5}(\\.[a-z][a-z0-9]{0,4})?"
    }

    /// Names, sometimes needing quotes.
    fn name() -> impl Strategy<Value = String> {
        prop_oneof![4 => ident(), 1 => "[ -~]{1,8}".prop_filter("no hash", |s| !s.contains('#'))]
    }

    /// Names of variant options, as a declaration accepts them: never `|`, which separates
    /// several (`a | b`), no blanks around (each named option is trimmed), never `_` (every
    /// other option, in a choice's arms).
    fn option_name() -> impl Strategy<Value = String> {
        name().prop_filter("no bar, no blanks around, not _", |s| !s.contains('|') && s.trim() == s && s != "_")
    }

    fn text() -> impl Strategy<Value = String> {
        "[ -~äé\\n\\t]{0,16}"
    }

    fn float() -> impl Strategy<Value = f64> {
        prop_oneof![-1e6..1e6f64, Just(0.0), Just(1.0), (-1000i32..1000).prop_map(|i| i as f64 / 8.0)]
    }

    /// A depth clear value: depth lies in 0..1 (others are refused where written).
    fn depth_value() -> impl Strategy<Value = f64> {
        prop_oneof![Just(0.0), Just(1.0), (0i32..=64).prop_map(|i| i as f64 / 64.0), 0.0..=1.0f64]
    }

    /// A preset's value as written: whole numbers stay whole, others stay floats.
    fn literal() -> impl Strategy<Value = Literal> {
        prop_oneof![
            (-1000i64..1000).prop_map(Literal::Int),
            (-1000i32..1000).prop_map(|i| Literal::Float(i as f64 / 8.0 + 0.0625)),
            any::<bool>().prop_map(Literal::Bool),
            proptest::collection::vec(float(), 2..=4).prop_map(Literal::Tuple),
        ]
    }

    fn kinds() -> impl Strategy<Value = Vec<LightKind>> {
        proptest::sample::subsequence(LightKind::ALL.to_vec(), 1..=3)
    }

    fn param(n: String) -> impl Strategy<Value = Param> {
        let ty = prop_oneof![
            Just(ParamType::Float),
            Just(ParamType::Int),
            Just(ParamType::Bool),
            Just(ParamType::Vec2),
            Just(ParamType::Vec3),
            Just(ParamType::Vec4),
            Just(ParamType::Color),
            proptest::collection::btree_set(name(), 1..4).prop_map(|s| ParamType::Enum(s.into_iter().collect())),
        ];
        (ty, any::<u64>(), proptest::option::of(text()), any::<bool>()).prop_flat_map(move |(ty, seed, doc, ranged)| {
            let value = |ty: &ParamType, seed: u64| -> BoxedStrategy<ParamValue> {
                match ty {
                    ParamType::Float => float().prop_map(ParamValue::Float).boxed(),
                    ParamType::Int => any::<i64>().prop_map(ParamValue::Int).boxed(),
                    ParamType::Bool => any::<bool>().prop_map(ParamValue::Bool).boxed(),
                    ParamType::Enum(opts) => Just(ParamValue::Enum(opts[seed as usize % opts.len()].clone())).boxed(),
                    t => proptest::collection::vec(float(), t.components().unwrap_or(1))
                        .prop_map(ParamValue::Vec)
                        .boxed(),
                }
            };
            let n = n.clone();
            (
                value(&ty, seed),
                proptest::option::of(value(&ty, seed / 3)),
                proptest::option::of(value(&ty, seed / 7)),
            )
                .prop_map(move |(d, lo, hi)| Param {
                    name: sp(n.clone()),
                    ty: sp(ty.clone()),
                    default: sp(d),
                    min: if ranged { lo.map(sp) } else { None },
                    max: if ranged { hi.map(sp) } else { None },
                    doc: doc.clone(),
                    span: Span::default(),
                })
        })
    }

    fn data() -> impl Strategy<Value = Option<Spanned<DataSource>>> {
        proptest::option::of(
            prop_oneof![
                name().prop_map(DataSource::File),
                proptest::collection::vec(float(), 0..4).prop_map(DataSource::F32),
                proptest::collection::vec(0u64..=u32::MAX as u64, 0..4).prop_map(DataSource::U32),
            ]
            .prop_map(sp),
        )
    }

    fn mip() -> impl Strategy<Value = Spanned<MipSel>> {
        prop_oneof![(0u32..12).prop_map(MipSel::Level), (-3i32..3).prop_map(MipSel::Rep)].prop_map(sp)
    }

    fn resource(n: String) -> impl Strategy<Value = Resource> {
        let texture = (
            proptest::sample::select(TextureFormat::ALL.to_vec()),
            prop_oneof![
                (1u32..5000, 1u32..5000).prop_map(|(w, h)| SizeSpec::Fixed { width: w, height: h }),
                (1u32..64).prop_map(|s| SizeSpec::Viewport { scale: s as f64 / 4.0 }),
                name().prop_map(SizeSpec::Param),
                name().prop_map(SizeSpec::ViewportParam)
            ],
            1u32..300,
            proptest::sample::select(vec![ViewDim::D2, ViewDim::D2Array, ViewDim::Cube]),
            1u32..12,
            proptest::option::of(kinds()),
            any::<bool>(),
            any::<bool>(),
            data(),
        )
            .prop_map(|(f, size, layers, view, mips, per, history, external, data)| {
                ResourceKind::Texture(TextureDesc {
                    format: sp(f),
                    size: sp(size),
                    layers: sp(layers),
                    view: sp(view),
                    mips: sp(mips),
                    per_light: per.map(sp),
                    history,
                    external,
                    data,
                })
            });
        let buffer = (
            1u64..1 << 40,
            proptest::option::of(kinds()),
            any::<bool>(),
            any::<bool>(),
            data(),
            any::<bool>(),
        )
            .prop_map(|(size, per, history, external, data, per_pixel)| {
                ResourceKind::Buffer(BufferDesc {
                    size: sp(size),
                    per_pixel,
                    per_light: per.map(sp),
                    history,
                    external,
                    data,
                })
            });
        let valid = proptest::option::of((float(), float()).prop_map(|(a, b)| sp((a.min(b), a.max(b)))));
        (prop_oneof![3 => texture, 1 => buffer], valid).prop_map(move |(kind, valid)| Resource {
            name: sp(n.clone()),
            kind,
            valid,
            span: Span::default(),
        })
    }

    fn cond() -> impl Strategy<Value = Condition> {
        let leaf = prop_oneof![
            proptest::sample::select(LightKind::ALL.to_vec()).prop_map(Condition::Light),
            proptest::sample::select(Effect::ALL.to_vec()).prop_map(Condition::Effect),
            Just(Condition::Reflective),
            name().prop_map(|n| Condition::Toggle(sp(n))),
            (name(), option_name()).prop_map(|(a, b)| Condition::Variant(sp(a), sp(b))),
        ];
        leaf.prop_recursive(3, 12, 3, |inner| {
            prop_oneof![
                inner.clone().prop_map(|c| Condition::Not(Box::new(sp(c)))),
                proptest::collection::vec(inner.clone(), 0..3).prop_map(|cs| Condition::All(cs.into_iter().map(sp).collect())),
                proptest::collection::vec(inner, 0..3).prop_map(|cs| Condition::Any(cs.into_iter().map(sp).collect())),
            ]
        })
    }

    fn layer() -> impl Strategy<Value = LayerSel> {
        prop_oneof![
            Just(LayerSel::Base),
            Just(LayerSel::Face),
            Just(LayerSel::All),
            (0u32..10).prop_map(LayerSel::Index),
            (-3i32..3).prop_map(LayerSel::Rep)
        ]
    }

    fn file() -> impl Strategy<Value = String> {
        prop_oneof![4 => "[a-z_]{1,6}\\.wgsl", 1 => "[a-z]{1,4}\\.frag", 1 => "[a-z]{1,4}\\.comp"]
    }

    fn entry() -> impl Strategy<Value = String> {
        prop_oneof![
            "[a-z_][a-z0-9_]{0,6}",
            Just("fs_main".to_string()),
            Just("main".to_string()),
            Just("vs_main".to_string())
        ]
    }

    fn targets() -> impl Strategy<Value = Targets> {
        let color = proptest::collection::vec(
            (
                name(),
                prop_oneof![
                    Just(Load::Load),
                    (float(), float(), float(), float()).prop_map(|(a, b, c, d)| Load::Clear([a, b, c, d]))
                ],
                proptest::option::of(proptest::sample::select(vec![Blend::Add, Blend::Alpha, Blend::Multiply])),
                layer(),
                mip(),
            )
                .prop_map(|(r, load, blend, layer, mip)| ColorTarget {
                    resource: sp(r),
                    load,
                    blend: blend.map(sp),
                    layer,
                    mip,
                    span: Span::default(),
                }),
            0..3,
        );
        let depth = proptest::option::of(
            (
                name(),
                prop_oneof![Just(Load::Load), depth_value().prop_map(Load::Clear)],
                proptest::sample::select(CompareFn::ALL.to_vec()),
                any::<bool>(),
                layer(),
                mip(),
            )
                .prop_map(|(r, load, compare, write, layer, mip)| DepthTarget {
                    resource: sp(r),
                    load,
                    compare,
                    write,
                    layer,
                    mip,
                    span: Span::default(),
                }),
        );
        (color, depth).prop_map(|(color, depth)| Targets { color, depth })
    }

    fn kind() -> impl Strategy<Value = PassKind> {
        let r = |f: &str, e: &str| ShaderRef {
            file: sp(f.to_string()),
            entry: sp(e.to_string()),
        };
        let raster = (
            proptest::sample::select(vec![CullMode::None, CullMode::Front, CullMode::Back]),
            1u32..8,
            proptest::option::of(2u32..7),
            proptest::option::of(1u32..100),
            targets(),
            (file(), file(), entry(), entry(), any::<u8>()),
        )
            .prop_map(move |(cull, instances, mv, verts, targets, (f1, f2, e1, e2, pick))| {
                let fragment = match pick % 3 {
                    0 => None,
                    1 => Some(r(&f1, &e2)),
                    _ => Some(r(&f2, &e2)),
                };
                PassKind::Raster(Raster {
                    vertex: r(&f1, &e1),
                    fragment,
                    targets,
                    draw: match (verts, pick % 4) {
                        (Some(n), 0 | 1) => Draw::Vertices(n),
                        (Some(n), _) => Draw::Triangles(n),
                        (None, k) => [Draw::Scene, Draw::Transparent][k as usize % 2].clone(),
                    },
                    cull,
                    instances: sp(instances),
                    multiview: mv.map(sp),
                })
            });
        let fullscreen = (targets(), file(), entry()).prop_map(move |(targets, f, e)| {
            PassKind::Fullscreen(Fullscreen {
                fragment: r(&f, &e),
                targets,
            })
        });
        let dispatch = prop_oneof![
            (0u32..64, 0u32..64, 0u32..64).prop_map(|(x, y, z)| Dispatch::Groups(x, y, z)),
            name().prop_map(|n| Dispatch::Size(sp(n)))
        ];
        let compute = (dispatch, file(), entry()).prop_map(move |(dispatch, f, e)| {
            PassKind::Compute(Compute {
                entry: r(&f, &e),
                dispatch: sp(dispatch),
            })
        });
        prop_oneof![raster, fullscreen, compute]
    }

    fn pass(n: String) -> impl Strategy<Value = Pass> {
        let common = (
            proptest::collection::vec(
                (name(), 0u8..5, mip(), 0u32..8, -3i32..3).prop_map(|(n, k, m, l, d)| match k {
                    0 => Read::Current(sp(n)),
                    1 => Read::Prev(sp(n)),
                    2 => Read::Mip(sp(n), m),
                    3 => Read::Layer(sp(n), sp(LayerSel::Index(l))),
                    _ => Read::Layer(sp(n), sp(LayerSel::Rep(d))),
                }),
                0..3,
            ),
            proptest::collection::vec(name().prop_map(sp), 0..2),
            proptest::collection::vec(name().prop_map(sp), 0..3),
            prop_oneof![3 => Just("params".to_string()), 1 => name()],
            proptest::collection::vec((name(), name()).prop_map(|(a, b)| (sp(a), sp(b))), 0..2),
            proptest::option::of(cond()),
            proptest::option::of(kinds()),
            any::<bool>(),
        );
        let values = prop_oneof![
            float().prop_map(ParamValue::Float),
            any::<bool>().prop_map(ParamValue::Bool),
            proptest::collection::vec(float(), 2..=4).prop_map(ParamValue::Vec),
        ];
        let extra = (
            proptest::collection::vec((name(), values).prop_map(|(k, v)| (sp(k), sp(v))), 0..3),
            proptest::option::of((0u32..12, 0u32..12).prop_map(|(from, to)| sp(MipRange { from, to }))),
            any::<bool>(),
            any::<bool>(),
            proptest::option::of(prop_oneof![(1u32..16).prop_map(Repeat::Times), name().prop_map(Repeat::Param)]),
        );
        let constant = prop_oneof![
            float().prop_map(Constant::Number),
            any::<bool>().prop_map(Constant::Bool),
            name().prop_map(Constant::Param),
            (name(), name()).prop_map(|(v, o)| Constant::Variant(v, o)),
        ];
        let constants = proptest::collection::vec((name(), constant).prop_map(|(k, c)| (sp(k), sp(c))), 0..3);
        (kind(), common, extra, constants).prop_map(move |(kind, c, (values, per_mip, always, shadow_casters, repeat), constants)| {
            let (reads, writes, params, block, bind, when, per_light, per_face) = c;
            Pass {
                name: sp(n.clone()),
                kind,
                reads,
                writes,
                params,
                param_block: sp(block),
                bind,
                when: when.map(sp),
                per_light: per_light.map(sp),
                per_face,
                shadow_casters,
                values,
                constants,
                per_mip,
                repeat: repeat.map(sp),
                always,
                // Choices are lowered to copies: the round trip of their forms is tested on files.
                choice: None,
                from: None,
                origin: None,
                span: Span::default(),
            }
        })
    }

    fn variant(n: String) -> impl Strategy<Value = Variant> {
        let option = |n: String| {
            (
                proptest::collection::vec(proptest::sample::select(Feature::ALL.to_vec()).prop_map(sp), 0..3),
                proptest::collection::vec(
                    (proptest::sample::select(Limits::NAMES.to_vec()), 0u64..100000).prop_map(|(k, v)| (sp(k.to_string()), sp(v))),
                    0..2,
                ),
                proptest::option::of(name().prop_map(sp)),
                proptest::collection::vec((name(), file()).prop_map(|(a, b)| (sp(a), sp(b))), 0..2),
                proptest::option::of(text()),
                proptest::collection::vec((name(), literal()).prop_map(|(k, v)| (sp(k), sp(v))), 0..3),
                any::<bool>(),
            )
                .prop_map(move |(requires, limits, fallback, shaders, doc, params, jitter)| VariantOption {
                    name: sp(n.clone()),
                    requires,
                    limits,
                    fallback,
                    shaders,
                    params,
                    jitter,
                    doc,
                    span: Span::default(),
                })
        };
        (
            proptest::collection::btree_set(option_name(), 0..4),
            option_name(),
            proptest::option::of(text()),
        )
            .prop_flat_map(move |(opts, default, doc)| {
                let n = n.clone();
                let opts: Vec<BoxedStrategy<VariantOption>> = opts.into_iter().map(|o| option(o).boxed()).collect();
                opts.prop_map(move |options| Variant {
                    name: sp(n.clone()),
                    options,
                    default: sp(default.clone()),
                    doc: doc.clone(),
                    span: Span::default(),
                })
            })
    }

    fn pipeline() -> impl Strategy<Value = Pipeline> {
        let names = |r: std::ops::Range<usize>| proptest::collection::btree_set(name(), r).prop_map(|s| s.into_iter().collect::<Vec<_>>());
        (name(), names(0..4), names(0..3), names(0..5), names(0..4), names(0..3), name()).prop_flat_map(
            |(pname, ps, ss, rs, passes, vs, out)| {
                let params: Vec<BoxedStrategy<Param>> = ps.into_iter().map(|n| param(n).boxed()).collect();
                let samplers: Vec<BoxedStrategy<SamplerDecl>> = ss
                    .into_iter()
                    .map(|n| {
                        (
                            proptest::sample::select(vec![FilterMode::Nearest, FilterMode::Linear]),
                            proptest::sample::select(vec![FilterMode::Nearest, FilterMode::Linear]),
                            proptest::sample::select(vec![AddressMode::ClampToEdge, AddressMode::Repeat, AddressMode::MirrorRepeat]),
                            proptest::option::of(proptest::sample::select(CompareFn::ALL.to_vec())),
                        )
                            .prop_map(move |(filter, mipmap, address, compare)| SamplerDecl {
                                name: sp(n.clone()),
                                filter,
                                mipmap,
                                address,
                                compare,
                                span: Span::default(),
                            })
                            .boxed()
                    })
                    .collect();
                let resources: Vec<BoxedStrategy<Resource>> = rs.into_iter().map(|n| resource(n).boxed()).collect();
                let passes: Vec<BoxedStrategy<Pass>> = passes.into_iter().map(|n| pass(n).boxed()).collect();
                let variants: Vec<BoxedStrategy<Variant>> = vs.into_iter().map(|n| variant(n).boxed()).collect();
                let (pname, out) = (pname.clone(), out.clone());
                (params, samplers, resources, passes, variants).prop_map(move |(params, samplers, resources, passes, variants)| Pipeline {
                    name: sp(pname.clone()),
                    params,
                    samplers,
                    resources,
                    passes,
                    variants,
                    lets: vec![],
                    // Some pipelines name their output as the HDR output too: both keys round-trip.
                    hdr_output: (out.len() % 2 == 0).then(|| sp(out.clone())),
                    output: sp(out.clone()),
                    always: out.len() % 3 == 0,
                    jitter: pname.len() % 2 == 0,
                    written: None,
                    span: Span::default(),
                })
            },
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(192))]

        #[test]
        fn lbp_print_parse_round_trips(p in pipeline()) {
            let text = lbp::print::print(&p, None);
            let back = parse_ok("gen.lbp", &text);
            prop_assert!(back.same_as(&p), "LBP round trip changed the IR:\n{}", text);
            // fmt is idempotent.
            let again = lbp::print::print(&back, Some(&text));
            prop_assert_eq!(&again, &text);
            // And through RON.
            let ron_text = ron::print::print(&p, None);
            let from_ron = parse_ok("gen.ron", &ron_text);
            prop_assert!(from_ron.same_as(&p), "RON round trip changed the IR:\n{}", ron_text);
        }

        #[test]
        fn lbp_parser_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
            let text = String::from_utf8_lossy(&bytes).into_owned();
            let (_, s) = parse("fuzz.lbp", &text);
            let _ = s.render();
        }

        #[test]
        fn mutated_lbp_never_panics(cut in 0usize..4000, pos in 0usize..4000, c in proptest::sample::select(vec!['(', ')', '"', ',', ':', '{', '}', 'x', '1', ' ', '/', '\\', '.', '=', '\n'])) {
            let src = std::fs::read_to_string(repo_root().join("pipelines/deferred.lbp")).unwrap();
            let mut chars: Vec<char> = src.chars().collect();
            let pos = pos % chars.len();
            chars[pos] = c;
            let text: String = chars[..cut.min(chars.len())].iter().collect();
            let (_, s) = parse("fuzz.lbp", &text);
            let _ = s.render();
        }
    }
}

/// A tuple wrong inside is not "expected a tuple, found `(`": it says what a tuple holds,
/// over the whole tuple.
#[test]
fn a_malformed_tuple_says_what_it_must_hold() {
    let text =
        "pipeline p\ntexture out: Rgba8Unorm viewport\nfullscreen f \"fill.wgsl\" {\n    color out clear(0, 0, 0 1)\n}\noutput out\n";
    let (_, s) = parse("p.lbp", text);
    let d = &s.diags.list[0];
    assert_eq!(d.message, "expected numbers separated by commas in this tuple, e.g. `(0, 0, 0, 1)`");
    assert_eq!(d.location(&s.sources).map(|(_, l, c)| (l, c)), Some((4, 20)));
    assert_eq!(&text[d.labels[0].span.range()], "(0, 0, 0 1)");
}

/// Several elements in an arm without parentheses: the syntax error says how to write them.
#[test]
fn an_arm_of_several_elements_without_parentheses_gets_a_hint() {
    for (arms, col) in [("x: a, b, y: a", 29), ("x: a, b", 30)] {
        let text = format!(
            "pipeline p\ntexture out: Rgba8Unorm viewport\nfullscreen f \"fill.wgsl\" {{\n    color out\n    reads match(v) {{ {arms} }}\n}}\noutput out\n"
        );
        let (_, s) = parse("p.lbp", &text);
        let d = &s.diags.list[0];
        assert_eq!(d.code, "lbp-syntax");
        assert_eq!(d.location(&s.sources).map(|(_, l, c)| (l, c)), Some((5, col)), "{}", d.message);
        assert!(d.message.starts_with("expected `:`"), "{}", d.message);
        assert!(
            d.notes.iter().any(|n| n.contains("in parentheses: `x: (a, b), y: c`")),
            "{:?}",
            d.notes
        );
    }
    // Elsewhere a missing `:` gets no such hint.
    let (_, s) = parse("p.lbp", "pipeline p\nparam a Float = 1\n");
    assert!(
        s.diags.list[0].notes.iter().all(|n| !n.contains("parentheses")),
        "{:?}",
        s.diags.list[0].notes
    );
}

/// A misspelt keyword gets the nearest keyword allowed where it stands, and the list of what
/// was expected names each thing once.
#[test]
fn misspelt_keywords_get_a_suggestion() {
    let text =
        "pipeline p\ntexture out: Rgba8Unorm viewport\nfullscreen f \"fill.wgsl\" {\n    color out\n    param exposure\n}\noutput out\n";
    let (_, s) = parse("p.lbp", text);
    let d = &s.diags.list[0];
    assert_eq!(d.code, "lbp-syntax");
    assert_eq!(d.location(&s.sources).map(|(_, l, c)| (l, c)), Some((5, 5)));
    assert!(d.notes.iter().any(|n| n == "did you mean `params`?"), "{:?}", d.notes);
    let words: Vec<&str> = d.message.split(" or ").collect();
    let mut unique = words.clone();
    unique.dedup();
    assert_eq!(words.len(), unique.len(), "no repeats: {}", d.message);
    let (_, s) = parse("p.lbp", "pipeline p\ntextur out: Rgba8Unorm viewport\noutput out\n");
    assert!(
        s.diags.list[0].notes.iter().any(|n| n == "did you mean `texture`?"),
        "{:?}",
        s.diags.list[0]
    );
}

/// A missing `}` is reported where parsing stopped, with the unclosed `{` as a second label.
#[test]
fn a_missing_brace_points_at_the_unclosed_one() {
    let text = "pipeline p\ntexture out: Rgba8Unorm viewport\nfullscreen f \"fill.wgsl\" {\n    color out\n\noutput out\n";
    let (_, s) = parse("p.lbp", text);
    let d = &s.diags.list[0];
    assert_eq!(d.location(&s.sources).map(|(_, l, c)| (l, c)), Some((6, 1)));
    let brace = d.labels.iter().find(|l| !l.primary).expect("a secondary label");
    assert_eq!(brace.message, "this `{` is not closed");
    assert_eq!(s.sources.get(brace.span.file).line_col(brace.span.start as usize), (3, 26));
}

/// `Enum(..)` is accepted as `enum(..)` is (the RON spelling of a type, like `Float`).
#[test]
fn enum_types_take_either_spelling() {
    let text = |kw: &str| format!("pipeline p\nparam m: {kw}(a, b) = b \"mode\"\ntexture out: Rgba8Unorm viewport\noutput out\n");
    let lower = parse_ok("p.lbp", &text("enum"));
    let upper = parse_ok("p.lbp", &text("Enum"));
    assert!(lower.same_as(&upper));
    assert_eq!(
        lower.params[0].ty.value,
        lightbench_compiler::ir::ParamType::Enum(vec!["a".into(), "b".into()])
    );
}

/// The README's "every LBP form" file parses as written and converts to RON and back to
/// the same pipeline.
#[test]
fn the_readme_shows_every_form_and_it_parses() {
    let readme = common::manual();
    let after = readme.split("Every LBP form in one file").nth(1).expect("the section");
    let block = after.split("```\n").nth(1).expect("its code block");
    assert!(block.starts_with("pipeline every_form"), "{block}");
    let p = parse_ok("every.lbp", block);
    let as_ron = ron::print::print(&p, Some(block));
    assert!(parse_ok("every.ron", &as_ron).same_as(&p), "{as_ron}");
    // The grammar's keywords each appear in the block.
    let grammar = std::fs::read_to_string(repo_root().join("compiler/src/front/lbp/lbp.pest")).unwrap();
    let keywords: std::collections::BTreeSet<&str> = grammar
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .flat_map(|l| l.split('"').skip(1).step_by(2))
        .filter(|w| w.len() > 1 && w.chars().all(|c| c.is_ascii_alphabetic() || c == '_'))
        .collect();
    // A pipeline that uses another is shown (and tested: tests/compose.rs) in its own section.
    let uses = readme
        .split("A pipeline that uses the bundled one")
        .nth(1)
        .and_then(|a| a.split("```\n").nth(1))
        .expect("the `use` example");
    let missing: Vec<&&str> = keywords.iter().filter(|k| !block.contains(**k) && !uses.contains(**k)).collect();
    assert!(
        missing.is_empty(),
        "the manual's every-form file and `use` example lack {missing:?}"
    );
}
