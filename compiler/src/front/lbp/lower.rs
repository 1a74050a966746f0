//! LBP parse tree -> IR, with the same defaults and checks as the RON front end.

use super::Rule;
use crate::diag::{suggestion_note, Diagnostic, Diagnostics};
use crate::format::TextureFormat;
use crate::ir::*;
use crate::profile::Feature;
use crate::span::{FileId, Span, Spanned};
use pest::iterators::{Pair, Pairs};

type P<'i> = Pair<'i, Rule>;
type Res<T> = Option<T>;

/// A color or depth target as written; color targets ignore `compare` and `write`.
struct Target {
    resource: Spanned<String>,
    load: LoadOp,
    blend: Option<Spanned<Blend>>,
    layer: LayerSel,
    compare: CompareFn,
    write: bool,
    span: Span,
}

/// Children of a pair without punctuation (which exists as rules only for error positions).
trait Kids<'i> {
    fn kids(self) -> std::iter::Filter<Pairs<'i, Rule>, fn(&P<'i>) -> bool>;
}

impl<'i> Kids<'i> for P<'i> {
    fn kids(self) -> std::iter::Filter<Pairs<'i, Rule>, fn(&P<'i>) -> bool> {
        fn keep(p: &P) -> bool {
            !matches!(
                p.as_rule(),
                Rule::colon | Rule::equals | Rule::open_brace | Rule::close_brace | Rule::open_paren | Rule::close_paren
            )
        }
        self.into_inner().filter(keep as fn(&P<'i>) -> bool)
    }
}

/// Remove and return the property of this rule, if the pass has it.
fn take<'i>(props: &mut Vec<P<'i>>, r: Rule) -> Option<P<'i>> {
    props.iter().position(|p| p.as_rule() == r).map(|i| props.remove(i))
}

pub struct Lowerer<'d> {
    pub file: FileId,
    pub diags: &'d mut Diagnostics,
}

/// Undo string escapes: `\"`, `\\`, `\n`, `\t`, `\r`, `\0`, `\u{XXXX}`.
pub fn unescape(s: &str) -> Result<String, String> {
    let mut out = String::new();
    let mut it = s.chars();
    while let Some(c) = it.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match it.next() {
            Some('"') => out.push('"'),
            Some('\\') => out.push('\\'),
            Some('n') => out.push('\n'),
            Some('t') => out.push('\t'),
            Some('r') => out.push('\r'),
            Some('0') => out.push('\0'),
            Some('u') => {
                let rest: String = it.by_ref().take_while(|c| *c != '}').collect();
                let hex = rest.strip_prefix('{').ok_or("invalid unicode escape, expected `\\u{XXXX}`")?;
                let ch = u32::from_str_radix(hex, 16)
                    .ok()
                    .and_then(char::from_u32)
                    .ok_or("invalid unicode escape")?;
                out.push(ch);
            }
            Some(o) => return Err(format!("unknown escape `\\{o}`")),
            None => return Err("unterminated escape".into()),
        }
    }
    Ok(out)
}

impl Lowerer<'_> {
    fn span(&self, p: &P) -> Span {
        let s = p.as_span();
        Span::new(self.file, s.start(), s.end())
    }

    fn err(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    fn string(&mut self, p: P) -> Res<Spanned<String>> {
        let span = self.span(&p);
        let inner = p.kids().next().map(|i| i.as_str()).unwrap_or("");
        match unescape(inner) {
            Ok(s) => Some(Spanned::new(s, span)),
            Err(e) => {
                self.err(Diagnostic::error("lbp-syntax", e, span));
                None
            }
        }
    }

    /// A `name`: dotted identifier or quoted string.
    fn name(&mut self, p: P) -> Res<Spanned<String>> {
        let span = self.span(&p);
        let inner = p.kids().next()?;
        match inner.as_rule() {
            Rule::string => self.string(inner),
            _ => Some(Spanned::new(inner.as_str().to_string(), span)),
        }
    }

    fn names(&mut self, p: P) -> Vec<Spanned<String>> {
        p.kids().filter_map(|n| self.name(n)).collect()
    }

    fn uint(&mut self, p: &P) -> Res<Spanned<u32>> {
        match p.as_str().parse::<u32>() {
            Ok(v) => Some(Spanned::new(v, self.span(p))),
            Err(_) => {
                self.err(Diagnostic::error(
                    "bad-number",
                    format!("`{}` is not a 32-bit whole number", p.as_str()),
                    self.span(p),
                ));
                None
            }
        }
    }

    fn number(&mut self, p: &P) -> Res<f64> {
        match p.as_str().parse::<f64>() {
            Ok(v) if v.is_finite() => Some(v),
            _ => {
                self.err(Diagnostic::error(
                    "bad-number",
                    format!("`{}` is not a finite number", p.as_str()),
                    self.span(p),
                ));
                None
            }
        }
    }

    /// A PascalCase IR enum value (`Rgba16Float`, `Point`, `LessEqual`).
    fn word<T>(&mut self, p: &P, what: &str, names: &[&str], parse: impl Fn(&str) -> Option<T>) -> Res<T> {
        match parse(p.as_str()) {
            Some(v) => Some(v),
            None => {
                self.err(
                    Diagnostic::error("unknown-value", format!("unknown {what} `{}`", p.as_str()), self.span(p))
                        .with_note(suggestion_note(p.as_str(), names)),
                );
                None
            }
        }
    }

    /// Add a declaration unless one of the same name exists (then report both places).
    fn push_unique<T>(&mut self, list: &mut Vec<T>, item: Option<T>, what: &str, name: impl Fn(&T) -> &Spanned<String>) {
        let Some(item) = item else { return };
        let n = name(&item);
        match list.iter().find(|q| name(q).value == n.value) {
            Some(prev) => {
                let d = Diagnostic::error("duplicate-name", format!("{what} `{}` is declared twice", n.value), n.span)
                    .with_secondary(name(prev).span, "first declared here");
                self.err(d);
            }
            None => list.push(item),
        }
    }

    pub fn file(&mut self, mut pairs: Pairs<Rule>) -> Res<Pipeline> {
        let file = pairs.next()?;
        let span = self.span(&file);
        let mut items = file.kids();
        let decl = items.next()?;
        let name = self.name(decl.kids().next()?)?;
        let mut params: Vec<Param> = vec![];
        let mut samplers: Vec<SamplerDecl> = vec![];
        let mut resources: Vec<Resource> = vec![];
        let mut passes: Vec<Pass> = vec![];
        let mut variants: Vec<Variant> = vec![];
        let mut output: Option<Spanned<String>> = None;
        for it in items {
            match it.as_rule() {
                Rule::param => {
                    let p = self.param(it);
                    self.push_unique(&mut params, p, "parameter", |p| &p.name);
                }
                Rule::sampler => {
                    let smp = self.sampler(it);
                    self.push_unique(&mut samplers, smp, "sampler", |s| &s.name);
                }
                Rule::texture => {
                    let r = self.texture(it);
                    self.push_unique(&mut resources, r, "resource", |r| &r.name);
                }
                Rule::buffer => {
                    let r = self.buffer(it);
                    self.push_unique(&mut resources, r, "resource", |r| &r.name);
                }
                Rule::pass => {
                    let p = self.pass(it);
                    self.push_unique(&mut passes, p, "pass", |p| &p.name);
                }
                Rule::variant => {
                    let v = self.variant(it);
                    self.push_unique(&mut variants, v, "variant", |v| &v.name);
                }
                Rule::output => {
                    let sp = self.span(&it);
                    let n = it.kids().next().and_then(|n| self.name(n));
                    if let Some(prev) = &output {
                        self.err(
                            Diagnostic::error("duplicate-key", "the pipeline has two `output` lines", sp)
                                .with_secondary(prev.span, "first output"),
                        );
                    } else {
                        output = n;
                    }
                }
                _ => {}
            }
        }
        let Some(output) = output else {
            self.err(
                Diagnostic::error(
                    "missing-key",
                    "pipeline has no `output` line",
                    Span::new(self.file, span.end as usize, span.end as usize),
                )
                .with_note("add `output NAME` naming the resource to present"),
            );
            return None;
        };
        Some(Pipeline {
            name,
            params,
            samplers,
            resources,
            passes,
            variants,
            output,
            span,
        })
    }

    fn param(&mut self, p: P) -> Res<Param> {
        let span = self.span(&p);
        let mut it = p.kids();
        let name = self.name(it.next()?)?;
        let ty_pair = it.next()?;
        let ty_span = self.span(&ty_pair);
        let inner = ty_pair.kids().next()?;
        let ty = match inner.as_rule() {
            Rule::enum_type => {
                let opts: Vec<String> = inner.kids().filter_map(|n| self.name(n)).map(|s| s.value).collect();
                ParamType::Enum(opts)
            }
            _ => self.word(&inner, "parameter type", &ParamType::NAMES, |s| match s {
                "Float" => Some(ParamType::Float),
                "Int" => Some(ParamType::Int),
                "Bool" => Some(ParamType::Bool),
                "Vec2" => Some(ParamType::Vec2),
                "Vec3" => Some(ParamType::Vec3),
                "Vec4" => Some(ParamType::Vec4),
                "Color" => Some(ParamType::Color),
                _ => None,
            })?,
        };
        let default = self.param_value(&ty, it.next()?);
        let (mut min, mut max, mut doc) = (None, None, None);
        for rest in it {
            match rest.as_rule() {
                Rule::range => {
                    let max_only = rest.as_str().starts_with("max");
                    let parts: Vec<P> = rest.kids().collect();
                    let mut ps = parts.into_iter();
                    match (ps.next(), ps.next()) {
                        (Some(a), Some(b)) => {
                            min = self.param_value(&ty, a);
                            max = self.param_value(&ty, b);
                        }
                        (Some(a), None) if max_only => max = self.param_value(&ty, a),
                        (Some(a), None) => min = self.param_value(&ty, a),
                        _ => {}
                    }
                }
                Rule::doc => doc = rest.kids().next().and_then(|s| self.string(s)).map(|s| s.value),
                _ => {}
            }
        }
        Some(Param {
            name,
            ty: Spanned::new(ty, ty_span),
            default: default?,
            min,
            max,
            doc,
            span,
        })
    }

    fn param_value(&mut self, ty: &ParamType, p: P) -> Res<Spanned<ParamValue>> {
        let span = self.span(&p);
        let inner = p.kids().next()?;
        let lit = match inner.as_rule() {
            Rule::number => match inner.as_str().parse::<i64>() {
                Ok(i) => Literal::Int(i),
                Err(_) => Literal::Float(self.number(&inner)?),
            },
            Rule::bool => Literal::Bool(inner.as_str() == "true"),
            Rule::string => Literal::Text(self.string(inner)?.value),
            Rule::dotted => Literal::Text(inner.as_str().to_string()),
            _ => {
                let mut v = vec![];
                for n in inner.kids() {
                    v.push(self.number(&n)?);
                }
                Literal::Tuple(v)
            }
        };
        match ty.value_of(lit) {
            Ok(v) => Some(Spanned::new(v, span)),
            Err(e) => {
                let mut d = Diagnostic::error(e.code, e.message, span);
                if let Some(n) = e.note {
                    d = d.with_note(n);
                }
                self.err(d);
                None
            }
        }
    }

    fn sampler(&mut self, p: P) -> Res<SamplerDecl> {
        let span = self.span(&p);
        let mut it = p.kids();
        let name = self.name(it.next()?)?;
        let (mut filter, mut mipmap, mut address, mut compare) = (FilterMode::Linear, FilterMode::Nearest, AddressMode::ClampToEdge, None);
        let filter_of = |s: &str| match s {
            "Nearest" => Some(FilterMode::Nearest),
            "Linear" => Some(FilterMode::Linear),
            _ => None,
        };
        for opt in it {
            let o = opt.kids().next()?;
            match o.as_rule() {
                Rule::mipmap => {
                    let w = o.kids().next()?;
                    mipmap = self.word(&w, "mipmap filter", &["Nearest", "Linear"], filter_of)?;
                }
                Rule::compare => {
                    let w = o.kids().next()?;
                    compare = Some(self.word(&w, "compare function", &CompareFn::NAMES, CompareFn::from_name)?);
                }
                _ => match o.as_str() {
                    "Nearest" | "Linear" => filter = filter_of(o.as_str())?,
                    "ClampToEdge" => address = AddressMode::ClampToEdge,
                    "Repeat" => address = AddressMode::Repeat,
                    "MirrorRepeat" => address = AddressMode::MirrorRepeat,
                    other => {
                        self.err(
                            Diagnostic::error("unknown-key", format!("unknown sampler option `{other}`"), self.span(&o)).with_note(
                                suggestion_note(
                                    other,
                                    &["Nearest", "Linear", "ClampToEdge", "Repeat", "MirrorRepeat", "mipmap", "compare"],
                                ),
                            ),
                        );
                        return None;
                    }
                },
            }
        }
        Some(SamplerDecl {
            name,
            filter,
            mipmap,
            address,
            compare,
            span,
        })
    }

    fn per_light(&mut self, p: P) -> Res<Spanned<Vec<LightKind>>> {
        let span = self.span(&p);
        let mut kinds = vec![];
        for k in p.kids() {
            let kind = self.word(&k, "light kind", &LightKind::NAMES, LightKind::from_name)?;
            if !kinds.contains(&kind) {
                kinds.push(kind);
            }
        }
        Some(Spanned::new(kinds, span))
    }

    fn texture(&mut self, p: P) -> Res<Resource> {
        let span = self.span(&p);
        let mut it = p.kids();
        let name = self.name(it.next()?)?;
        let fp = it.next()?;
        let format = Spanned::new(
            self.word(&fp, "texture format", TextureFormat::NAMES, TextureFormat::from_name)?,
            self.span(&fp),
        );
        let sp = it.next()?;
        let size_span = self.span(&sp);
        let s = sp.kids().next()?;
        let size = match s.as_rule() {
            Rule::fixed => {
                let mut d = s.kids();
                let w = self.uint(&d.next()?)?.value;
                let h = self.uint(&d.next()?)?.value;
                if w == 0 || h == 0 {
                    self.err(Diagnostic::error(
                        "value-out-of-range",
                        "texture size must be at least 1×1",
                        size_span,
                    ));
                    return None;
                }
                SizeSpec::Fixed { width: w, height: h }
            }
            _ => match s.kids().next() {
                None => SizeSpec::Viewport { scale: 1.0 },
                Some(n) => {
                    let scale = self.number(&n)?;
                    if !(scale > 0.0 && scale <= 16.0) {
                        self.err(Diagnostic::error(
                            "value-out-of-range",
                            "viewport scale must be in (0, 16]",
                            self.span(&n),
                        ));
                        return None;
                    }
                    SizeSpec::Viewport { scale }
                }
            },
        };
        let mut desc = TextureDesc {
            format,
            size: Spanned::new(size, size_span),
            layers: Spanned::new(1, span),
            view: Spanned::new(ViewDim::D2, span),
            mips: Spanned::new(1, span),
            per_light: None,
            history: false,
            external: false,
        };
        for opt in it {
            let o = opt.kids().next()?;
            match o.as_rule() {
                Rule::layers => desc.layers = self.uint(&o.kids().next()?)?,
                Rule::mips => desc.mips = self.uint(&o.kids().next()?)?,
                Rule::per_light => desc.per_light = Some(self.per_light(o)?),
                _ => match o.as_str() {
                    "D2" => desc.view = Spanned::new(ViewDim::D2, self.span(&o)),
                    "D2Array" => desc.view = Spanned::new(ViewDim::D2Array, self.span(&o)),
                    "Cube" => desc.view = Spanned::new(ViewDim::Cube, self.span(&o)),
                    "history" => desc.history = true,
                    "external" => desc.external = true,
                    other => {
                        self.err(
                            Diagnostic::error("unknown-key", format!("unknown texture option `{other}`"), self.span(&o)).with_note(
                                suggestion_note(
                                    other,
                                    &["layers", "mips", "D2", "D2Array", "Cube", "per_light", "history", "external"],
                                ),
                            ),
                        );
                        return None;
                    }
                },
            }
        }
        Some(Resource {
            name,
            kind: ResourceKind::Texture(desc),
            span,
        })
    }

    fn buffer(&mut self, p: P) -> Res<Resource> {
        let span = self.span(&p);
        let mut it = p.kids();
        let name = self.name(it.next()?)?;
        let sp = it.next()?;
        let size = match sp.as_str().parse::<u64>() {
            Ok(v) if v > 0 => Spanned::new(v, self.span(&sp)),
            _ => {
                self.err(Diagnostic::error(
                    "value-out-of-range",
                    "buffer size must be a positive number of bytes",
                    self.span(&sp),
                ));
                return None;
            }
        };
        let mut desc = BufferDesc {
            size,
            per_light: None,
            history: false,
            external: false,
        };
        for opt in it {
            let o = opt.kids().next()?;
            match o.as_rule() {
                Rule::per_light => desc.per_light = Some(self.per_light(o)?),
                _ => match o.as_str() {
                    "history" => desc.history = true,
                    "external" => desc.external = true,
                    other => {
                        self.err(
                            Diagnostic::error("unknown-key", format!("unknown buffer option `{other}`"), self.span(&o))
                                .with_note(suggestion_note(other, &["per_light", "history", "external"])),
                        );
                        return None;
                    }
                },
            }
        }
        Some(Resource {
            name,
            kind: ResourceKind::Buffer(desc),
            span,
        })
    }

    fn stage(&mut self, shader: &Option<Spanned<String>>, given: Option<P>, stage: naga::ShaderStage, pass_span: Span) -> Res<ShaderRef> {
        let (text, span) = match given {
            Some(p) => {
                let span = self.span(&p);
                let inner = p.kids().next()?;
                let t = if inner.as_rule() == Rule::string {
                    self.string(inner)?.value
                } else {
                    inner.as_str().to_string()
                };
                (Some(t), span)
            }
            None => (None, shader.as_ref().map(|s| s.span).unwrap_or(pass_span)),
        };
        if let Some((file, entry)) = text.as_deref().and_then(|t| t.split_once('#')) {
            return Some(ShaderRef {
                file: Spanned::new(file.to_string(), span),
                entry: Spanned::new(entry.to_string(), span),
            });
        }
        let Some(file) = shader.clone() else {
            self.err(Diagnostic::error(
                "missing-key",
                format!("pass has no shader file for its {} stage", crate::check::entry::stage_word(stage)),
                pass_span,
            ));
            return None;
        };
        let entry = text.unwrap_or_else(|| default_entry(stage, &file.value).to_string());
        Some(ShaderRef {
            file,
            entry: Spanned::new(entry, span),
        })
    }

    fn target(&mut self, p: P, depth: bool) -> Res<Target> {
        let span = self.span(&p);
        let mut it = p.kids();
        let resource = self.name(it.next()?)?;
        let mut load = LoadOp::Clear(if depth { vec![1.0] } else { vec![0.0; 4] });
        let (mut blend, mut layer, mut compare, mut write) = (None, LayerSel::Base, CompareFn::Less, true);
        for opt in it {
            let o = opt.kids().next()?;
            let ospan = self.span(&o);
            match o.as_rule() {
                Rule::clear => {
                    let t = o.kids().next()?;
                    let mut v = vec![];
                    for n in t.kids() {
                        v.push(self.number(&n)?);
                    }
                    if v.len() != if depth { 1 } else { 4 } {
                        self.err(Diagnostic::error(
                            "type-mismatch",
                            if depth {
                                "a depth clear is one value: `clear(1.0)`"
                            } else {
                                "a color clear is `clear(r, g, b, a)`"
                            },
                            ospan,
                        ));
                        return None;
                    }
                    load = LoadOp::Clear(v);
                }
                Rule::load => load = LoadOp::Load,
                Rule::blend if !depth => {
                    let w = o.kids().next()?;
                    let b = self.word(&w, "blend mode", &["Add", "Alpha", "Multiply"], |s| match s {
                        "Add" => Some(Blend::Add),
                        "Alpha" => Some(Blend::Alpha),
                        "Multiply" => Some(Blend::Multiply),
                        _ => None,
                    })?;
                    blend = Some(Spanned::new(b, ospan));
                }
                Rule::layer => {
                    let w = o.kids().next()?;
                    layer = if w.as_rule() == Rule::uint {
                        LayerSel::Index(self.uint(&w)?.value)
                    } else {
                        self.word(&w, "layer", &["Base", "Face", "All"], |s| match s {
                            "Base" => Some(LayerSel::Base),
                            "Face" => Some(LayerSel::Face),
                            "All" => Some(LayerSel::All),
                            _ => None,
                        })?
                    };
                }
                Rule::compare if depth => {
                    let w = o.kids().next()?;
                    compare = self.word(&w, "compare function", &CompareFn::NAMES, CompareFn::from_name)?;
                }
                Rule::nowrite if depth => write = false,
                _ => {
                    self.err(Diagnostic::error(
                        "misplaced",
                        format!(
                            "`{}` does not apply to a {} target",
                            o.as_str().split_whitespace().next().unwrap_or(""),
                            if depth { "depth" } else { "color" }
                        ),
                        ospan,
                    ));
                    return None;
                }
            }
        }
        Some(Target {
            resource,
            load,
            blend,
            layer,
            compare,
            write,
            span,
        })
    }

    fn pass(&mut self, p: P) -> Res<Pass> {
        let span = self.span(&p);
        let mut it = p.kids().peekable();
        let kind_word = it.next()?.as_str().to_string();
        let name = self.name(it.next()?)?;
        let shader = match it.peek().map(|n| n.as_rule()) {
            Some(Rule::string) => self.string(it.next()?),
            _ => None,
        };
        let mut seen: Vec<(Rule, Span)> = vec![];
        let mut props: Vec<P> = vec![];
        for item in it {
            let r = item.as_rule();
            let s = self.span(&item);
            if let Some((_, prev)) = seen.iter().find(|(q, _)| *q == r) {
                let word = item.as_str().split_whitespace().next().unwrap_or("").to_string();
                self.err(
                    Diagnostic::error("duplicate-key", format!("`{word}` is given twice in pass `{}`", name.value), s)
                        .with_secondary(*prev, "first here"),
                );
                continue;
            }
            seen.push((r, s));
            let misplaced = match kind_word.as_str() {
                "raster" => matches!(r, Rule::entry | Rule::dispatch),
                "fullscreen" => matches!(
                    r,
                    Rule::entry | Rule::dispatch | Rule::vertex | Rule::draw | Rule::cull | Rule::instances | Rule::multiview
                ),
                _ => matches!(
                    r,
                    Rule::vertex | Rule::fragment | Rule::draw | Rule::cull | Rule::instances | Rule::multiview
                ),
            };
            if misplaced {
                let word = item.as_str().split_whitespace().next().unwrap_or("").to_string();
                self.err(Diagnostic::error(
                    "misplaced",
                    format!("`{word}` is not a property of {kind_word} passes"),
                    s,
                ));
                continue;
            }
            props.push(item);
        }
        let has_color = props.iter().any(|p| p.as_rule() == Rule::color);
        let (kind, vertex, fragment, compute) = match kind_word.as_str() {
            "raster" => {
                let draw = match take(&mut props, Rule::draw) {
                    Some(d) => {
                        let inner = d.kids().next()?;
                        match inner.as_rule() {
                            Rule::vertices => Draw::Vertices(self.uint(&inner.kids().next()?)?.value),
                            _ if inner.as_str() == "Scene" => Draw::Scene,
                            _ => {
                                self.err(
                                    Diagnostic::error("unknown-value", format!("unknown draw `{}`", inner.as_str()), self.span(&inner))
                                        .with_note("expected `Scene` or `vertices(N)`"),
                                );
                                return None;
                            }
                        }
                    }
                    None => Draw::Scene,
                };
                let cull = match take(&mut props, Rule::cull) {
                    Some(c) => {
                        let w = c.kids().next()?;
                        self.word(&w, "cull mode", &["None", "Front", "Back"], |s| match s {
                            "None" => Some(CullMode::None),
                            "Front" => Some(CullMode::Front),
                            "Back" => Some(CullMode::Back),
                            _ => None,
                        })?
                    }
                    None => CullMode::Back,
                };
                let instances = match take(&mut props, Rule::instances) {
                    Some(n) => self.uint(&n.kids().next()?)?.value.max(1),
                    None => 1,
                };
                let multiview = match take(&mut props, Rule::multiview) {
                    Some(n) => Some(self.uint(&n.kids().next()?)?),
                    None => None,
                };
                let v = self.stage(
                    &shader,
                    take(&mut props, Rule::vertex).and_then(|p| p.kids().next()),
                    naga::ShaderStage::Vertex,
                    span,
                )?;
                let f = match take(&mut props, Rule::fragment) {
                    Some(fp) => {
                        let inner = fp.kids().next()?;
                        if inner.as_rule() == Rule::none {
                            None
                        } else {
                            Some(self.stage(&shader, Some(inner), naga::ShaderStage::Fragment, span)?)
                        }
                    }
                    None if has_color => Some(self.stage(&shader, None, naga::ShaderStage::Fragment, span)?),
                    None => None,
                };
                (
                    PassKind::Raster {
                        draw,
                        cull,
                        instances,
                        multiview,
                    },
                    Some(v),
                    f,
                    None,
                )
            }
            "fullscreen" => {
                let v = ShaderRef {
                    file: Spanned::new(crate::shader::FULLSCREEN_FILE.to_string(), span),
                    entry: Spanned::new(crate::shader::FULLSCREEN_ENTRY.to_string(), span),
                };
                let fg = take(&mut props, Rule::fragment).and_then(|p| p.kids().next());
                let f = self.stage(&shader, fg, naga::ShaderStage::Fragment, span)?;
                (PassKind::Fullscreen, Some(v), Some(f), None)
            }
            _ => {
                let eg = take(&mut props, Rule::entry).and_then(|p| p.kids().next());
                let c = self.stage(&shader, eg, naga::ShaderStage::Compute, span)?;
                let Some(d) = take(&mut props, Rule::dispatch) else {
                    self.err(
                        Diagnostic::error("missing-key", format!("compute pass `{}` has no `dispatch`", name.value), name.span)
                            .with_note("add `dispatch groups(x, y, z)` or `dispatch size(RESOURCE)`"),
                    );
                    return None;
                };
                let inner = d.kids().next()?;
                let dispatch = match inner.as_rule() {
                    Rule::groups => {
                        let mut g = inner.kids();
                        Dispatch::Groups(
                            self.uint(&g.next()?)?.value,
                            self.uint(&g.next()?)?.value,
                            self.uint(&g.next()?)?.value,
                        )
                    }
                    _ => Dispatch::Size(self.name(inner.kids().next()?)?),
                };
                (PassKind::Compute { dispatch }, None, None, Some(c))
            }
        };
        let mut pass = Pass {
            name,
            kind,
            vertex,
            fragment,
            compute,
            reads: vec![],
            writes: vec![],
            color: vec![],
            depth: None,
            params: vec![],
            param_block: Spanned::new("params".to_string(), span),
            bind: vec![],
            when: None,
            per_light: None,
            per_face: false,
            span,
        };
        for item in props {
            match item.as_rule() {
                Rule::reads => {
                    for r in item.kids() {
                        let inner = r.kids().next()?;
                        if inner.as_rule() == Rule::prev {
                            pass.reads.push(Read::Prev(self.name(inner.kids().next()?)?));
                        } else {
                            pass.reads.push(Read::Current(self.name(inner)?));
                        }
                    }
                }
                Rule::writes => pass.writes = self.names(item.kids().next()?),
                Rule::params => pass.params = self.names(item.kids().next()?),
                Rule::param_block => pass.param_block = self.name(item.kids().next()?)?,
                Rule::bind => {
                    for b in item.kids() {
                        let mut kv = b.kids();
                        let k = self.name(kv.next()?)?;
                        let v = self.name(kv.next()?)?;
                        pass.bind.push((k, v));
                    }
                }
                Rule::when => pass.when = Some(self.cond(item.kids().next()?)?),
                Rule::per_light => pass.per_light = Some(self.per_light(item)?),
                Rule::per_face => pass.per_face = true,
                Rule::color => {
                    for t in item.kids() {
                        let t = self.target(t, false)?;
                        pass.color.push(ColorTarget {
                            resource: t.resource,
                            load: t.load,
                            blend: t.blend,
                            layer: t.layer,
                            span: t.span,
                        });
                    }
                }
                Rule::depth => {
                    let t = self.target(item.kids().next()?, true)?;
                    pass.depth = Some(DepthTarget {
                        resource: t.resource,
                        load: t.load,
                        compare: t.compare,
                        write: t.write,
                        layer: t.layer,
                        span: t.span,
                    });
                }
                _ => {}
            }
        }
        Some(pass)
    }

    fn cond(&mut self, p: P) -> Res<Spanned<Condition>> {
        let span = self.span(&p);
        let inner = p.kids().next()?;
        let c = match inner.as_rule() {
            Rule::reflective => Condition::Reflective,
            Rule::not_cond => Condition::Not(Box::new(self.cond(inner.kids().next()?)?)),
            Rule::all_cond | Rule::any_cond => {
                let all = inner.as_rule() == Rule::all_cond;
                let mut cs = vec![];
                for c in inner.kids() {
                    cs.push(self.cond(c)?);
                }
                if all {
                    Condition::All(cs)
                } else {
                    Condition::Any(cs)
                }
            }
            _ => {
                let mut it = inner.kids();
                let f = it.next()?;
                let fname = f.as_str().to_string();
                let args: Vec<P> = it.collect();
                let arity = |n: usize, this: &mut Self| {
                    if args.len() != n {
                        this.err(Diagnostic::error(
                            "type-mismatch",
                            format!("`{fname}(...)` takes {n} argument(s), found {}", args.len()),
                            span,
                        ));
                        false
                    } else {
                        true
                    }
                };
                match fname.as_str() {
                    "light" if arity(1, self) => {
                        Condition::Light(self.word(&args[0], "light kind", &LightKind::NAMES, LightKind::from_name)?)
                    }
                    "effect" if arity(1, self) => match Effect::from_name(args[0].as_str()) {
                        Some(e) => Condition::Effect(e),
                        None => {
                            self.err(
                                Diagnostic::error(
                                    "unknown-effect",
                                    format!("unknown effect `{}`", args[0].as_str()),
                                    self.span(&args[0]),
                                )
                                .with_note(suggestion_note(args[0].as_str(), &Effect::NAMES)),
                            );
                            return None;
                        }
                    },
                    "toggle" if arity(1, self) => Condition::Toggle(self.name(args[0].clone())?),
                    "variant" if arity(2, self) => Condition::Variant(self.name(args[0].clone())?, self.name(args[1].clone())?),
                    "light" | "effect" | "toggle" | "variant" => return None,
                    other => {
                        self.err(
                            Diagnostic::error("unknown-kind", format!("unknown condition `{other}`"), self.span(&f)).with_note(
                                suggestion_note(other, &["light", "effect", "toggle", "variant", "not", "all", "any", "reflective"]),
                            ),
                        );
                        return None;
                    }
                }
            }
        };
        Some(Spanned::new(c, span))
    }

    fn variant(&mut self, p: P) -> Res<Variant> {
        let span = self.span(&p);
        let mut it = p.kids();
        let name = self.name(it.next()?)?;
        let default = self.name(it.next()?)?;
        let mut doc = None;
        let mut options: Vec<VariantOption> = vec![];
        for item in it {
            match item.as_rule() {
                Rule::doc => doc = item.kids().next().and_then(|s| self.string(s)).map(|s| s.value),
                Rule::option => {
                    let o = self.option(item);
                    self.push_unique(&mut options, o, "variant option", |o| &o.name);
                }
                _ => {}
            }
        }
        Some(Variant {
            name,
            options,
            default,
            doc,
            span,
        })
    }

    fn option(&mut self, p: P) -> Res<VariantOption> {
        let span = self.span(&p);
        let mut it = p.kids();
        let name = self.name(it.next()?)?;
        let mut o = VariantOption {
            name,
            requires: vec![],
            limits: vec![],
            fallback: None,
            shaders: vec![],
            doc: None,
            span,
        };
        for item in it {
            match item.as_rule() {
                Rule::doc => o.doc = item.kids().next().and_then(|s| self.string(s)).map(|s| s.value),
                Rule::option_opt => {
                    let inner = item.kids().next()?;
                    match inner.as_rule() {
                        Rule::requires => {
                            for f in inner.kids() {
                                let feat = self.word(&f, "feature", Feature::NAMES, Feature::from_name)?;
                                o.requires.push(Spanned::new(feat, self.span(&f)));
                            }
                        }
                        Rule::limit => {
                            for li in inner.kids() {
                                let mut kv = li.kids();
                                let k = kv.next()?;
                                let kspan = self.span(&k);
                                if !crate::profile::Limits::NAMES.contains(&k.as_str()) {
                                    self.err(
                                        Diagnostic::error("unknown-limit", format!("unknown limit `{}`", k.as_str()), kspan)
                                            .with_note(suggestion_note(k.as_str(), crate::profile::Limits::NAMES)),
                                    );
                                    return None;
                                }
                                let v = self.uint(&kv.next()?)?;
                                o.limits
                                    .push((Spanned::new(k.as_str().to_string(), kspan), Spanned::new(v.value as u64, v.span)));
                            }
                        }
                        Rule::fallback => o.fallback = Some(self.name(inner.kids().next()?)?),
                        _ => {
                            for sub in inner.kids() {
                                let mut kv = sub.kids();
                                let k = self.name(kv.next()?)?;
                                let v = self.string(kv.next()?)?;
                                o.shaders.push((k, v));
                            }
                        }
                    }
                }
                _ => {}
            }
        }
        Some(o)
    }
}
