//! Syntax tree -> canonical LBP text. `lightbench fmt` is parse + print; the layout is
//! fixed, so printing what was printed gives the same text (idempotent). What to leave out
//! was decided by the raise (the defaults table); this only spells the tree in LBP.
//! Comments in the source are kept before the item that followed them.

use crate::front::comments::Out;
use crate::front::{item_start, quote};
use crate::ir::Pipeline;
use crate::span::Span;
use crate::syntax::defaults;
use crate::tree::{Field, Node, Value};
use std::borrow::Cow;
use std::fmt::Write;

const RESERVED: [&str; 9] = ["none", "true", "false", "prev", "load", "nowrite", "in", "mip", "rep"];

/// A name as written: bare when it is a dotted identifier, quoted otherwise.
pub fn name(s: &str) -> String {
    let ident = |p: &str| {
        let mut c = p.chars();
        matches!(c.next(), Some(ch) if ch.is_ascii_alphabetic() || ch == '_') && c.all(|ch| ch.is_ascii_alphanumeric() || ch == '_')
    };
    if !s.is_empty() && s.split('.').all(ident) && !RESERVED.contains(&s) {
        s.to_string()
    } else {
        quote(s)
    }
}

pub fn print(p: &Pipeline, source: Option<&str>) -> String {
    print_tree(&crate::syntax::raise::pipeline(p), source)
}

/// The text of a string or identifier; a template's parameter `Arg("x")` as written, `$x`.
fn text(n: &Node) -> Cow<'_, str> {
    match (&*n.value, n.name()) {
        (Value::Tuple { items, .. }, Some("Arg")) => Cow::Owned(format!("${}", items.first().and_then(|i| i.text()).unwrap_or(""))),
        _ => Cow::Borrowed(n.text().unwrap_or("")),
    }
}

/// A name as written (`name`), or a template's parameter standing for one.
fn name_of(n: &Node) -> String {
    match n.name() {
        Some("Arg") => text(n).into_owned(),
        _ => name(&text(n)),
    }
}

/// Options `a | b` as written, or a template's parameter standing for them.
fn options_of(n: &Node) -> String {
    match n.name() {
        Some("Arg") => text(n).into_owned(),
        _ => options(&text(n)),
    }
}

/// A string quoted, or a template's parameter standing for one.
fn quoted(n: &Node) -> String {
    match n.name() {
        Some("Arg") => text(n).into_owned(),
        _ => quote(&text(n)),
    }
}

fn get<'a>(fields: &'a [Field], key: &str) -> Option<&'a Node> {
    fields.iter().find(|f| f.0 == key).map(|f| &f.2)
}

fn fields(n: &Node) -> &[Field] {
    match &*n.value {
        Value::Struct { fields, .. } => fields,
        _ => &[],
    }
}

fn items(n: &Node) -> &[Node] {
    match &*n.value {
        Value::List(items) | Value::Tuple { items, .. } => items,
        _ => &[],
    }
}

fn entries(n: &Node) -> &[(Node, Node)] {
    match &*n.value {
        Value::Map(e) => e,
        _ => &[],
    }
}

/// A value: numbers as written, tuples `(a, b)`, strings as names.
fn value(n: &Node) -> String {
    match &*n.value {
        Value::Bool(b) => b.to_string(),
        Value::Int(i) => i.to_string(),
        // `+ 0.0` turns -0.0 into 0.0: "-0" would read back as an integer, and `fmt` must
        // be idempotent.
        Value::Float(f) => format!("{}", f + 0.0),
        Value::Tuple { .. } if n.name() == Some("Arg") => text(n).into_owned(),
        Value::Tuple { .. } => format!("({})", items(n).iter().map(value).collect::<Vec<_>>().join(", ")),
        _ => name_of(n),
    }
}

fn join(ns: &[Node], f: impl Fn(&Node) -> String) -> String {
    ns.iter().map(f).collect::<Vec<_>>().join(", ")
}

pub fn print_tree(root: &Node, source: Option<&str>) -> String {
    let mut pr = Printer {
        out: Out::new(source, root),
    };
    pr.root(fields(root));
    pr.out.finish()
}

struct Printer {
    out: Out,
}

impl Printer {
    fn root(&mut self, f: &[Field]) {
        if let Some(n) = get(f, "name") {
            self.out.comments_before(n.span, "");
            let _ = writeln!(self.out.text, "pipeline {}", name_of(n));
        }
        self.composing(f);
        for (key, line) in [
            ("params", param as fn(&Node, &Node) -> String),
            ("samplers", sampler),
            ("resources", resource),
            ("lets", let_line),
        ] {
            let Some(map) = get(f, key) else { continue };
            self.out.text.push('\n');
            for (k, v) in entries(map) {
                self.out.comments_before(item_start(k, v), "");
                let l = match replaced(v) {
                    Some(r) => format!("replace {}", line(k, r)),
                    None => line(k, v),
                };
                let _ = writeln!(self.out.text, "{l}");
            }
        }
        for (k, v) in get(f, "templates").map(entries).unwrap_or(&[]) {
            self.template(k, v);
        }
        for p in get(f, "passes").map(items).unwrap_or(&[]) {
            self.pass_or_group(p, "");
        }
        for (k, v) in get(f, "variants").map(entries).unwrap_or(&[]) {
            self.variant(k, v);
        }
        if get(f, "hdr_output").is_some() || get(f, "output").is_some() {
            self.out.text.push('\n');
        }
        for key in ["hdr_output", "output"] {
            if let Some(n) = get(f, key) {
                self.out.comments_before(n.span, "");
                let _ = writeln!(self.out.text, "{key} {}", name_of(n));
            }
        }
        for key in ["always", "jitter"] {
            if let Some(n) = get(f, key) {
                self.out.comments_before(n.span, "");
                let _ = writeln!(self.out.text, "{key}");
            }
        }
    }

    fn pass_or_group(&mut self, p: &Node, indent: &str) {
        match p.name() {
            Some("Group") => self.group(p, indent),
            _ => self.pass(p, indent),
        }
    }

    /// `template NAME(PARAMS) like OTHER(ARGS) {`, its attributes, `}`.
    fn template(&mut self, k: &Node, t: &Node) {
        self.out.text.push('\n');
        self.out.comments_before(item_start(k, t), "");
        let params = get(fields(t), "parameters").map(|p| format!("({})", join(items(p), |n| text(n).into_owned())));
        let _ = writeln!(
            self.out.text,
            "template {}{}{} {{",
            name_of(k),
            params.unwrap_or_default(),
            like(fields(t))
        );
        for (k, _, v) in fields(t).iter().filter(|f| f.0 != "parameters" && f.0 != "like") {
            self.out.comments_before(v.span, "    ");
            let _ = writeln!(self.out.text, "    {}", pass_line(k, v));
        }
        let _ = writeln!(self.out.text, "}}");
    }

    /// `group {`, its attributes, its passes and groups, `}`.
    fn group(&mut self, g: &Node, indent: &str) {
        self.out.text.push('\n');
        self.out.comments_before(g.span, indent);
        let named = get(fields(g), "name").map(|n| format!(" {}", name_of(n))).unwrap_or_default();
        let _ = writeln!(self.out.text, "{indent}group{named}{} {{", like(fields(g)));
        let inner = format!("{indent}    ");
        for (k, _, v) in fields(g).iter().filter(|f| !matches!(f.0.as_str(), "passes" | "like" | "name")) {
            self.out.comments_before(v.span, &inner);
            let _ = writeln!(self.out.text, "{inner}{}", pass_line(k, v));
        }
        for p in get(fields(g), "passes").map(items).unwrap_or(&[]) {
            self.pass_or_group(p, &inner);
        }
        let _ = writeln!(self.out.text, "{indent}}}");
    }

    fn pass(&mut self, p: &Node, indent: &str) {
        self.out.text.push('\n');
        self.out.comments_before(p.span, indent);
        let f = fields(p);
        let kind = p.name().unwrap_or("").to_lowercase();
        let replace = if get(f, "replace").is_some() { "replace " } else { "" };
        // A chosen shader is a line of the body.
        let chosen_shader = get(f, "shader").is_some_and(is_match);
        let shader = get(f, "shader")
            .filter(|_| !chosen_shader)
            .map(|s| format!(" {}", quoted(s)))
            .unwrap_or_default();
        let head = format!(
            "{indent}{replace}{kind} {}{shader}{}",
            name(&get(f, "name").map(text).unwrap_or_default()),
            like(f)
        );
        // Comments inside the pass body come first in it.
        let inner = format!("{indent}    ");
        let end = Span::new(p.span.file, p.span.end as usize, p.span.end as usize);
        let body: Vec<&Field> = f
            .iter()
            .filter(|(k, _, _)| !matches!(k.as_str(), "name" | "replace" | "like") && (k != "shader" || chosen_shader))
            .collect();
        // A pass like a template may say nothing more (a comment in its empty body then
        // goes before what follows it).
        if body.is_empty() && get(f, "like").is_some() {
            let _ = writeln!(self.out.text, "{head}");
            return;
        }
        let _ = writeln!(self.out.text, "{head} {{");
        self.out.comments_before(end, &inner);
        for (k, _, v) in body {
            let _ = writeln!(self.out.text, "{inner}{}", pass_line(k, v));
        }
        let _ = writeln!(self.out.text, "{indent}}}");
    }

    /// `use "file"`, `fix v = o`, `remove kind name`.
    fn composing(&mut self, f: &[Field]) {
        if let Some(u) = get(f, "use") {
            self.out.text.push('\n');
            self.out.comments_before(u.span, "");
            let _ = writeln!(self.out.text, "use {}", quoted(u));
        }
        for (k, v) in get(f, "fix").map(entries).unwrap_or(&[]) {
            self.out.comments_before(item_start(k, v), "");
            let _ = writeln!(self.out.text, "fix {} = {}", name_of(k), name_of(v));
        }
        for r in get(f, "remove").map(items).unwrap_or(&[]) {
            self.out.comments_before(r.span, "");
            let what = r.name().unwrap_or("").to_lowercase();
            let _ = writeln!(
                self.out.text,
                "remove {what} {}",
                name(&items(r).first().map(text).unwrap_or_default())
            );
        }
    }

    fn variant(&mut self, k: &Node, v: &Node) {
        self.out.text.push('\n');
        self.out.comments_before(item_start(k, v), "");
        let (v, replace) = match replaced(v) {
            Some(r) => (r, "replace "),
            None => (v, ""),
        };
        let f = fields(v);
        let doc = get(f, "doc").map(|d| format!(" {}", quoted(d))).unwrap_or_default();
        let default = get(f, "default").map(text).unwrap_or_default();
        let _ = writeln!(self.out.text, "{replace}variant {} = {}{doc} {{", name_of(k), name(&default));
        for (ok, ov) in get(f, "options").map(entries).unwrap_or(&[]) {
            self.out.comments_before(item_start(ok, ov), "    ");
            let _ = writeln!(self.out.text, "    option {}{}", name_of(ok), option(fields(ov)));
        }
        self.out.text.push_str("}\n");
    }
}

fn param(k: &Node, v: &Node) -> String {
    let f = fields(v);
    let ty = match get(f, "options") {
        Some(opts) => format!("enum({})", join(items(opts), name_of)),
        None => v.name().unwrap_or("").to_string(),
    };
    let mut line = format!("param {}: {ty} = {}", name_of(k), get(f, "default").map(value).unwrap_or_default());
    match (get(f, "min"), get(f, "max")) {
        (Some(lo), Some(hi)) => line += &format!(" in {}..{}", value(lo), value(hi)),
        (Some(lo), None) => line += &format!(" min {}", value(lo)),
        (None, Some(hi)) => line += &format!(" max {}", value(hi)),
        (None, None) => {}
    }
    if let Some(d) = get(f, "doc") {
        line += &format!(" {}", quoted(d));
    }
    line
}

fn sampler(k: &Node, v: &Node) -> String {
    let mut line = format!("sampler {}:", name_of(k));
    for (key, _, n) in fields(v) {
        match key.as_str() {
            "mipmap" | "compare" => line += &format!(" {key} {}", text(n)),
            _ => line += &format!(" {}", text(n)),
        }
    }
    line
}

fn size(n: &Node) -> String {
    match n.name() {
        Some("Fixed") => format!("{}x{}", value(&items(n)[0]), value(&items(n)[1])),
        Some("Param") => format!("param({})", name(&items(n).first().map(text).unwrap_or_default())),
        _ if items(n).len() == 1 && items(n)[0].name() == Some("Param") => format!("viewport*{}", size(&items(n)[0])),
        _ if items(n).len() == 1 => format!("viewport*{}", value(&items(n)[0])),
        _ => "viewport".to_string(),
    }
}

fn per_light(n: &Node) -> String {
    format!("per_light({})", join(items(n), |k| text(k).to_string()))
}

fn resource(k: &Node, v: &Node) -> String {
    let f = fields(v);
    if v.name() == Some("AccelerationStructure") {
        return format!("acceleration_structure {}", name_of(k));
    }
    let mut line = if v.name() == Some("Buffer") {
        format!("buffer {}: {} bytes", name_of(k), get(f, "size").map(value).unwrap_or_default())
    } else {
        // LBP always writes the size; the tree leaves it out when it is the default.
        let default = defaults::get("Texture", "size").map(|d| d.node(v.span));
        let sz = get(f, "size").cloned().or(default).map(|n| size(&n)).unwrap_or_default();
        format!("texture {}: {} {sz}", name_of(k), get(f, "format").map(text).unwrap_or_default())
    };
    for (key, _, n) in f {
        match key.as_str() {
            "layers" | "mips" => line += &format!(" {key} {}", value(n)),
            "view" => line += &format!(" {}", text(n)),
            "per_light" => line += &format!(" {}", per_light(n)),
            "history" | "external" | "per_pixel" if matches!(*n.value, Value::Bool(true)) => line += &format!(" {key}"),
            "data" => line += &format!(" data {}", data(n)),
            "valid" => line += &format!(" valid {}", join(items(n), value).replace(", ", "..")),
            _ => {}
        }
    }
    line
}

fn data(n: &Node) -> String {
    let list = || items(n).first().map(items).unwrap_or(&[]);
    match n.name() {
        Some("F32") => format!("f32({})", join(list(), value)),
        Some("U32") => format!("u32({})", join(list(), value)),
        _ => quote(&items(n).first().map(text).unwrap_or_default()),
    }
}

/// `2`, `rep`, `rep-1`, `rep+1` (a mip level or an array layer).
fn mip(n: &Node) -> String {
    let arg = items(n).first().map(value).unwrap_or_default();
    match n.name() {
        Some("Rep") if arg == "0" => "rep".into(),
        Some("Rep") if arg.starts_with('-') => format!("rep{arg}"),
        Some("Rep") => format!("rep+{arg}"),
        _ => arg,
    }
}

/// A stage reference: an entry name, or `"file#entry"` quoted.
fn stage(n: &Node) -> String {
    if n.name() == Some("Arg") {
        return text(n).into_owned();
    }
    let t = text(n);
    if t.contains('#') {
        quote(&t)
    } else {
        name(&t)
    }
}

/// ` like NAME(ARGS), …` for an item `like` templates, else nothing.
fn like(f: &[Field]) -> String {
    let Some(l) = get(f, "like") else { return String::new() };
    let one = |l: &Node| {
        let (template, args) = items(l).split_first().map_or((None, &[][..]), |(t, a)| (Some(t), a));
        let args = if args.is_empty() {
            String::new()
        } else {
            format!("({})", join(args, argument))
        };
        format!("{}{args}", name(&template.map(text).unwrap_or_default()))
    };
    match &*l.value {
        Value::List(likes) => format!(" like {}", join(likes, one)),
        _ => format!(" like {}", one(l)),
    }
}

/// A template's argument: a value, or options `a | b` as a condition writes them.
fn argument(n: &Node) -> String {
    match &*n.value {
        Value::Str(s) if s.contains('|') => options(s),
        _ => value(n),
    }
}

fn pass_line(key: &str, v: &Node) -> String {
    if is_match(v) {
        let keyword = if key == "values" { "set" } else { key };
        return format!("{keyword} {}", choice(v, |a| arm_value(key, a)));
    }
    match key {
        "fragment" if v.name() == Some("None") && matches!(&*v.value, Value::Ident(_)) => "fragment none".into(),
        "vertex" | "fragment" | "entry" => format!("{key} {}", stage(v)),
        "draw" if matches!(&*v.value, Value::Ident(_)) => format!("draw {}", text(v)),
        "draw" => format!(
            "draw {}({})",
            v.name().unwrap_or("Vertices").to_lowercase(),
            items(v).first().map(value).unwrap_or_default()
        ),
        "cull" => format!("cull {}", text(v)),
        // A pass's shader is in its header; a group's is a line of its own.
        "shader" => format!("shader {}", quoted(v)),
        "per_light" => per_light(v),
        "per_face" => "per_face".into(),
        "shadow_casters" => "shadow_casters".into(),
        "always" => "always".into(),
        "per_mip" => format!("per_mip {}", join(items(v), value).replace(", ", "..")),
        "repeat" if v.name() == Some("Param") => format!("repeat param({})", items(v).first().map(name_of).unwrap_or_default()),
        "values" => format!("set {}", assignments(v, value)),
        "constants" => format!("constants {}", assignments(v, constant)),
        "reads" => format!("reads {}", join(items(v), |n| element(n, read))),
        "writes" | "params" => format!("{key} {}", join(items(v), |n| element(n, name_of))),
        "param_block" => format!("param_block {}", name_of(v)),
        "after" => format!("after {}", name_of(v)),
        "color" => format!("color {}", join(items(v), |n| element(n, target))),
        "depth" => format!("depth {}", target(v)),
        "bind" => format!("bind {}", assignments(v, name_of)),
        "when" => format!("when {}", cond(v)),
        "dispatch" if v.name() == Some("Groups") => format!("dispatch groups({})", join(items(v), value)),
        "dispatch" => format!("dispatch size({})", items(v).first().map(name_of).unwrap_or_default()),
        _ => format!("{key} {}", value(v)),
    }
}

/// `match(VARIANT) { a | b: VALUE, _: VALUE }`.
fn choice(n: &Node, value: impl Fn(&Node) -> String) -> String {
    let f = fields(n);
    // By variant, `arms`; by the kind of light a pass runs per, `light`.
    let by_light = get(f, "light");
    let arms: Vec<String> = by_light
        .or(get(f, "arms"))
        .map(entries)
        .unwrap_or(&[])
        .iter()
        .map(|(k, v)| format!("{}: {}", options(&text(k)), value(v)))
        .collect();
    let selector = match by_light {
        Some(_) => "light".to_string(),
        None => format!("({})", name(&get(f, "variant").map(text).unwrap_or_default())),
    };
    format!(
        "match{}{selector} {{ {} }}",
        if by_light.is_some() { " " } else { "" },
        arms.join(", ")
    )
}

/// A list element, or a choice of elements (an arm of several in parentheses).
fn element(n: &Node, one: impl Fn(&Node) -> String + Copy) -> String {
    if !is_match(n) {
        return one(n);
    }
    choice(n, |v| match &*v.value {
        Value::List(items) => format!("({})", join(items, |i| element(i, one))),
        _ => element(v, one),
    })
}

/// A whole field's arm: the field's line without its keyword.
fn arm_value(key: &str, v: &Node) -> String {
    if is_match(v) {
        return choice(v, |a| arm_value(key, a));
    }
    let line = pass_line(key, v);
    let rest = line.split_once(' ').map(|(_, r)| r.to_string()).unwrap_or_default();
    match key {
        "per_light" => line.trim_start_matches("per_light").to_string(),
        "values" | "bind" | "constants" => format!("({rest})"),
        "shader" => quoted(v),
        _ => rest,
    }
}

/// `NAME = VALUE, ...` of a map (`set`, `constants`, `bind`).
fn assignments(v: &Node, value: impl Fn(&Node) -> String) -> String {
    let each: Vec<String> = entries(v).iter().map(|(a, b)| format!("{} = {}", name_of(a), value(b))).collect();
    each.join(", ")
}

/// `Replace(x)` (an item of a used pipeline replaced): `x`.
fn replaced(n: &Node) -> Option<&Node> {
    crate::syntax::compose::replacement(n)
}

fn is_match(n: &Node) -> bool {
    crate::syntax::lower::is_match(n)
}

/// A constant's value: `4`, `true`, `param(p)`, `variant(v, o)`.
fn constant(n: &Node) -> String {
    match n.name() {
        Some(w @ ("Param" | "Variant")) if matches!(&*n.value, Value::Tuple { .. }) => {
            format!("{}({})", w.to_lowercase(), join(items(n), name_of))
        }
        _ => value(n),
    }
}

fn read(n: &Node) -> String {
    match n.name() {
        Some("Prev") if matches!(&*n.value, Value::Tuple { .. }) => {
            format!("prev({})", name(&items(n).first().map(text).unwrap_or_default()))
        }
        Some("Layer") if matches!(&*n.value, Value::Tuple { .. }) => format!(
            "layer({}, {})",
            name(&items(n).first().map(text).unwrap_or_default()),
            items(n)
                .get(1)
                .map(|l| if l.name() == Some("Rep") { mip(l) } else { value(l) })
                .unwrap_or_default()
        ),
        Some("Mip") if matches!(&*n.value, Value::Tuple { .. }) => format!(
            "mip({}, {})",
            name(&items(n).first().map(text).unwrap_or_default()),
            items(n).get(1).map(mip).unwrap_or_default()
        ),
        _ => name_of(n),
    }
}

fn target(n: &Node) -> String {
    let f = fields(n);
    if f.is_empty() {
        return name_of(n);
    }
    let mut t = name(&get(f, "resource").map(text).unwrap_or_default());
    for (key, _, v) in f {
        match key.as_str() {
            "load" => t += " load",
            "clear" if matches!(&*v.value, Value::Tuple { .. }) => t += &format!(" clear{}", value(v)),
            "clear" => t += &format!(" clear({})", value(v)),
            "blend" | "compare" => t += &format!(" {key} {}", text(v)),
            "write" => t += " nowrite",
            "layer" if v.name() == Some("Index") => t += &format!(" layer {}", value(&items(v)[0])),
            "layer" if v.name() == Some("Rep") => t += &format!(" layer {}", mip(v)),
            "layer" => t += &format!(" layer {}", text(v)),
            "mip" => t += &format!(" mip {}", mip(v)),
            _ => {}
        }
    }
    t
}

/// `let NAME = CONDITION`.
fn let_line(k: &Node, v: &Node) -> String {
    format!("let {} = {}", name_of(k), cond(v))
}

fn cond(n: &Node) -> String {
    let args = items(n);
    match n.name().unwrap_or("") {
        "Let" => args.first().map(name_of).unwrap_or_default(),
        "Reflective" => "reflective".into(),
        "Blended" => "blended".into(),
        "Not" => format!("not {}", args.first().map(cond).unwrap_or_default()),
        w @ ("All" | "Any") => format!("{}({})", w.to_lowercase(), join(args.first().map(items).unwrap_or(&[]), cond)),
        w @ ("Light" | "Effect") => format!("{}({})", w.to_lowercase(), join(args, |a| text(a).to_string())),
        // A variant's option may be several: `a | b`, each a name.
        "Variant" => match args {
            [v, o] => format!("variant({}, {})", name_of(v), options_of(o)),
            _ => format!("variant({})", join(args, name_of)),
        },
        w => format!("{}({})", w.to_lowercase(), join(args, name_of)),
    }
}

/// Option names as LBP writes them: `a`, or `a | b`.
fn options(text: &str) -> String {
    text.split('|').map(|o| name(o.trim())).collect::<Vec<_>>().join(" | ")
}

fn option(f: &[Field]) -> String {
    let mut line = String::new();
    for (key, _, v) in f {
        match key.as_str() {
            "requires" => line += &format!(" requires({})", join(items(v), |r| text(r).to_string())),
            "limits" => {
                let ls: Vec<String> = entries(v).iter().map(|(k, n)| format!("{} = {}", text(k), value(n))).collect();
                line += &format!(" limit({})", ls.join(", "));
            }
            "fallback" => line += &format!(" fallback {}", name_of(v)),
            "shaders" => {
                let ss: Vec<String> = entries(v).iter().map(|(k, n)| format!("{} = {}", name_of(k), quoted(n))).collect();
                line += &format!(" shader({})", ss.join(", "));
            }
            "params" => {
                let ss: Vec<String> = entries(v).iter().map(|(k, n)| format!("{} = {}", name_of(k), value(n))).collect();
                line += &format!(" set({})", ss.join(", "));
            }
            "jitter" if matches!(*v.value, Value::Bool(true)) => line += " jitter",
            _ => {}
        }
    }
    if let Some(d) = get(f, "doc") {
        line += &format!(" {}", quoted(d));
    }
    line
}
