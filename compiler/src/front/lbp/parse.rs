//! LBP parse pairs -> the syntax tree. Only syntax is decided here (which keyword is which
//! key, string escapes, number literals); defaults, ranges and references are the
//! lowering's and the checks' business, as for RON.

use super::Rule;
use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::span::{FileId, Span};
use crate::tree::{Field, Node, Value};
use pest::iterators::{Pair, Pairs};

type P<'i> = Pair<'i, Rule>;

/// Children of a pair without punctuation (which exists as rules only for error positions).
fn kids<'i>(p: P<'i>) -> impl Iterator<Item = P<'i>> {
    p.into_inner().filter(|p| {
        !matches!(
            p.as_rule(),
            Rule::colon | Rule::equals | Rule::open_brace | Rule::close_brace | Rule::open_paren | Rule::close_paren
        )
    })
}

/// Condition keywords of the language (`not`, `all`, `any`, `reflective` have rules of their own).
const CONDITIONS: [&str; 8] = ["light", "effect", "toggle", "variant", "not", "all", "any", "reflective"];

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

pub struct Builder<'d> {
    pub file: FileId,
    pub diags: &'d mut Diagnostics,
    pub text_len: usize,
}

/// A top-level map of the pipeline being gathered: key, entries, span.
type MapField = (&'static str, Vec<(Node, Node)>, Span);

/// Fields of one item as they are read.
#[derive(Default)]
struct Fields(Vec<Field>);

impl Fields {
    fn put(&mut self, key: &str, key_span: Span, node: Node) {
        self.0.push((key.to_string(), key_span, node));
    }
}

impl Builder<'_> {
    fn span(&self, p: &P) -> Span {
        let s = p.as_span();
        Span::new(self.file, s.start(), s.end())
    }

    fn err(&mut self, d: Diagnostic) -> Option<Node> {
        self.diags.push(d);
        None
    }

    fn string(&mut self, p: P) -> Option<Node> {
        let span = self.span(&p);
        let inner = kids(p).next().map(|i| i.as_str()).unwrap_or("");
        match unescape(inner) {
            Ok(s) => Some(Node::str(s, span)),
            Err(e) => self.err(Diagnostic::error(Code::LbpSyntax, e, span)),
        }
    }

    /// `$NAME`, a template's parameter: `Arg("NAME")` (the templates stage puts the
    /// instance's argument in its place).
    fn arg(&self, p: &P) -> Node {
        let span = self.span(p);
        Node::call("Arg", vec![Node::str(&p.as_str()[1..], span)], span)
    }

    /// A string, or a template's parameter standing for one.
    fn string_or_arg(&mut self, p: P) -> Option<Node> {
        match p.as_rule() {
            Rule::arg => Some(self.arg(&p)),
            _ => self.string(p),
        }
    }

    /// A `name`: dotted identifier or quoted string, as a string node.
    fn name(&mut self, p: P) -> Option<Node> {
        let span = self.span(&p);
        let inner = kids(p).next()?;
        match inner.as_rule() {
            Rule::string => self.string(inner),
            Rule::arg => Some(self.arg(&inner)),
            _ => Some(Node::str(inner.as_str(), span)),
        }
    }

    /// A word naming an IR enum value (`Rgba16Float`, `Point`): an identifier node.
    fn word(&self, p: &P) -> Node {
        Node::ident(p.as_str(), self.span(p))
    }

    fn uint(&mut self, p: &P) -> Option<Node> {
        match p.as_str().parse::<i64>() {
            Ok(v) => Some(Node::int(v, self.span(p))),
            Err(_) => self.err(Diagnostic::error(
                Code::BadNumber,
                format!("`{}` is not a 32-bit whole number", p.as_str()),
                self.span(p),
            )),
        }
    }

    fn number(&mut self, p: &P) -> Option<Node> {
        let span = self.span(p);
        if let Ok(i) = p.as_str().parse::<i64>() {
            return Some(Node::int(i, span));
        }
        match p.as_str().parse::<f64>() {
            Ok(v) if v.is_finite() => Some(Node::float(v, span)),
            _ => self.err(Diagnostic::error(
                Code::BadNumber,
                format!("`{}` is not a finite number", p.as_str()),
                span,
            )),
        }
    }

    fn tuple(&mut self, p: P) -> Option<Node> {
        let span = self.span(&p);
        let items = kids(p).map(|n| self.number(&n)).collect::<Option<Vec<_>>>()?;
        Some(Node::tuple(items, span))
    }

    fn value(&mut self, p: P) -> Option<Node> {
        let inner = kids(p).next()?;
        match inner.as_rule() {
            Rule::bool => Some(Node::bool(inner.as_str() == "true", self.span(&inner))),
            Rule::tuple => self.tuple(inner),
            Rule::number => self.number(&inner),
            Rule::string => self.string(inner),
            Rule::arg => Some(self.arg(&inner)),
            _ => Some(Node::str(inner.as_str(), self.span(&inner))),
        }
    }

    /// A pass's list of names; an element may be a choice.
    fn names(&mut self, p: P) -> Option<Node> {
        let span = self.span(&p);
        let items = kids(p)
            .map(|n| match n.as_rule() {
                Rule::name_match => self.element_choice(n, Self::name),
                _ => self.name(n),
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Node::list(items, span))
    }

    /// `match(VARIANT) { a | b: VALUE, _: VALUE }`: the tree's `Match(variant: .., arms: {..})`,
    /// each arm's value made by `value` from the arm's parts.
    fn choice(&mut self, p: P, at: Span, mut value: impl FnMut(&mut Self, Vec<P>, Span) -> Option<Node>) -> Option<Node> {
        self.choice_of(kids(p).collect(), at, &mut value)
    }

    /// A choice from its parts: `match_head` then the arms.
    fn choice_of<F: FnMut(&mut Self, Vec<P>, Span) -> Option<Node>>(&mut self, parts: Vec<P>, at: Span, value: &mut F) -> Option<Node> {
        let mut it = parts.into_iter();
        let head = it.next()?;
        let head_span = self.span(&head);
        let selector = kids(head).next()?;
        let by_light = selector.as_rule() == Rule::by_light;
        let variant = if by_light { None } else { Some(self.name(selector)?) };
        let mut arms = vec![];
        for arm in it {
            let arm_span = self.span(&arm);
            let mut parts = kids(arm);
            let key = parts.next()?;
            let key_span = self.span(&key);
            let options = kids(key).map(|n| self.name(n).map(|n| n.text().unwrap_or("").to_string()));
            let options = options.collect::<Option<Vec<_>>>()?;
            let parts: Vec<P> = parts.collect();
            let v = match parts.first().map(|p| p.as_rule()) {
                Some(Rule::match_head) => self.choice_of(parts, arm_span, value)?,
                _ => value(self, parts, arm_span)?,
            };
            arms.push((Node::str(options.join(" | "), key_span), v));
        }
        let fields = match variant {
            Some(variant) => vec![
                ("variant".to_string(), variant.span, variant),
                ("arms".to_string(), at, Node::map(arms, at)),
            ],
            None => vec![("light".to_string(), head_span, Node::map(arms, at))],
        };
        // From `match` on: messages about the choice as a whole point there.
        let span = Span::new(at.file, head_span.start as usize, at.end as usize);
        Some(Node::structure("Match", head_span, fields, span))
    }

    /// A list element: `one`, or a choice of elements.
    fn element(&mut self, p: P, one: fn(&mut Self, P) -> Option<Node>) -> Option<Node> {
        match p.as_rule() {
            Rule::name_match | Rule::color_match => self.element_choice(p, one),
            _ => one(self, p),
        }
    }

    /// A choice standing for list elements: an arm is one element or `(a, b, ...)`.
    fn element_choice(&mut self, p: P, one: fn(&mut Self, P) -> Option<Node>) -> Option<Node> {
        let at = self.span(&p);
        self.choice(p, at, |s, mut parts, span| {
            let v = parts.pop()?;
            match v.as_rule() {
                Rule::read_group | Rule::name_group | Rule::color_group => {
                    let items = kids(v).map(|x| s.element(x, one)).collect::<Option<Vec<_>>>()?;
                    Some(Node::list(items, span))
                }
                _ => s.element(v, one),
            }
        })
    }

    fn per_light(&mut self, p: P) -> Node {
        let span = self.span(&p);
        Node::list(kids(p).map(|k| self.word(&k)).collect(), span)
    }

    pub fn file(&mut self, mut pairs: Pairs<Rule>) -> Option<Node> {
        let file = pairs.next()?;
        let span = self.span(&file);
        let mut items = kids(file);
        let decl = items.next()?;
        let mut root = Fields::default();
        let name = self.name(kids(decl.clone()).next()?)?;
        root.put("name", self.span(&decl), name);
        let mut maps: [MapField; 5] = [
            ("params", vec![], span),
            ("samplers", vec![], span),
            ("resources", vec![], span),
            ("variants", vec![], span),
            ("lets", vec![], span),
        ];
        let mut passes = vec![];
        let mut templates = vec![];
        let mut outputs = Fields::default();
        let mut composing = Composing::default();
        for it in items {
            let at = self.span(&it);
            if self.composing(&it, &mut composing, &mut maps, &mut passes) {
                continue;
            }
            match it.as_rule() {
                Rule::param | Rule::sampler | Rule::texture | Rule::buffer | Rule::accel | Rule::variant | Rule::let_decl => {
                    self.map_item(it, &mut maps, |v| v);
                }
                Rule::pass => {
                    passes.extend(self.pass(it));
                }
                Rule::template => templates.extend(self.template(it)),
                Rule::group => {
                    passes.extend(self.group(it));
                }
                Rule::top_flag => outputs.0.push((it.as_str().to_string(), at, Node::bool(true, at))),
                Rule::output | Rule::hdr_output => {
                    let key = if it.as_rule() == Rule::output { "output" } else { "hdr_output" };
                    let n = kids(it).next().and_then(|n| self.name(n));
                    outputs.0.extend(n.map(|n| (key.to_string(), at, n)));
                }
                _ => {}
            }
        }
        composing.put(&mut root);
        // In the order a Plan's items are printed in: declarations, passes, variants.
        let [params, samplers, resources, variants, lets] = maps;
        for (key, entries, mspan) in [params, samplers, resources, lets] {
            if !entries.is_empty() {
                root.put(key, mspan, Node::map(entries, mspan));
            }
        }
        if let (Some(first), Some(last)) = (templates.first(), templates.last()) {
            let at = first.1.span.to(last.1.span);
            root.put("templates", at, Node::map(templates, at));
        }
        root.put("passes", span, Node::list(passes, span));
        let (key, entries, mspan) = variants;
        if !entries.is_empty() {
            root.put(key, mspan, Node::map(entries, mspan));
        }
        root.0.extend(outputs.0);
        // A missing key is reported where it would be added: at the end of the file.
        let end = Span::new(self.file, self.text_len, self.text_len);
        Some(Node::structure("Pipeline", end, root.0, span))
    }

    fn param(&mut self, p: P) -> Option<(Node, Node)> {
        let span = self.span(&p);
        let mut it = kids(p);
        let name = self.name(it.next()?)?;
        let ty = it.next()?;
        let ty_span = self.span(&ty);
        let ty_inner = kids(ty).next()?;
        let mut f = Fields::default();
        let kind = if ty_inner.as_rule() == Rule::enum_type {
            let opts = kids(ty_inner).map(|n| self.name(n)).collect::<Option<Vec<_>>>()?;
            f.put("options", ty_span, Node::list(opts, ty_span));
            "Enum".to_string()
        } else {
            ty_inner.as_str().to_string()
        };
        let default = it.next()?;
        f.put("default", self.span(&default), self.value(default)?);
        for rest in it {
            let at = self.span(&rest);
            match rest.as_rule() {
                Rule::range => {
                    let max_only = rest.as_str().starts_with("max");
                    let mut vs = kids(rest);
                    match (vs.next(), vs.next()) {
                        (Some(a), Some(b)) => {
                            f.put("min", at, self.value(a)?);
                            f.put("max", at, self.value(b)?);
                        }
                        (Some(a), None) => f.put(if max_only { "max" } else { "min" }, at, self.value(a)?),
                        _ => {}
                    }
                }
                Rule::doc => f.put("doc", at, self.string(kids(rest).next()?)?),
                _ => {}
            }
        }
        Some((name, Node::structure(&kind, ty_span, f.0, span)))
    }

    fn sampler(&mut self, p: P) -> Option<(Node, Node)> {
        let span = self.span(&p);
        let mut it = kids(p);
        let name = self.name(it.next()?)?;
        let mut f = Fields::default();
        for opt in it {
            let o = kids(opt).next()?;
            let at = self.span(&o);
            match o.as_rule() {
                Rule::mipmap => f.put("mipmap", at, self.word(&kids(o).next()?)),
                Rule::compare => f.put("compare", at, self.word(&kids(o).next()?)),
                _ if matches!(o.as_str(), "Nearest" | "Linear") => f.put("filter", at, self.word(&o)),
                _ => f.put("address", at, self.word(&o)),
            }
        }
        Some((name.clone(), Node::structure("Sampler", name.span, f.0, span)))
    }

    /// `layers N`, `mips N`, `per_light(..)` and the flags (view, `history`, `external`).
    fn resource_opt(&mut self, f: &mut Fields, o: P) -> Option<()> {
        let at = self.span(&o);
        match o.as_rule() {
            Rule::layers => f.put("layers", at, self.uint(&kids(o).next()?)?),
            Rule::mips => f.put("mips", at, self.uint(&kids(o).next()?)?),
            Rule::per_light => f.put("per_light", at, self.per_light(o)),
            Rule::valid => {
                let mut k = kids(o);
                let (lo, hi) = (self.number(&k.next()?)?, self.number(&k.next()?)?);
                f.put("valid", at, Node::tuple(vec![lo, hi], at))
            }
            Rule::data => {
                let inner = kids(o).next()?;
                let node = match inner.as_rule() {
                    Rule::string => Node::call("File", vec![self.string(inner)?], at),
                    Rule::data_f32 => {
                        let nums = kids(inner).map(|n| self.number(&n)).collect::<Option<Vec<_>>>()?;
                        Node::call("F32", vec![Node::list(nums, at)], at)
                    }
                    _ => {
                        let nums = kids(inner).map(|n| self.uint(&n)).collect::<Option<Vec<_>>>()?;
                        Node::call("U32", vec![Node::list(nums, at)], at)
                    }
                };
                f.put("data", at, node)
            }
            _ => match o.as_str() {
                "history" | "external" | "per_pixel" => f.put(o.as_str(), at, Node::bool(true, at)),
                view => f.put("view", at, Node::ident(view, at)),
            },
        }
        Some(())
    }

    fn texture(&mut self, p: P) -> Option<(Node, Node)> {
        let span = self.span(&p);
        let mut it = kids(p);
        let name = self.name(it.next()?)?;
        let mut f = Fields::default();
        let format = it.next()?;
        f.put("format", self.span(&format), self.word(&format));
        let size = it.next()?;
        let size_span = self.span(&size);
        let s = kids(size).next()?;
        let size = match s.as_rule() {
            Rule::fixed => {
                let mut d = kids(s);
                let (w, h) = (self.uint(&d.next()?)?, self.uint(&d.next()?)?);
                Node::call("Fixed", vec![w, h], size_span)
            }
            Rule::param_size => Node::call("Param", vec![self.name(kids(s).next()?)?], size_span),
            _ => match kids(s).next() {
                None => Node::ident("Viewport", size_span),
                Some(n) if n.as_rule() == Rule::param_size => {
                    let at = self.span(&n);
                    let param = Node::call("Param", vec![self.name(kids(n).next()?)?], at);
                    Node::call("Viewport", vec![param], size_span)
                }
                Some(n) => Node::call("Viewport", vec![self.number(&n)?], size_span),
            },
        };
        f.put("size", size_span, size);
        for opt in it {
            self.resource_opt(&mut f, kids(opt).next()?)?;
        }
        Some((name.clone(), Node::structure("Texture", name.span, f.0, span)))
    }

    fn buffer(&mut self, p: P) -> Option<(Node, Node)> {
        let span = self.span(&p);
        let mut it = kids(p);
        let name = self.name(it.next()?)?;
        let mut f = Fields::default();
        let size = it.next()?;
        f.put("size", self.span(&size), self.uint(&size)?);
        for opt in it {
            self.resource_opt(&mut f, kids(opt).next()?)?;
        }
        Some((name.clone(), Node::structure("Buffer", name.span, f.0, span)))
    }

    fn accel(&mut self, p: P) -> Option<(Node, Node)> {
        let span = self.span(&p);
        let name = self.name(kids(p).next()?)?;
        Some((name.clone(), Node::structure("AccelerationStructure", name.span, vec![], span)))
    }

    /// A parameter, sampler, resource or variant line into its map, its value through `wrap`.
    fn map_item(&mut self, it: P, maps: &mut [MapField; 5], wrap: impl FnOnce(Node) -> Node) {
        let at = self.span(&it);
        let (slot, entry) = match it.as_rule() {
            Rule::param => (0, self.param(it)),
            Rule::sampler => (1, self.sampler(it)),
            Rule::texture => (2, self.texture(it)),
            Rule::buffer => (2, self.buffer(it)),
            Rule::accel => (2, self.accel(it)),
            Rule::let_decl => (4, self.let_decl(it)),
            _ => (3, self.variant(it)),
        };
        maps[slot].1.extend(entry.map(|(k, v)| (k, wrap(v))));
        maps[slot].2 = maps[slot].2.to(at);
    }

    /// `use`, `fix`, `remove` and `replace` items (false for any other item).
    fn composing(&mut self, it: &P, c: &mut Composing, maps: &mut [MapField; 5], passes: &mut Vec<Node>) -> bool {
        let at = self.span(it);
        match it.as_rule() {
            Rule::use_decl => c.used.extend(kids(it.clone()).next().and_then(|s| self.string(s)).map(|s| (at, s))),
            Rule::fix => {
                let mut k = kids(it.clone());
                let pair = (k.next().and_then(|n| self.name(n)), k.next().and_then(|n| self.name(n)));
                if let (Some(v), Some(o)) = pair {
                    c.fix.push((v, o));
                    c.fix_span = Some(c.fix_span.map_or(at, |s| s.to(at)));
                }
            }
            Rule::remove => {
                let mut k = kids(it.clone());
                let kind = k.next().map(|w| w.as_str().to_string()).unwrap_or_default();
                let kind = kind[..1].to_uppercase() + &kind[1..];
                if let Some(n) = k.next().and_then(|n| self.name(n)) {
                    c.remove.push(Node::call(&kind, vec![n], at));
                    c.remove_span = Some(c.remove_span.map_or(at, |s| s.to(at)));
                }
            }
            Rule::replace => {
                let Some(inner) = kids(it.clone()).next() else { return true };
                if inner.as_rule() == Rule::pass {
                    passes.extend(self.pass(inner).map(|p| with_field(p, "replace", Node::bool(true, at))));
                } else {
                    self.map_item(inner, maps, |v| Node::call("Replace", vec![v], at));
                }
            }
            _ => return false,
        }
        true
    }

    fn pass(&mut self, p: P) -> Option<Node> {
        let span = self.span(&p);
        let mut it = kids(p).peekable();
        let kind = match it.next()?.as_str() {
            "raster" => "Raster",
            "fullscreen" => "Fullscreen",
            _ => "Compute",
        };
        let name = self.name(it.next()?)?;
        let mut f = Fields::default();
        f.put("name", name.span, name.clone());
        if it.peek().map(|n| n.as_rule()) == Some(Rule::string) {
            let s = it.next()?;
            f.put("shader", self.span(&s), self.string(s)?);
        }
        if it.peek().map(|n| n.as_rule()) == Some(Rule::like) {
            let l = it.next()?;
            f.put("like", self.span(&l), self.like(l)?);
        }
        for item in it {
            let at = self.span(&item);
            let key = pass_key(item.as_rule());
            let errors = self.diags.error_count();
            let Some(node) = self.pass_item(item, at) else {
                // Never drop a pass without a word: a form the grammar takes but this reader
                // does not is an error at it.
                if self.diags.error_count() == errors {
                    self.err(Diagnostic::error(Code::LbpSyntax, format!("cannot read this `{key}`"), at));
                }
                return None;
            };
            f.put(key, at, node);
        }
        // A pass is named by its name: messages about the pass as a whole point there.
        Some(Node::structure(kind, name.span, f.0, span))
    }

    /// `group { … }`: its attributes as fields, its passes and groups in `passes`.
    fn group(&mut self, p: P) -> Option<Node> {
        let span = self.span(&p);
        let head = Span::new(span.file, span.start as usize, span.start as usize + "group".len());
        let mut f = Fields::default();
        let mut passes = vec![];
        for item in kids(p) {
            let at = self.span(&item);
            match item.as_rule() {
                Rule::pass => passes.push(self.pass(item)?),
                Rule::group => passes.push(self.group(item)?),
                Rule::like => f.put("like", at, self.like(item)?),
                Rule::name => f.put("name", at, self.name(item)?),
                rule => {
                    let key = pass_key(rule);
                    let node = self.pass_item(item, at)?;
                    f.put(key, at, node);
                }
            }
        }
        f.put("passes", span, Node::list(passes, span));
        Some(Node::structure("Group", head, f.0, span))
    }

    /// `like NAME(ARGS)`: `Like("NAME", ARGS...)`; `like A, B(ARGS)` a list of them.
    fn like(&mut self, p: P) -> Option<Node> {
        let span = self.span(&p);
        let refs = kids(p).filter(|k| k.as_rule() == Rule::template_ref);
        let mut likes = refs.map(|r| self.template_ref(r)).collect::<Option<Vec<_>>>()?;
        match likes.len() {
            1 => likes.pop(),
            _ => Some(Node::list(likes, span)),
        }
    }

    fn template_ref(&mut self, p: P) -> Option<Node> {
        let span = self.span(&p);
        let mut it = kids(p);
        let mut items = vec![self.name(it.next()?)?];
        for a in it {
            let v = kids(a).next()?;
            // A lone name is a value (a string, as `name` reads it); `a | b` options joined.
            let arg = match v.as_rule() {
                Rule::arm_key if kids(v.clone()).count() > 1 => self.option_list(v)?,
                Rule::arm_key => self.name(kids(v).next()?)?,
                _ => self.value(v)?,
            };
            items.push(arg);
        }
        Some(Node::call("Like", items, span))
    }

    /// `template NAME(PARAMS) like OTHER(ARGS) { … }`: the entry `NAME: Template(parameters:
    /// [..], like: .., ATTRIBUTES)` of the pipeline's `templates`.
    fn template(&mut self, p: P) -> Option<(Node, Node)> {
        let span = self.span(&p);
        let mut it = kids(p).peekable();
        let name = self.name(it.next()?)?;
        let mut f = Fields::default();
        if it.peek().map(|n| n.as_rule()) == Some(Rule::template_params) {
            let ps = it.next()?;
            let at = self.span(&ps);
            let names = kids(ps).map(|i| Node::str(i.as_str(), self.span(&i))).collect();
            f.put("parameters", at, Node::list(names, at));
        }
        for item in it {
            let at = self.span(&item);
            if item.as_rule() == Rule::like {
                f.put("like", at, self.like(item)?);
                continue;
            }
            let key = pass_key(item.as_rule());
            let node = self.pass_item(item, at)?;
            f.put(key, at, node);
        }
        Some((name.clone(), Node::structure("Template", name.span, f.0, span)))
    }

    fn pass_item(&mut self, item: P, at: Span) -> Option<Node> {
        let rule = item.as_rule();
        if rule == Rule::per_face || rule == Rule::always || rule == Rule::shadow_casters {
            return Some(Node::bool(true, at));
        }
        if kids(item.clone()).next().is_some_and(|k| k.as_rule() == Rule::match_head) {
            return self.choice(item, at, |s, parts, span| s.pass_value(rule, parts, span));
        }
        self.pass_value(rule, kids(item).collect(), at)
    }

    /// A pass field's value from its parts (the keyword's, or a choice's arm's).
    fn pass_value(&mut self, rule: Rule, mut parts: Vec<P>, at: Span) -> Option<Node> {
        match rule {
            Rule::pass_per_light => Some(self.per_light(parts.pop()?)),
            Rule::shader => self.string_or_arg(parts.pop()?),
            Rule::vertex | Rule::entry => self.stage_ref(parts.pop()?),
            Rule::fragment => {
                let inner = parts.pop()?;
                if inner.as_rule() == Rule::none {
                    Some(Node::ident("None", self.span(&inner)))
                } else {
                    self.stage_ref(inner)
                }
            }
            Rule::draw => {
                let inner = parts.pop()?;
                match inner.as_rule() {
                    Rule::vertices => Some(Node::call("Vertices", vec![self.uint(&kids(inner).next()?)?], at)),
                    Rule::triangles => Some(Node::call("Triangles", vec![self.uint(&kids(inner).next()?)?], at)),
                    _ => Some(self.word(&inner)),
                }
            }
            Rule::cull => Some(self.word(&parts.pop()?)),
            Rule::instances | Rule::multiview => self.uint(&parts.pop()?),
            Rule::color => {
                let targets = parts.into_iter().map(|t| match t.as_rule() {
                    Rule::color_match => self.element_choice(t, |s, t| s.target(t, "Target")),
                    _ => self.target(t, "Target"),
                });
                Some(Node::list(targets.collect::<Option<Vec<_>>>()?, at))
            }
            Rule::depth => self.target(parts.pop()?, "Depth"),
            Rule::reads => {
                let reads = parts.into_iter().map(|r| self.read(r)).collect::<Option<Vec<_>>>()?;
                Some(Node::list(reads, at))
            }
            Rule::writes | Rule::params => self.names(parts.pop()?),
            Rule::param_block | Rule::after => self.name(parts.pop()?),
            Rule::bind => {
                let pairs = parts.into_iter().map(|b| self.binding(b)).collect::<Option<Vec<_>>>()?;
                Some(Node::map(pairs, at))
            }
            // A choice's arm may be `true`/`false`: lowering says that `when` takes no choice.
            Rule::when => {
                let v = parts.pop()?;
                match v.as_rule() {
                    Rule::bool => Some(Node::bool(v.as_str() == "true", at)),
                    _ => self.cond(v),
                }
            }
            Rule::per_mip => {
                let (to, from) = (self.uint(&parts.pop()?)?, self.uint(&parts.pop()?)?);
                Some(Node::tuple(vec![from, to], at))
            }
            Rule::repeat => {
                let inner = parts.pop()?;
                match inner.as_rule() {
                    Rule::repeat_param => Some(Node::call("Param", vec![self.name(kids(inner).next()?)?], at)),
                    _ => self.uint(&inner),
                }
            }
            Rule::set => {
                let pairs = parts.into_iter().map(|s| self.setting(s)).collect::<Option<Vec<_>>>()?;
                Some(Node::map(pairs, at))
            }
            Rule::constants => {
                let pairs = parts.into_iter().map(|c| self.constant(c)).collect::<Option<Vec<_>>>()?;
                Some(Node::map(pairs, at))
            }
            _ => self.dispatch(parts.pop()?),
        }
    }

    fn stage_ref(&mut self, p: P) -> Option<Node> {
        let inner = kids(p).next()?;
        match inner.as_rule() {
            Rule::string => self.string(inner),
            Rule::arg => Some(self.arg(&inner)),
            _ => Some(Node::str(inner.as_str(), self.span(&inner))),
        }
    }

    fn read(&mut self, r: P) -> Option<Node> {
        let inner = kids(r).next()?;
        let span = self.span(&inner);
        match inner.as_rule() {
            Rule::read_match => self.element_choice(inner, Self::read),
            Rule::prev => Some(Node::call("Prev", vec![self.name(kids(inner).next()?)?], span)),
            Rule::mip_read => {
                let mut k = kids(inner);
                let name = self.name(k.next()?)?;
                Some(Node::call("Mip", vec![name, self.mip_sel(k.next()?)?], span))
            }
            Rule::layer_read => {
                let mut k = kids(inner);
                let name = self.name(k.next()?)?;
                let at = k.next()?;
                let layer = match at.as_rule() {
                    Rule::rep_sel => self.rep(&at)?,
                    _ => self.uint(&at)?,
                };
                Some(Node::call("Layer", vec![name, layer], span))
            }
            _ => self.name(inner),
        }
    }

    /// `2` is `Level(2)`; `rep`, `rep-1`, `rep+1` are `Rep(0)`, `Rep(-1)`, `Rep(1)`.
    fn mip_sel(&mut self, p: P) -> Option<Node> {
        let span = self.span(&p);
        let inner = kids(p).next()?;
        if inner.as_rule() == Rule::uint {
            return Some(Node::call("Level", vec![self.uint(&inner)?], span));
        }
        self.rep(&inner)
    }

    /// `rep`, `rep-1`, `rep+1`: `Rep(0)`, `Rep(-1)`, `Rep(1)`.
    fn rep(&mut self, p: &P) -> Option<Node> {
        let span = self.span(p);
        let offset = p.as_str().trim_start_matches("rep").trim_start_matches('+');
        let d: i64 = match offset.parse() {
            _ if offset.is_empty() => 0,
            Ok(d) => d,
            Err(_) => {
                return self.err(Diagnostic::error(
                    Code::BadNumber,
                    format!("`{offset}` is not a repetition offset"),
                    span,
                ))
            }
        };
        Some(Node::call("Rep", vec![Node::int(d, span)], span))
    }

    fn setting(&mut self, s: P) -> Option<(Node, Node)> {
        let mut kv = kids(s);
        Some((self.name(kv.next()?)?, self.value(kv.next()?)?))
    }

    /// `NAME = 4 | true | param(p) | variant(v, o)`.
    fn constant(&mut self, c: P) -> Option<(Node, Node)> {
        let mut k = kids(c);
        let name = self.name(k.next()?)?;
        let v = k.next()?;
        let span = self.span(&v);
        let value = match v.as_rule() {
            Rule::const_param => Node::call("Param", vec![self.name(kids(v).next()?)?], span),
            Rule::const_variant => {
                let names = kids(v).map(|n| self.name(n)).collect::<Option<Vec<_>>>()?;
                Node::call("Variant", names, span)
            }
            Rule::bool => Node::bool(v.as_str() == "true", span),
            _ => self.number(&v)?,
        };
        Some((name, value))
    }

    fn binding(&mut self, b: P) -> Option<(Node, Node)> {
        let mut kv = kids(b);
        Some((self.name(kv.next()?)?, self.name(kv.next()?)?))
    }

    fn dispatch(&mut self, inner: P) -> Option<Node> {
        let span = self.span(&inner);
        match inner.as_rule() {
            Rule::groups => {
                let g = kids(inner).map(|n| self.uint(&n)).collect::<Option<Vec<_>>>()?;
                Some(Node::call("Groups", g, span))
            }
            _ => Some(Node::call("Size", vec![self.name(kids(inner).next()?)?], span)),
        }
    }

    /// A color (`Target`) or depth (`Depth`) target: its name alone, or its options.
    fn target(&mut self, p: P, kind: &str) -> Option<Node> {
        let span = self.span(&p);
        let mut it = kids(p);
        let resource = self.name(it.next()?)?;
        let mut f = Fields::default();
        f.put("resource", resource.span, resource.clone());
        for opt in it {
            let o = kids(opt).next()?;
            let at = self.span(&o);
            let rule = o.as_rule();
            let key = match rule {
                Rule::clear => "clear",
                Rule::load => "load",
                Rule::blend => "blend",
                Rule::layer => "layer",
                Rule::target_mip => "mip",
                Rule::compare => "compare",
                _ => "write",
            };
            let node = match rule {
                Rule::load => Node::ident("Load", at),
                Rule::nowrite => Node::bool(false, at),
                Rule::clear => self.clear(kids(o).next()?, kind)?,
                Rule::layer => {
                    let w = kids(o).next()?;
                    match w.as_rule() {
                        Rule::uint => Node::call("Index", vec![self.uint(&w)?], at),
                        Rule::arg => Node::call("Index", vec![self.arg(&w)], at),
                        Rule::rep_sel => self.rep(&w)?,
                        _ => self.word(&w),
                    }
                }
                Rule::target_mip => self.mip_sel(kids(o).next()?)?,
                _ => self.word(&kids(o).next()?),
            };
            f.put(key, at, node);
        }
        if f.0.len() == 1 {
            return Some(resource);
        }
        Some(Node::structure(kind, span, f.0, span))
    }

    /// `clear(r, g, b, a)` for color; a depth clear is one value, `clear(1.0)`.
    fn clear(&mut self, t: P, kind: &str) -> Option<Node> {
        let tuple = self.tuple(t)?;
        match &*tuple.value {
            Value::Tuple { items, .. } if kind == "Depth" && items.len() == 1 => Some(items[0].clone()),
            _ => Some(tuple),
        }
    }

    fn cond(&mut self, p: P) -> Option<Node> {
        let span = self.span(&p);
        let inner = kids(p).next()?;
        match inner.as_rule() {
            Rule::reflective => Some(Node::ident("Reflective", span)),
            Rule::blended => Some(Node::ident("Blended", span)),
            Rule::let_ref => Some(Node::call("Let", vec![Node::str(inner.as_str(), span)], span)),
            Rule::not_cond => {
                let negated = kids(inner).find(|k| k.as_rule() == Rule::cond)?;
                Some(Node::call("Not", vec![self.cond(negated)?], span))
            }
            Rule::all_cond | Rule::any_cond => {
                let name = if inner.as_rule() == Rule::all_cond { "All" } else { "Any" };
                let cs = kids(inner).map(|c| self.cond(c)).collect::<Option<Vec<_>>>()?;
                Some(Node::call(name, vec![Node::list(cs, span)], span))
            }
            _ => self.call_cond(inner, span),
        }
    }

    /// A condition's argument after the first: a name, or names joined by `|` as one string
    /// (a variant's options, `variant(v, a | b)`).
    fn option_list(&mut self, p: P) -> Option<Node> {
        if p.as_rule() != Rule::arm_key {
            return self.name(p);
        }
        let span = self.span(&p);
        let names = kids(p).map(|n| self.name(n)).collect::<Option<Vec<_>>>()?;
        match names.as_slice() {
            [one] => Some(one.clone()),
            _ => {
                let texts: Vec<&str> = names.iter().map(|n| n.text().unwrap_or("")).collect();
                Some(Node::str(texts.join(" | "), span))
            }
        }
    }

    /// `light(Point)`, `effect(Ssr)`, `toggle(p)`, `variant(v, o)`, `variant(v, a | b)`.
    fn call_cond(&mut self, inner: P, span: Span) -> Option<Node> {
        let mut it = kids(inner);
        let f = it.next()?;
        let args: Vec<P> = it.collect();
        let (name, words) = match f.as_str() {
            "light" => ("Light", true),
            "effect" => ("Effect", true),
            "toggle" => ("Toggle", false),
            "variant" => ("Variant", false),
            other => {
                let d = Diagnostic::error(Code::UnknownKind, format!("unknown condition `{other}`"), self.span(&f))
                    .with_note(suggestion_note(other, &CONDITIONS));
                return self.err(d);
            }
        };
        // Kinds and effects are enum values; toggles and variants name declarations; a
        // variant's option may be several, `a | b` (true while any is chosen).
        let args = args
            .into_iter()
            .map(|a| {
                let n = self.option_list(a)?;
                Some(if words { Node::ident(n.text().unwrap_or(""), n.span) } else { n })
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Node::call(name, args, span))
    }

    /// `let NAME = CONDITION`.
    fn let_decl(&mut self, p: P) -> Option<(Node, Node)> {
        let mut it = kids(p);
        let name = self.name(it.next()?)?;
        let cond = self.cond(it.next()?)?;
        Some((name, cond))
    }

    fn variant(&mut self, p: P) -> Option<(Node, Node)> {
        let span = self.span(&p);
        let mut it = kids(p);
        let name = self.name(it.next()?)?;
        let default = it.next()?;
        let mut f = Fields::default();
        f.put("default", self.span(&default), self.name(default)?);
        let mut options = vec![];
        let mut opts_span = name.span;
        for item in it {
            let at = self.span(&item);
            match item.as_rule() {
                Rule::doc => f.put("doc", at, self.string(kids(item).next()?)?),
                _ => {
                    options.extend(self.option(item));
                    opts_span = opts_span.to(at);
                }
            }
        }
        f.put("options", opts_span, Node::map(options, opts_span));
        Some((name.clone(), Node::structure("Variant", name.span, f.0, span)))
    }

    fn option(&mut self, p: P) -> Option<(Node, Node)> {
        let span = self.span(&p);
        let mut it = kids(p);
        let name = self.name(it.next()?)?;
        let mut f = Fields::default();
        for item in it {
            let at = self.span(&item);
            if item.as_rule() == Rule::doc {
                f.put("doc", at, self.string(kids(item).next()?)?);
                continue;
            }
            let inner = kids(item).next()?;
            let at = self.span(&inner);
            match inner.as_rule() {
                Rule::requires => f.put("requires", at, Node::list(kids(inner).map(|w| self.word(&w)).collect(), at)),
                Rule::limit => {
                    let items = kids(inner)
                        .map(|li| {
                            let mut kv = kids(li);
                            let k = kv.next()?;
                            Some((Node::str(k.as_str(), self.span(&k)), self.uint(&kv.next()?)?))
                        })
                        .collect::<Option<Vec<_>>>()?;
                    f.put("limits", at, Node::map(items, at));
                }
                Rule::fallback => f.put("fallback", at, self.name(kids(inner).next()?)?),
                Rule::preset => {
                    let pairs = kids(inner).map(|s| self.setting(s)).collect::<Option<Vec<_>>>()?;
                    f.put("params", at, Node::map(pairs, at));
                }
                Rule::opt_jitter => f.put("jitter", at, Node::bool(true, at)),
                _ => {
                    let subs = kids(inner)
                        .map(|sub| {
                            let mut kv = kids(sub);
                            Some((self.name(kv.next()?)?, self.string(kv.next()?)?))
                        })
                        .collect::<Option<Vec<_>>>()?;
                    f.put("shaders", at, Node::map(subs, at));
                }
            }
        }
        let node = Node::new(Value::Struct { name: None, fields: f.0 }, span);
        Some((name, node))
    }
}

/// A pipeline's `use`, `fix` and `remove`, gathered from their lines.
#[derive(Default)]
struct Composing {
    /// Every `use` line (composition reports a second one).
    used: Vec<(Span, Node)>,
    fix: Vec<(Node, Node)>,
    fix_span: Option<Span>,
    remove: Vec<Node>,
    remove_span: Option<Span>,
}

impl Composing {
    fn put(self, root: &mut Fields) {
        for (at, u) in self.used {
            root.put("use", at, u);
        }
        if let Some(at) = self.fix_span {
            root.put("fix", at, Node::map(self.fix, at));
        }
        if let Some(at) = self.remove_span {
            root.put("remove", at, Node::list(self.remove, at));
        }
    }
}

/// A struct node with one more field.
fn with_field(n: Node, key: &str, value: Node) -> Node {
    match &*n.value {
        Value::Struct { name, fields } => {
            let mut fields = fields.clone();
            fields.push((key.to_string(), value.span, value));
            Node::new(
                Value::Struct {
                    name: name.clone(),
                    fields,
                },
                n.span,
            )
        }
        _ => n,
    }
}

/// The tree key of a pass property: its keyword (the grammar's pass items are exactly these).
fn pass_key(r: Rule) -> &'static str {
    match super::keyword(&r) {
        Some("set") => "values",
        Some(k) => k,
        None => "dispatch",
    }
}
