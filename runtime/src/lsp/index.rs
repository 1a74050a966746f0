//! Language server, index: what a pipeline declares (parameters, samplers, resources,
//! passes, variants and their options) and every place the pipeline names them, from the
//! one IR the compiler lowers both front ends to, with the spans it carries. Hover,
//! definition, references, rename, symbols and completion read it.

use lightbench_compiler::format::TextureFormat;
use lightbench_compiler::front::item_start;
use lightbench_compiler::ir::{
    Condition, Constant, Param, Pass, PassKind, Pipeline, Repeat, Resource, ResourceKind, SamplerDecl, SizeSpec, Variant,
};
use lightbench_compiler::span::{SourceMap, Span, Spanned};
use lightbench_compiler::tree::{Node, Value};
use std::collections::{BTreeSet, HashMap};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    Param,
    Sampler,
    Resource,
    Pass,
    Variant,
    /// An option of the variant at this index of `symbols`.
    Option(usize),
    /// A named condition (`let`).
    Let,
    /// Attributes written once (`template`), given to the passes and groups `like` it.
    Template,
}

impl Kind {
    pub fn word(self) -> &'static str {
        match self {
            Kind::Param => "parameter",
            Kind::Sampler => "sampler",
            Kind::Resource => "resource",
            Kind::Pass => "pass",
            Kind::Variant => "variant",
            Kind::Option(_) => "option",
            Kind::Let => "named condition",
            Kind::Template => "template",
        }
    }
}

pub struct Symbol {
    pub kind: Kind,
    pub name: String,
    /// Where it is declared (its name).
    pub decl: Span,
    /// The whole declaration (for document symbols).
    pub extent: Span,
    /// Markdown shown on hover.
    pub hover: String,
}

/// A shader named by a pass: the file, and the entry point when the text names one.
pub struct ShaderUse {
    pub file: Spanned<String>,
    pub entry: Option<Spanned<String>>,
    /// The pass naming it.
    pub pass: String,
}

pub struct Index {
    pub symbols: Vec<Symbol>,
    /// (span, symbol): every naming of a symbol, declarations included.
    pub uses: Vec<(Span, usize)>,
    pub shaders: Vec<ShaderUse>,
    /// Each symbol's index by kind and name (lookups stay linear in the document's size).
    by_name: HashMap<(Kind, String), usize>,
    /// The first symbol declared at each place (passes a choice by light kind makes share one).
    by_decl: HashMap<(Kind, Span), usize>,
    /// Every texture format written (hover describes it).
    pub formats: Vec<Spanned<TextureFormat>>,
    /// The source map the spans point into.
    pub sources: SourceMap,
}

impl Index {
    pub fn of(p: &Pipeline, sources: SourceMap) -> Index {
        let mut ix = Index {
            symbols: vec![],
            uses: vec![],
            shaders: vec![],
            formats: vec![],
            by_name: HashMap::new(),
            by_decl: HashMap::new(),
            sources,
        };
        p.params
            .iter()
            .for_each(|x| ix.declare(Kind::Param, &x.name, x.span, param_hover(x)));
        p.samplers
            .iter()
            .for_each(|x| ix.declare(Kind::Sampler, &x.name, x.span, sampler_hover(x)));
        p.resources
            .iter()
            .for_each(|x| ix.declare(Kind::Resource, &x.name, x.span, resource_hover(p, x)));
        for pass in p.written_passes() {
            ix.declare(Kind::Pass, &pass.name, pass.span, pass_hover(p, pass));
        }
        for v in &p.variants {
            ix.declare(Kind::Variant, &v.name, v.span, variant_hover(v));
            let vi = ix.symbols.len() - 1;
            for o in &v.options {
                let hover = format!(
                    "**option** `{}` of variant `{}`\n\n{}",
                    o.name.value,
                    v.name.value,
                    o.doc.clone().unwrap_or_default()
                );
                ix.declare(Kind::Option(vi), &o.name, o.span, hover);
            }
        }
        for l in &p.lets {
            let hover = format!("**let** `{}` = `{}`", l.name.value, l.value.value.describe());
            ix.declare(Kind::Let, &l.name, l.name.span.to(l.value.span), hover);
        }
        ix.templates(p);
        ix.name_uses(p);
        ix.uses.sort_by_key(|(s, i)| (s.file, s.start, s.end, *i));
        ix.uses.dedup();
        ix
    }

    fn declare(&mut self, kind: Kind, name: &Spanned<String>, extent: Span, hover: String) {
        // A pass written with choices has a copy per arm: declared once.
        if self.find(kind, &name.value).is_some() {
            return;
        }
        // The passes one pass makes by choosing by light kind share its written name: the
        // first one's hover there shows each of them.
        let sibling = self.by_decl.get(&(kind, name.span)).copied();
        match sibling {
            Some(first) => self.symbols[first].hover.push_str(&format!("\n\n---\n\n{hover}")),
            None => _ = self.by_decl.insert((kind, name.span), self.symbols.len()),
        }
        self.by_name.insert((kind, name.value.clone()), self.symbols.len());
        self.symbols.push(Symbol {
            kind,
            name: name.value.clone(),
            decl: name.span,
            extent,
            hover,
        });
        if sibling.is_none() {
            self.uses.push((name.span, self.symbols.len() - 1));
        }
    }

    /// Templates and the items `like` them: only the file as written holds them (they are
    /// given before lowering).
    fn templates(&mut self, p: &Pipeline) {
        let Some(root) = p.written.as_ref().map(|w| &w.0) else { return };
        let Value::Struct { fields, .. } = &*root.value else { return };
        let mut likes = vec![];
        for (key, _, v) in fields {
            likes_under(key, v, &mut likes);
        }
        let entries = match fields.iter().find(|f| f.0 == "templates").map(|f| &*f.2.value) {
            Some(Value::Map(entries)) => entries.as_slice(),
            _ => &[],
        };
        for (k, v) in entries {
            let name = k.text().unwrap_or("").to_string();
            let users: Vec<&str> = likes.iter().filter(|l| l.0 == name).map(|l| l.2.as_str()).collect();
            let hover = template_hover(&name, v, &users);
            let extent = item_start(k, v).to(v.span);
            self.declare(Kind::Template, &Spanned::new(name, k.span), extent, hover);
        }
        for (name, span, _) in likes {
            self.name_use(Kind::Template, &Spanned::new(name, span));
        }
    }

    /// The symbol of this kind and name.
    pub fn find(&self, kind: Kind, name: &str) -> Option<usize> {
        self.by_name.get(&(kind, name.to_string())).copied()
    }

    fn name_use(&mut self, kind: Kind, name: &Spanned<String>) {
        if let Some(i) = self.find(kind, &name.value) {
            self.uses.push((name.span, i));
        }
    }

    fn name_uses(&mut self, p: &Pipeline) {
        for pass in &p.passes {
            self.pass_uses(pass);
        }
        for l in &p.lets {
            self.condition_uses(&l.value.value);
        }
        for v in &p.variants {
            let vi = self.find(Kind::Variant, &v.name.value);
            for o in &v.options {
                o.shaders.iter().for_each(|(pass, _)| self.name_use(Kind::Pass, pass));
                o.params.iter().for_each(|(prm, _)| self.name_use(Kind::Param, prm));
                if let (Some(vi), Some(f)) = (vi, &o.fallback) {
                    self.name_use(Kind::Option(vi), f);
                }
            }
            if let Some(vi) = vi {
                self.name_use(Kind::Option(vi), &v.default);
            }
        }
        self.name_use(Kind::Resource, &p.output);
        if let Some(h) = &p.hdr_output {
            self.name_use(Kind::Resource, h);
        }
        for r in &p.resources {
            if let ResourceKind::Texture(t) = &r.kind {
                self.formats.push(t.format.clone());
                if let SizeSpec::Param(n) | SizeSpec::ViewportParam(n) = &t.size.value {
                    self.name_within(Kind::Param, t.size.span, n);
                }
            }
        }
    }

    /// A name written inside a larger spanned value (`param(shadow.size)`, a constant's
    /// `param(…)`): its first whole-word occurrence there.
    fn name_within(&mut self, kind: Kind, within: Span, name: &str) {
        let Some(i) = self.find(kind, name) else { return };
        let text = &self.sources.get(within.file).text;
        let Some(inner) = text.get(within.start as usize..within.end as usize) else {
            return;
        };
        let is_word = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '.';
        let found = inner.match_indices(name).find(|(at, _)| {
            let before = inner[..*at].chars().next_back();
            let after = inner[at + name.len()..].chars().next();
            !before.is_some_and(is_word) && !after.is_some_and(is_word)
        });
        if let Some((at, _)) = found {
            let start = within.start + at as u32;
            let span = Span {
                start,
                end: start + name.len() as u32,
                ..within
            };
            self.uses.push((span, i));
        }
    }

    fn pass_uses(&mut self, pass: &Pass) {
        self.name_use(Kind::Pass, &pass.name);
        let resources: Vec<&Spanned<String>> = pass
            .reads
            .iter()
            .map(|r| r.name())
            .chain(&pass.writes)
            .chain(pass.color().iter().map(|c| &c.resource))
            .chain(pass.depth().map(|d| &d.resource))
            .collect();
        resources.into_iter().for_each(|r| self.name_use(Kind::Resource, r));
        pass.params.iter().for_each(|prm| self.name_use(Kind::Param, prm));
        for (_, declared) in &pass.bind {
            self.name_use(Kind::Resource, declared);
            self.name_use(Kind::Sampler, declared);
        }
        let when = pass.choice.as_ref().map_or(&pass.when, |c| &c.when);
        if let Some(w) = when {
            self.condition_uses(&w.value);
        }
        for (_, c) in &pass.constants {
            if let Constant::Param(n) = &c.value {
                self.name_within(Kind::Param, c.span, n);
            }
        }
        if let Some(Spanned {
            value: Repeat::Param(n),
            span,
        }) = &pass.repeat
        {
            self.name_within(Kind::Param, *span, n);
        }
        for (_, sref) in pass.stages() {
            // The built-in full-screen vertex stage is named by no text.
            if sref.file.span != pass.span {
                // The entry point as written, or the default one the pass runs.
                let entry = (sref.entry.span != pass.span).then(|| sref.entry.clone());
                // One file may serve several stages, each with its entry point.
                let entry_span = entry.as_ref().map(|e| e.span);
                let known = |s: &ShaderUse| s.file.span == sref.file.span && s.entry.as_ref().map(|e| e.span) == entry_span;
                if !self.shaders.iter().any(known) {
                    self.shaders.push(ShaderUse {
                        file: sref.file.clone(),
                        entry,
                        pass: pass.name.value.clone(),
                    });
                }
            }
        }
    }

    fn condition_uses(&mut self, c: &Condition) {
        match c {
            Condition::Toggle(p) => self.name_use(Kind::Param, p),
            Condition::Variant(v, o) => {
                self.name_use(Kind::Variant, v);
                if let Some(vi) = self.find(Kind::Variant, &v.value) {
                    self.name_use(Kind::Option(vi), o);
                }
            }
            Condition::Not(inner) => self.condition_uses(&inner.value),
            // The use of the name; what it names is indexed with its declaration.
            Condition::Named(name, _) => self.name_use(Kind::Let, name),
            Condition::All(cs) | Condition::Any(cs) => cs.iter().for_each(|c| self.condition_uses(&c.value)),
            _ => {}
        }
    }

    /// The symbol named at a byte offset of a file (the innermost naming).
    pub fn at(&self, file: usize, offset: usize) -> Option<usize> {
        self.uses
            .iter()
            .filter(|(s, _)| s.file == file && (s.start as usize) <= offset && offset <= s.end as usize)
            .min_by_key(|(s, _)| s.end - s.start)
            .map(|(_, i)| *i)
    }

    /// The shader file (or `file#entry`) named at a byte offset.
    pub fn shader_at(&self, file: usize, offset: usize) -> Option<&ShaderUse> {
        let inside = |s: &Span| s.file == file && (s.start as usize) <= offset && offset <= s.end as usize;
        self.shaders
            .iter()
            .find(|u| inside(&u.file.span) || u.entry.as_ref().is_some_and(|e| inside(&e.span)))
    }

    /// Every span naming the symbol.
    pub fn uses_of(&self, symbol: usize) -> impl Iterator<Item = Span> + '_ {
        self.uses.iter().filter(move |(_, i)| *i == symbol).map(|(s, _)| *s)
    }

    /// Where a span is, as the protocol says it.
    pub fn location(&self, s: Span) -> Option<lsp_types::Location> {
        let f = self.sources.get(s.file);
        Some(lsp_types::Location {
            uri: super::text::uri_of(std::path::Path::new(&f.name))?,
            range: super::text::range(&f.text, s.start as usize, s.end as usize),
        })
    }

    /// Names of every symbol of a kind.
    pub fn names(&self, kind: Kind) -> BTreeSet<&str> {
        self.symbols.iter().filter(|s| s.kind == kind).map(|s| s.name.as_str()).collect()
    }
}

fn param_hover(p: &Param) -> String {
    let range = match (&p.min, &p.max) {
        (Some(lo), Some(hi)) => format!(" in {}..{}", lo.value.describe(), hi.value.describe()),
        _ => String::new(),
    };
    format!(
        "**parameter** `{}`: {} = {}{range}\n\n{}",
        p.name.value,
        p.ty.value.name(),
        p.default.value.describe(),
        p.doc.clone().unwrap_or_default()
    )
}

fn sampler_hover(s: &SamplerDecl) -> String {
    let compare = s.compare.map(|c| format!(", compare {c:?}")).unwrap_or_default();
    format!(
        "**sampler** `{}`: filter {:?}, mipmap {:?}, address {:?}{compare}",
        s.name.value, s.filter, s.mipmap, s.address
    )
}

fn resource_hover(p: &Pipeline, r: &Resource) -> String {
    let what = match &r.kind {
        ResourceKind::Texture(t) => {
            let mut w = format!("**texture** `{}`: {:?}, {}", r.name.value, t.format.value, t.size.value.describe());
            if t.layers.value > 1 {
                w += &format!(", {} layers ({:?})", t.layers.value, t.view.value);
            }
            if t.mips.value > 1 {
                w += &format!(", {} mips", t.mips.value);
            }
            w
        }
        ResourceKind::Buffer(b) => {
            let per = if b.per_pixel { " per pixel" } else { "" };
            format!("**buffer** `{}`: {} bytes{per}", r.name.value, b.size.value)
        }
        ResourceKind::AccelerationStructure => format!(
            "**acceleration structure** `{}`: the scene's triangles, built by the executor for ray queries",
            r.name.value
        ),
    };
    let passes = |f: &dyn Fn(&Pass) -> bool| {
        let names: Vec<String> = p.written_passes().filter(|x| f(x)).map(|x| format!("`{}`", x.name.value)).collect();
        if names.is_empty() {
            "none".to_string()
        } else {
            names.join(", ")
        }
    };
    let name = r.name.value.as_str();
    let writers = passes(&|x: &Pass| x.written().any(|w| w.value == name));
    let readers = passes(&|x: &Pass| x.reads.iter().any(|rd| rd.name().value == name) || x.depth_tested().is_some_and(|d| d.value == name));
    format!("{what}\n\nwritten by {writers}; read by {readers}")
}

fn pass_hover(p: &Pipeline, pass: &Pass) -> String {
    let kind = match &pass.kind {
        PassKind::Raster(_) => "raster",
        PassKind::Fullscreen(_) => "fullscreen",
        PassKind::Compute(_) => "compute",
    };
    let mut lines = vec![format!("**{kind} pass** `{}`", pass.name.value)];
    let shaders: Vec<String> = p
        .passes
        .iter()
        .filter(|q| q.name.value == pass.name.value)
        .flat_map(|q| q.stages())
        .filter(|(_, s)| s.file.span != pass.span)
        .map(|(st, s)| format!("{:?}: `{}#{}`", st, s.file.value, s.entry.value))
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    lines.extend(shaders);
    if let Some(k) = &pass.per_light {
        let kinds: Vec<&str> = k.value.iter().map(|k| k.name()).collect();
        lines.push(format!("runs per {} light", kinds.join(" or ")));
    }
    let when = pass.choice.as_ref().map_or(&pass.when, |c| &c.when);
    if let Some(w) = when {
        lines.push(format!("when `{}`", w.value.describe()));
    }
    if let Some(from) = &pass.from {
        lines.push(format!("from `{from}`"));
    }
    lines.join("\n\n")
}

fn variant_hover(v: &Variant) -> String {
    let mut lines = vec![format!("**variant** `{}` (default `{}`)", v.name.value, v.default.value)];
    lines.extend(v.doc.clone());
    for o in &v.options {
        let mut line = format!("- `{}`", o.name.value);
        if !o.requires.is_empty() {
            let req: Vec<String> = o.requires.iter().map(|r| format!("{:?}", r.value)).collect();
            line += &format!(" (requires {})", req.join(", "));
        }
        if !o.params.is_empty() {
            let sets: Vec<String> = o
                .params
                .iter()
                .map(|(k, v)| format!("{} = {}", k.value, literal(&v.value)))
                .collect();
            line += &format!(" (presets {})", sets.join(", "));
        }
        if let Some(doc) = &o.doc {
            line += &format!(": {doc}");
        }
        lines.push(line);
    }
    lines.join("\n\n")
}

/// A preset's value as written.
fn literal(l: &lightbench_compiler::ir::Literal) -> String {
    use lightbench_compiler::ir::Literal as L;
    match l {
        L::Int(i) => i.to_string(),
        L::Float(f) => f.to_string(),
        L::Bool(b) => b.to_string(),
        L::Text(t) => t.clone(),
        L::Tuple(v) => format!("({})", v.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(", ")),
        L::Other(o) => o.clone(),
    }
}

/// A shader file's entry points: name, stage and byte offset of the name. WGSL entry points
/// are the functions after `@vertex`, `@fragment` or `@compute`; a GLSL file's is `main`.
pub fn entry_points(text: &str, path: &std::path::Path) -> Vec<(String, &'static str, usize)> {
    if path.extension().and_then(|e| e.to_str()) != Some("wgsl") {
        let at = text.find("main").unwrap_or(0);
        return vec![("main".into(), "glsl", at)];
    }
    let mut out = vec![];
    for (stage, word) in [("vertex", "@vertex"), ("fragment", "@fragment"), ("compute", "@compute")] {
        for (at, _) in text.match_indices(word) {
            let rest = &text[at..];
            let Some(fn_at) = rest.find("fn ") else { continue };
            let name_at = at + fn_at + 3;
            let name: String = text[name_at..]
                .trim_start()
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            let name_at = name_at + (text[name_at..].len() - text[name_at..].trim_start().len());
            if !name.is_empty() {
                out.push((name, stage, name_at));
            }
        }
    }
    out.sort_by_key(|e| e.2);
    out
}

/// Each `like NAME` under a key of the written tree: (template, its span, what is like it).
fn likes_under(key: &str, n: &Node, out: &mut Vec<(String, Span, String)>) {
    match &*n.value {
        Value::Map(entries) if key == "templates" => {
            for (k, v) in entries {
                likes_of(v, &format!("template `{}`", k.text().unwrap_or("")), out);
            }
        }
        Value::List(items) if key == "passes" => {
            for item in items {
                let name = item.fields().iter().find(|f| f.0 == "name").and_then(|f| f.2.text());
                let what = match (item.name(), name) {
                    (Some("Group"), Some(n)) => format!("group `{n}`"),
                    (Some("Group"), None) => "a group".to_string(),
                    (_, n) => format!("pass `{}`", n.unwrap_or("")),
                };
                likes_of(item, &what, out);
                for (k, _, v) in item.fields().iter().filter(|f| f.0 == "passes") {
                    likes_under(k, v, out);
                }
            }
        }
        _ => {}
    }
}

/// The templates an item's `like` names.
fn likes_of(item: &Node, what: &str, out: &mut Vec<(String, Span, String)>) {
    let Some((_, _, like)) = item.fields().iter().find(|f| f.0 == "like") else {
        return;
    };
    let refs: Vec<&Node> = match &*like.value {
        Value::List(items) => items.iter().collect(),
        _ => vec![like],
    };
    for r in refs {
        if let Value::Tuple { items, .. } = &*r.value {
            if let Some(name) = items.first() {
                out.push((name.text().unwrap_or("").to_string(), name.span, what.to_string()));
            }
        }
    }
}

/// A template: its parameters, the attributes it gives, what is like it.
fn template_hover(name: &str, t: &Node, users: &[&str]) -> String {
    let f = t.fields();
    let params = f
        .iter()
        .find(|x| x.0 == "parameters")
        .map(|x| match &*x.2.value {
            Value::List(ps) => format!("({})", ps.iter().filter_map(|p| p.text()).collect::<Vec<_>>().join(", ")),
            _ => String::new(),
        })
        .unwrap_or_default();
    let gives: Vec<String> = f
        .iter()
        .filter(|x| x.0 != "parameters")
        .map(|x| format!("`{}`", if x.0 == "values" { "set" } else { x.0.as_str() }))
        .collect();
    let like = if users.is_empty() {
        "nothing".to_string()
    } else {
        users.join(", ")
    };
    format!(
        "**template** `{name}{params}`

gives {}

like it: {like}",
        gives.join(", ")
    )
}
