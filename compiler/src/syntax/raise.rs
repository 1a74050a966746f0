//! The raise: IR -> syntax tree, the inverse of the lowering, with every key whose value
//! equals the defaults table left out. Both printers print this tree, so RON and LBP agree
//! on what is implied. Nodes keep the spans of the IR items (printers place comments by them).

use super::defaults::is_default;
use crate::ir::*;
use crate::span::{Span, Spanned};
use crate::tree::{Field, Node, Value};

/// Fields of one item, dropping those at their default.
struct Fields {
    owner: &'static str,
    list: Vec<Field>,
}

impl Fields {
    fn new(owner: &'static str) -> Self {
        Fields { owner, list: vec![] }
    }
    fn put(&mut self, key: &str, node: Node) {
        if !is_default(self.owner, key, &node) {
            self.list.push((key.to_string(), node.span, node));
        }
    }
    fn opt(&mut self, key: &str, node: Option<Node>) {
        if let Some(n) = node {
            self.put(key, n);
        }
    }
    fn into_node(self, name: Option<&str>, head: Span, span: Span) -> Node {
        let name = name.map(|n| (n.to_string(), head));
        Node::new(Value::Struct { name, fields: self.list }, span)
    }
}

pub fn pipeline(p: &Pipeline) -> Node {
    // A pipeline that uses another is printed as written: its own items, not the merge.
    if let Some(Source(written)) = &p.written {
        return written.clone();
    }
    let mut f = Fields::new("Pipeline");
    f.put("name", Node::str(&p.name.value, p.name.span));
    let nonempty = |n: Node| matches!(&*n.value, Value::Map(m) if !m.is_empty()).then_some(n);
    f.opt("params", nonempty(named_map(&p.params, |x| &x.name, param, p.span)));
    f.opt("samplers", nonempty(named_map(&p.samplers, |x| &x.name, sampler, p.span)));
    f.opt("resources", nonempty(named_map(&p.resources, |x| &x.name, resource, p.span)));
    let named = |l: &crate::ir::LetDecl| condition(&l.value.value, l.value.span);
    f.opt("lets", nonempty(named_map(&p.lets, |x| &x.name, named, p.span)));
    f.put("passes", Node::list(p.written_passes().map(written_pass).collect(), p.span));
    f.opt("variants", nonempty(named_map(&p.variants, |x| &x.name, variant, p.span)));
    f.opt("hdr_output", p.hdr_output.as_ref().map(|h| Node::str(&h.value, h.span)));
    f.put("output", Node::str(&p.output.value, p.output.span));
    f.put("always", Node::bool(p.always, p.span));
    f.put("jitter", Node::bool(p.jitter, p.span));
    f.into_node(Some("Pipeline"), p.span, p.span)
}

fn named_map<T>(items: &[T], name: impl Fn(&T) -> &crate::span::Spanned<String>, raise: impl Fn(&T) -> Node, span: Span) -> Node {
    let entries = items.iter().map(|i| (Node::str(&name(i).value, name(i).span), raise(i))).collect();
    Node::map(entries, span)
}

fn strs<'a>(items: impl IntoIterator<Item = &'a crate::span::Spanned<String>>, span: Span) -> Node {
    Node::list(items.into_iter().map(|s| Node::str(&s.value, s.span)).collect(), span)
}

fn kinds(k: &[LightKind], span: Span) -> Node {
    Node::list(k.iter().map(|k| Node::ident(k.name(), span)).collect(), span)
}

fn value(v: &ParamValue, span: Span) -> Node {
    match v {
        ParamValue::Float(f) => Node::float(*f, span),
        ParamValue::Int(i) => Node::int(*i, span),
        ParamValue::Bool(b) => Node::bool(*b, span),
        ParamValue::Vec(v) => Node::tuple(v.iter().map(|x| Node::float(*x, span)).collect(), span),
        ParamValue::Enum(s) => Node::str(s, span),
    }
}

fn constant(c: &Constant, span: Span) -> Node {
    match c {
        Constant::Number(x) => Node::float(*x, span),
        Constant::Bool(b) => Node::bool(*b, span),
        Constant::Param(p) => Node::call("Param", vec![Node::str(p, span)], span),
        Constant::Variant(v, o) => Node::call("Variant", vec![Node::str(v, span), Node::str(o, span)], span),
    }
}

fn literal(l: &Literal, span: Span) -> Node {
    match l {
        Literal::Int(i) => Node::int(*i, span),
        Literal::Float(f) => Node::float(*f, span),
        Literal::Bool(b) => Node::bool(*b, span),
        Literal::Tuple(v) => Node::tuple(v.iter().map(|x| Node::float(*x, span)).collect(), span),
        // Lowering refuses anything else in a preset; kept as text should one slip through.
        Literal::Text(s) | Literal::Other(s) => Node::str(s, span),
    }
}

fn param(p: &Param) -> Node {
    let mut f = Fields::new("Param");
    if let ParamType::Enum(opts) = &p.ty.value {
        f.put(
            "options",
            Node::list(opts.iter().map(|o| Node::str(o, p.ty.span)).collect(), p.ty.span),
        );
    }
    f.put("default", value(&p.default, p.default.span));
    f.opt("min", p.min.as_ref().map(|m| value(m, m.span)));
    f.opt("max", p.max.as_ref().map(|m| value(m, m.span)));
    f.opt("doc", p.doc.as_ref().map(|d| Node::str(d, p.span)));
    f.into_node(Some(p.ty.name()), p.ty.span, p.span)
}

fn sampler(s: &SamplerDecl) -> Node {
    let mut f = Fields::new("Sampler");
    f.put("filter", Node::ident(s.filter.name(), s.span));
    f.put("mipmap", Node::ident(s.mipmap.name(), s.span));
    f.put("address", Node::ident(s.address.name(), s.span));
    f.opt("compare", s.compare.map(|c| Node::ident(c.name(), s.span)));
    f.into_node(Some("Sampler"), s.span, s.span)
}

fn size(s: &SizeSpec, span: Span) -> Node {
    match s {
        SizeSpec::Viewport { scale } if *scale == 1.0 => Node::ident("Viewport", span),
        SizeSpec::Viewport { scale } => Node::call("Viewport", vec![Node::float(*scale, span)], span),
        SizeSpec::Param(name) => Node::call("Param", vec![Node::str(name, span)], span),
        SizeSpec::ViewportParam(name) => Node::call("Viewport", vec![Node::call("Param", vec![Node::str(name, span)], span)], span),
        SizeSpec::Fixed { width, height } => {
            Node::call("Fixed", vec![Node::int(*width as i64, span), Node::int(*height as i64, span)], span)
        }
    }
}

fn resource(r: &Resource) -> Node {
    let (kind, mut f) = match &r.kind {
        ResourceKind::AccelerationStructure => {
            return Fields::new("AccelerationStructure").into_node(Some("AccelerationStructure"), r.span, r.span);
        }
        ResourceKind::Texture(t) => {
            let mut f = Fields::new("Texture");
            f.put("format", Node::ident(t.format.value.name(), t.format.span));
            f.put("size", size(&t.size.value, t.size.span));
            f.put("layers", Node::int(t.layers.value as i64, t.layers.span));
            f.put("view", Node::ident(t.view.value.name(), t.view.span));
            f.put("mips", Node::int(t.mips.value as i64, t.mips.span));
            ("Texture", f)
        }
        ResourceKind::Buffer(b) => {
            let mut f = Fields::new("Buffer");
            f.put("size", Node::int(b.size.value as i64, b.size.span));
            f.put("per_pixel", Node::bool(b.per_pixel, b.size.span));
            ("Buffer", f)
        }
    };
    f.opt("per_light", r.per_light().map(|k| kinds(k, k.span)));
    f.put("history", Node::bool(r.history(), r.span));
    f.put("external", Node::bool(r.external(), r.span));
    f.opt("data", r.data().map(|d| data(&d.value, d.span)));
    f.opt(
        "valid",
        r.valid
            .as_ref()
            .map(|v| Node::tuple(vec![Node::float(v.value.0, v.span), Node::float(v.value.1, v.span)], v.span)),
    );
    f.into_node(Some(kind), r.span, r.span)
}

fn data(d: &DataSource, span: Span) -> Node {
    match d {
        DataSource::File(f) => Node::call("File", vec![Node::str(f, span)], span),
        DataSource::F32(v) => Node::call(
            "F32",
            vec![Node::list(v.iter().map(|x| Node::float(*x, span)).collect(), span)],
            span,
        ),
        DataSource::U32(v) => Node::call(
            "U32",
            vec![Node::list(v.iter().map(|x| Node::int(*x as i64, span)).collect(), span)],
            span,
        ),
    }
}

/// How a stage is written given the pass's shader file: `None` when the default applies,
/// `file#entry` for another file, else the entry name.
fn stage_ref(r: &ShaderRef, pass_file: &str, stage: Stage, default_applies: bool) -> Option<Node> {
    let text = if r.file.value != pass_file {
        format!("{}#{}", r.file.value, r.entry.value)
    } else if default_applies && r.entry.value == default_entry(stage, &r.file.value) {
        return None;
    } else {
        r.entry.value.clone()
    };
    Some(Node::str(text, r.entry.span))
}

/// A pass as written: one with choices is its first copy, raised, with the chosen fields
/// (and its own `when`) as the source has them.
fn written_pass(p: &Pass) -> Node {
    let Some((choice, Source(src))) = p.choice.as_ref().and_then(|c| Some((c, c.source.as_ref()?))) else {
        return pass(p);
    };
    let raised = pass(p);
    let (Value::Struct { name, fields }, Value::Struct { fields: written, .. }) = (&*raised.value, &*src.value) else {
        return raised;
    };
    let chosen = |k: &str| written.iter().find(|f| f.0 == k && find_match(&f.2).is_some());
    let mut out: Vec<Field> = vec![];
    for (k, span, v) in fields {
        match (chosen(k), k.as_str()) {
            (Some(f), _) => out.push(f.clone()),
            (None, "when") => {}
            (None, _) => out.push((k.clone(), *span, v.clone())),
        }
    }
    // Chosen fields the first copy leaves at their default: after the field written before them.
    for (i, f) in written.iter().enumerate().filter(|(_, f)| chosen(&f.0).is_some()) {
        if out.iter().any(|o| o.0 == f.0) {
            continue;
        }
        let before = written[..i].iter().rev().find_map(|w| out.iter().position(|o| o.0 == w.0));
        out.insert(before.map_or(out.len().min(1), |b| b + 1), f.clone());
    }
    if let Some(w) = &choice.when {
        let at = out.iter().position(|o| o.0 == "dispatch").unwrap_or(out.len());
        out.insert(at, ("when".into(), w.span, condition(&w.value, w.span)));
    }
    Node::new(
        Value::Struct {
            name: name.clone(),
            fields: out,
        },
        raised.span,
    )
}

fn find_match(n: &Node) -> Option<&Node> {
    super::lower::find_match(n)
}

fn pass(p: &Pass) -> Node {
    let kind = match &p.kind {
        PassKind::Raster(_) => "Raster",
        PassKind::Fullscreen(_) => "Fullscreen",
        PassKind::Compute(_) => "Compute",
    };
    let mut f = Fields::new(kind);
    f.put("name", Node::str(&p.name.value, p.name.span));
    let file = &p.main_stage().file;
    f.put("shader", Node::str(&file.value, file.span));
    match &p.kind {
        PassKind::Raster(r) => raster(&mut f, r, &file.value, p.span),
        PassKind::Fullscreen(fs) => f.opt("fragment", stage_ref(&fs.fragment, &file.value, Stage::Fragment, true)),
        PassKind::Compute(c) => f.opt("entry", stage_ref(&c.entry, &file.value, Stage::Compute, true)),
    }
    f.opt("per_light", p.per_light.as_ref().map(|k| kinds(k, k.span)));
    f.put("per_face", Node::bool(p.per_face, p.span));
    f.put("shadow_casters", Node::bool(p.shadow_casters, p.span));
    f.opt("per_mip", p.per_mip.as_ref().map(|m| mip_range(m.value, m.span)));
    f.opt(
        "repeat",
        p.repeat.as_ref().map(|r| match &r.value {
            Repeat::Times(n) => Node::int(*n as i64, r.span),
            Repeat::Param(name) => Node::call("Param", vec![Node::str(name, r.span)], r.span),
        }),
    );
    f.put("always", Node::bool(p.always, p.span));
    f.put("reads", Node::list(p.reads.iter().map(read).collect(), p.span));
    f.put("writes", strs(&p.writes, p.span));
    if let Some(t) = p.targets() {
        f.put("color", Node::list(t.color.iter().map(color_target).collect(), p.span));
        f.opt("depth", t.depth.as_ref().map(depth_target));
    }
    f.put("params", strs(&p.params, p.span));
    let values = p.values.iter().map(|(k, v)| (Node::str(&k.value, k.span), value(&v.value, v.span)));
    f.put("values", Node::map(values.collect(), p.span));
    let constants = p
        .constants
        .iter()
        .map(|(k, v)| (Node::str(&k.value, k.span), constant(&v.value, v.span)));
    f.put("constants", Node::map(constants.collect(), p.span));
    f.put("param_block", Node::str(&p.param_block.value, p.param_block.span));
    let bind = p
        .bind
        .iter()
        .map(|(k, v)| (Node::str(&k.value, k.span), Node::str(&v.value, v.span)));
    f.put("bind", Node::map(bind.collect(), p.span));
    f.opt("when", p.when.as_ref().map(|w| condition(&w.value, w.span)));
    if let PassKind::Compute(c) = &p.kind {
        f.put("dispatch", dispatch(&c.dispatch.value, p.span));
    }
    f.into_node(Some(kind), p.name.span, p.span)
}

fn raster(f: &mut Fields, r: &Raster, file: &str, span: Span) {
    f.opt("vertex", stage_ref(&r.vertex, file, Stage::Vertex, true));
    let has_color = !r.targets.color.is_empty();
    match &r.fragment {
        None if has_color => f.put("fragment", Node::ident("None", span)),
        None => {}
        Some(fr) => f.opt("fragment", stage_ref(fr, file, Stage::Fragment, has_color)),
    }
    f.put(
        "draw",
        match r.draw {
            Draw::Scene => Node::ident("Scene", span),
            Draw::Transparent => Node::ident("Transparent", span),
            Draw::LightVolume => Node::ident("LightVolume", span),
            Draw::Vertices(n) => Node::call("Vertices", vec![Node::int(n as i64, span)], span),
            Draw::Triangles(n) => Node::call("Triangles", vec![Node::int(n as i64, span)], span),
        },
    );
    f.put("cull", Node::ident(r.cull.name(), span));
    f.put("instances", Node::int(r.instances.value as i64, r.instances.span));
    f.opt("multiview", r.multiview.as_ref().map(|m| Node::int(m.value as i64, m.span)));
}

fn read(r: &Read) -> Node {
    let n = r.name();
    match r {
        Read::Current(_) => Node::str(&n.value, n.span),
        Read::Prev(_) => Node::call("Prev", vec![Node::str(&n.value, n.span)], n.span),
        Read::Mip(_, m) => Node::call("Mip", vec![Node::str(&n.value, n.span), mip(m.value, m.span)], n.span),
        Read::Layer(_, l) => {
            let at = match l.value {
                LayerSel::Rep(d) => Node::call("Rep", vec![Node::int(d as i64, l.span)], l.span),
                other => Node::int(other.at(0, 1).unwrap_or(0) as i64, l.span),
            };
            Node::call("Layer", vec![Node::str(&n.value, n.span), at], n.span)
        }
    }
}

fn mip(m: MipSel, span: Span) -> Node {
    match m {
        MipSel::Level(l) => Node::call("Level", vec![Node::int(l as i64, span)], span),
        MipSel::Rep(d) => Node::call("Rep", vec![Node::int(d as i64, span)], span),
    }
}

fn mip_range(m: MipRange, span: Span) -> Node {
    Node::tuple(vec![Node::int(m.from as i64, span), Node::int(m.to as i64, span)], span)
}

fn layer(l: LayerSel, span: Span) -> Node {
    match l {
        LayerSel::Base => Node::ident("Base", span),
        LayerSel::Face => Node::ident("Face", span),
        LayerSel::All => Node::ident("All", span),
        LayerSel::Index(i) => Node::call("Index", vec![Node::int(i as i64, span)], span),
        LayerSel::Rep(d) => Node::call("Rep", vec![Node::int(d as i64, span)], span),
    }
}

/// A target whose every key is at its default is written as its resource name alone.
fn target(kind: &'static str, f: Fields, resource: &crate::span::Spanned<String>, span: Span) -> Node {
    if f.list.is_empty() {
        return Node::str(&resource.value, resource.span);
    }
    let mut all = Fields::new(kind);
    all.put("resource", Node::str(&resource.value, resource.span));
    all.list.extend(f.list);
    all.into_node(Some(kind), span, span)
}

fn color_target(c: &ColorTarget) -> Node {
    let mut f = Fields::new("Target");
    match c.load {
        Load::Load => f.put("load", Node::ident("Load", c.span)),
        Load::Clear(v) => f.put("clear", Node::tuple(v.iter().map(|x| Node::float(*x, c.span)).collect(), c.span)),
    }
    f.opt("blend", c.blend.as_ref().map(|b| Node::ident(b.value.name(), b.span)));
    f.put("layer", layer(c.layer, c.span));
    f.put("mip", mip(c.mip.value, c.mip.span));
    target("Target", f, &c.resource, c.span)
}

fn depth_target(d: &DepthTarget) -> Node {
    let mut f = Fields::new("Depth");
    match d.load {
        Load::Load => f.put("load", Node::ident("Load", d.span)),
        Load::Clear(v) => f.put("clear", Node::float(v, d.span)),
    }
    f.put("compare", Node::ident(d.compare.name(), d.span));
    f.put("write", Node::bool(d.write, d.span));
    f.put("layer", layer(d.layer, d.span));
    f.put("mip", mip(d.mip.value, d.mip.span));
    target("Depth", f, &d.resource, d.span)
}

fn dispatch(d: &Dispatch, span: Span) -> Node {
    match d {
        Dispatch::Groups(x, y, z) => Node::call("Groups", [x, y, z].iter().map(|v| Node::int(**v as i64, span)).collect(), span),
        Dispatch::Size(r) => Node::call("Size", vec![Node::str(&r.value, r.span)], span),
    }
}

/// `Variant("v", "a | b")` as lowered (several options of one variant sharing the written
/// string's span): the variant, the options as written, and where.
fn compact_options(cs: &[Spanned<Condition>]) -> Option<(Spanned<String>, String, Span)> {
    let mut options = vec![];
    let mut first: Option<(&Spanned<String>, Span)> = None;
    for c in cs {
        let Condition::Variant(v, o) = &c.value else { return None };
        match first {
            None => first = Some((v, o.span)),
            Some((fv, at)) if fv.value == v.value && at == o.span => {}
            _ => return None,
        }
        options.push(o.value.as_str());
    }
    let (v, at) = first.filter(|_| options.len() > 1)?;
    Some((v.clone(), options.join(" | "), at))
}

pub fn condition(c: &Condition, span: Span) -> Node {
    match c {
        Condition::Light(k) => Node::call("Light", vec![Node::ident(k.name(), span)], span),
        Condition::Effect(e) => Node::call("Effect", vec![Node::ident(e.name(), span)], span),
        Condition::Reflective => Node::ident("Reflective", span),
        Condition::Blended => Node::ident("Blended", span),
        Condition::Toggle(p) => Node::call("Toggle", vec![Node::str(&p.value, p.span)], span),
        Condition::Variant(v, o) => Node::call("Variant", vec![Node::str(&v.value, v.span), Node::str(&o.value, o.span)], span),
        Condition::Not(c) => Node::call("Not", vec![condition(&c.value, c.span)], span),
        Condition::Named(name, _) => Node::call("Let", vec![Node::str(&name.value, name.span)], span),
        Condition::All(cs) => Node::call(
            "All",
            vec![Node::list(cs.iter().map(|c| condition(&c.value, c.span)).collect(), span)],
            span,
        ),
        Condition::Any(cs) => match compact_options(cs) {
            Some((v, options, at)) => Node::call("Variant", vec![Node::str(&v.value, v.span), Node::str(options, at)], span),
            None => Node::call(
                "Any",
                vec![Node::list(cs.iter().map(|c| condition(&c.value, c.span)).collect(), span)],
                span,
            ),
        },
    }
}

fn variant(v: &Variant) -> Node {
    let mut f = Fields::new("Variant");
    f.put("default", Node::str(&v.default.value, v.default.span));
    f.opt("doc", v.doc.as_ref().map(|d| Node::str(d, v.span)));
    f.put("options", named_map(&v.options, |o| &o.name, option, v.span));
    f.into_node(Some("Variant"), v.span, v.span)
}

fn option(o: &VariantOption) -> Node {
    let mut f = Fields::new("Option");
    f.put(
        "requires",
        Node::list(o.requires.iter().map(|r| Node::ident(r.value.name(), r.span)).collect(), o.span),
    );
    let limits = o
        .limits
        .iter()
        .map(|(k, n)| (Node::str(&k.value, k.span), Node::int(n.value as i64, n.span)));
    f.put("limits", Node::map(limits.collect(), o.span));
    f.opt("fallback", o.fallback.as_ref().map(|fb| Node::str(&fb.value, fb.span)));
    let shaders = o
        .shaders
        .iter()
        .map(|(k, n)| (Node::str(&k.value, k.span), Node::str(&n.value, n.span)));
    f.put("shaders", Node::map(shaders.collect(), o.span));
    let params = o
        .params
        .iter()
        .map(|(k, v)| (Node::str(&k.value, k.span), literal(&v.value, v.span)));
    f.put("params", Node::map(params.collect(), o.span));
    f.put("jitter", Node::bool(o.jitter, o.span));
    f.opt("doc", o.doc.as_ref().map(|d| Node::str(d, o.span)));
    // Options are written anonymously: `"classic": ()`.
    f.into_node(None, o.span, o.span)
}
