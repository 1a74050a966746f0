//! IR -> canonical LBP text. `lightbench fmt` is parse + print; the layout is fixed, so
//! printing what was printed gives the same text (idempotent). Comments in the source are
//! kept before the item that followed them.

use crate::front::comments::{emit, Comments};
use crate::ir::*;
use std::fmt::Write;

const RESERVED: [&str; 7] = ["none", "true", "false", "prev", "load", "nowrite", "in"];

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

pub fn quote(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            '\0' => out.push_str("\\0"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn num(x: f64) -> String {
    format!("{x}")
}

fn value(v: &ParamValue) -> String {
    match v {
        ParamValue::Float(f) => num(*f),
        ParamValue::Int(i) => i.to_string(),
        ParamValue::Bool(b) => b.to_string(),
        ParamValue::Vec(v) => format!("({})", v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")),
        ParamValue::Enum(s) => name(s),
    }
}

fn kinds(k: &[LightKind]) -> String {
    format!("per_light({})", k.iter().map(|k| k.name()).collect::<Vec<_>>().join(", "))
}

pub fn cond(c: &Condition) -> String {
    match c {
        Condition::Light(k) => format!("light({})", k.name()),
        Condition::Effect(e) => format!("effect({})", e.name()),
        Condition::Reflective => "reflective".into(),
        Condition::Toggle(p) => format!("toggle({})", name(p)),
        Condition::Variant(v, o) => format!("variant({}, {})", name(v), name(o)),
        Condition::Not(c) => format!("not {}", cond(c)),
        Condition::All(cs) => format!("all({})", cs.iter().map(|c| cond(c)).collect::<Vec<_>>().join(", ")),
        Condition::Any(cs) => format!("any({})", cs.iter().map(|c| cond(c)).collect::<Vec<_>>().join(", ")),
    }
}

fn layer(l: LayerSel) -> Option<String> {
    match l {
        LayerSel::Base => None,
        LayerSel::Face => Some("layer Face".into()),
        LayerSel::All => Some("layer All".into()),
        LayerSel::Index(i) => Some(format!("layer {i}")),
    }
}

/// The file a pass's shader string names: the stage that defines the pass.
pub fn main_file(p: &Pass) -> Option<&str> {
    let main = match p.kind {
        PassKind::Raster { .. } => p.vertex.as_ref(),
        PassKind::Fullscreen => p.fragment.as_ref(),
        PassKind::Compute { .. } => p.compute.as_ref(),
    };
    main.map(|r| r.file.value.as_str())
}

/// How a stage is written given the pass's shader file; `None` when the default applies.
fn stage(r: &ShaderRef, file: Option<&str>, stage: naga::ShaderStage, default_applies: bool) -> Option<String> {
    written_entry(r, file, stage, default_applies).map(|t| if t.contains('#') { quote(&t) } else { name(&t) })
}

pub fn print(p: &Pipeline, source: Option<&str>) -> String {
    let mut comments = Comments::new(source);
    let mut s = String::new();
    emit(&mut s, &comments.before(p.name.span), "");
    let _ = writeln!(s, "pipeline {}", name(&p.name));
    let section = |s: &mut String, first: &mut bool| {
        if *first {
            s.push('\n');
            *first = false;
        }
    };
    let mut first = true;
    for prm in &p.params {
        section(&mut s, &mut first);
        emit(&mut s, &comments.before(prm.span), "");
        let ty = match &prm.ty.value {
            ParamType::Enum(opts) => format!("enum({})", opts.iter().map(|o| name(o)).collect::<Vec<_>>().join(", ")),
            t => t.name().to_string(),
        };
        let mut line = format!("param {}: {ty} = {}", name(&prm.name), value(&prm.default));
        match (&prm.min, &prm.max) {
            (Some(lo), Some(hi)) => {
                let _ = write!(line, " in {}..{}", value(lo), value(hi));
            }
            (Some(lo), None) => {
                let _ = write!(line, " min {}", value(lo));
            }
            (None, Some(hi)) => {
                let _ = write!(line, " max {}", value(hi));
            }
            (None, None) => {}
        }
        if let Some(d) = &prm.doc {
            let _ = write!(line, " {}", quote(d));
        }
        let _ = writeln!(s, "{line}");
    }
    first = true;
    for smp in &p.samplers {
        section(&mut s, &mut first);
        emit(&mut s, &comments.before(smp.span), "");
        let mut line = format!("sampler {}:", name(&smp.name));
        if smp.filter != FilterMode::Linear {
            let _ = write!(line, " {:?}", smp.filter);
        }
        if smp.mipmap != FilterMode::Nearest {
            let _ = write!(line, " mipmap {:?}", smp.mipmap);
        }
        if smp.address != AddressMode::ClampToEdge {
            let _ = write!(line, " {:?}", smp.address);
        }
        if let Some(c) = smp.compare {
            let _ = write!(line, " compare {c:?}");
        }
        let _ = writeln!(s, "{line}");
    }
    first = true;
    for r in &p.resources {
        section(&mut s, &mut first);
        emit(&mut s, &comments.before(r.span), "");
        let mut line = match &r.kind {
            ResourceKind::Texture(t) => {
                let size = match &t.size.value {
                    SizeSpec::Viewport { scale } if *scale == 1.0 => "viewport".to_string(),
                    SizeSpec::Viewport { scale } => format!("viewport*{}", num(*scale)),
                    SizeSpec::Fixed { width, height } => format!("{width}x{height}"),
                };
                let mut l = format!("texture {}: {} {size}", name(&r.name), t.format.value.name());
                if t.layers.value != 1 {
                    let _ = write!(l, " layers {}", t.layers.value);
                }
                if t.view.value != ViewDim::D2 {
                    let _ = write!(l, " {}", t.view.value.name());
                }
                if t.mips.value != 1 {
                    let _ = write!(l, " mips {}", t.mips.value);
                }
                l
            }
            ResourceKind::Buffer(b) => format!("buffer {}: {} bytes", name(&r.name), b.size.value),
        };
        if let Some(k) = r.per_light() {
            let _ = write!(line, " {}", kinds(k));
        }
        if r.history() {
            line.push_str(" history");
        }
        if r.external() {
            line.push_str(" external");
        }
        let _ = writeln!(s, "{line}");
    }
    for pass in &p.passes {
        s.push('\n');
        emit(&mut s, &comments.before(pass.span), "");
        let file = main_file(pass);
        let _ = writeln!(
            s,
            "{} {}{} {{",
            pass.kind.word(),
            name(&pass.name),
            file.map(|f| format!(" {}", quote(f))).unwrap_or_default()
        );
        // Comments inside the pass body come first in it.
        emit(
            &mut s,
            &comments.before(crate::span::Span {
                file: pass.span.file,
                start: pass.span.end,
                end: pass.span.end,
            }),
            "    ",
        );
        let mut lines: Vec<String> = vec![];
        match &pass.kind {
            PassKind::Raster {
                draw,
                cull,
                instances,
                multiview,
            } => {
                if let Some(v) = pass.vertex.as_ref().and_then(|r| stage(r, file, naga::ShaderStage::Vertex, true)) {
                    lines.push(format!("vertex {v}"));
                }
                let has_color = !pass.color.is_empty();
                match &pass.fragment {
                    None if has_color => lines.push("fragment none".into()),
                    None => {}
                    Some(r) => {
                        if let Some(f) = stage(r, file, naga::ShaderStage::Fragment, has_color) {
                            lines.push(format!("fragment {f}"));
                        }
                    }
                }
                if let Draw::Vertices(n) = draw {
                    lines.push(format!("draw vertices({n})"));
                }
                if *cull != CullMode::Back {
                    lines.push(format!("cull {cull:?}"));
                }
                if *instances != 1 {
                    lines.push(format!("instances {instances}"));
                }
                if let Some(m) = multiview {
                    lines.push(format!("multiview {}", m.value));
                }
            }
            PassKind::Fullscreen => {
                if let Some(f) = pass
                    .fragment
                    .as_ref()
                    .and_then(|r| stage(r, file, naga::ShaderStage::Fragment, true))
                {
                    lines.push(format!("fragment {f}"));
                }
            }
            PassKind::Compute { .. } => {
                if let Some(c) = pass.compute.as_ref().and_then(|r| stage(r, file, naga::ShaderStage::Compute, true)) {
                    lines.push(format!("entry {c}"));
                }
            }
        }
        if let Some(k) = &pass.per_light {
            lines.push(kinds(k));
        }
        if pass.per_face {
            lines.push("per_face".into());
        }
        if !pass.reads.is_empty() {
            let rs: Vec<String> = pass
                .reads
                .iter()
                .map(|r| {
                    if r.is_prev() {
                        format!("prev({})", name(r.name()))
                    } else {
                        name(r.name())
                    }
                })
                .collect();
            lines.push(format!("reads {}", rs.join(", ")));
        }
        if !pass.writes.is_empty() {
            lines.push(format!(
                "writes {}",
                pass.writes.iter().map(|w| name(w)).collect::<Vec<_>>().join(", ")
            ));
        }
        if !pass.color.is_empty() {
            let ts: Vec<String> = pass
                .color
                .iter()
                .map(|c| {
                    let mut t = name(&c.resource);
                    match &c.load {
                        LoadOp::Load => t.push_str(" load"),
                        LoadOp::Clear(v) if v.iter().all(|x| *x == 0.0) && v.len() == 4 => {}
                        LoadOp::Clear(v) => t.push_str(&format!(" clear({})", v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", "))),
                    }
                    if let Some(b) = &c.blend {
                        t.push_str(&format!(" blend {:?}", b.value));
                    }
                    if let Some(l) = layer(c.layer) {
                        t.push_str(&format!(" {l}"));
                    }
                    t
                })
                .collect();
            lines.push(format!("color {}", ts.join(", ")));
        }
        if let Some(d) = &pass.depth {
            let mut t = format!("depth {}", name(&d.resource));
            match &d.load {
                LoadOp::Load => t.push_str(" load"),
                LoadOp::Clear(v) if v.len() == 1 && v[0] == 1.0 => {}
                LoadOp::Clear(v) => t.push_str(&format!(" clear({})", v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", "))),
            }
            if d.compare != CompareFn::Less {
                t.push_str(&format!(" compare {:?}", d.compare));
            }
            if !d.write {
                t.push_str(" nowrite");
            }
            if let Some(l) = layer(d.layer) {
                t.push_str(&format!(" {l}"));
            }
            lines.push(t);
        }
        if !pass.params.is_empty() {
            lines.push(format!(
                "params {}",
                pass.params.iter().map(|w| name(w)).collect::<Vec<_>>().join(", ")
            ));
        }
        if pass.param_block.value != "params" {
            lines.push(format!("param_block {}", name(&pass.param_block)));
        }
        if !pass.bind.is_empty() {
            lines.push(format!(
                "bind {}",
                pass.bind
                    .iter()
                    .map(|(k, v)| format!("{} = {}", name(k), name(v)))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        if let Some(w) = &pass.when {
            lines.push(format!("when {}", cond(w)));
        }
        if let PassKind::Compute { dispatch } = &pass.kind {
            lines.push(match dispatch {
                Dispatch::Groups(x, y, z) => format!("dispatch groups({x}, {y}, {z})"),
                Dispatch::Size(r) => format!("dispatch size({})", name(r)),
            });
        }
        for l in lines {
            let _ = writeln!(s, "    {l}");
        }
        s.push_str("}\n");
    }
    for v in &p.variants {
        s.push('\n');
        emit(&mut s, &comments.before(v.span), "");
        let _ = writeln!(
            s,
            "variant {} = {}{} {{",
            name(&v.name),
            name(&v.default),
            v.doc.as_ref().map(|d| format!(" {}", quote(d))).unwrap_or_default()
        );
        for o in &v.options {
            emit(&mut s, &comments.before(o.span), "    ");
            let mut line = format!("    option {}", name(&o.name));
            if !o.requires.is_empty() {
                let _ = write!(
                    line,
                    " requires({})",
                    o.requires.iter().map(|f| f.value.name()).collect::<Vec<_>>().join(", ")
                );
            }
            if !o.limits.is_empty() {
                let _ = write!(
                    line,
                    " limit({})",
                    o.limits
                        .iter()
                        .map(|(k, v)| format!("{} = {}", k.value, v.value))
                        .collect::<Vec<_>>()
                        .join(", ")
                );
            }
            if let Some(f) = &o.fallback {
                let _ = write!(line, " fallback {}", name(f));
            }
            if !o.shaders.is_empty() {
                let _ = write!(
                    line,
                    " shader({})",
                    o.shaders
                        .iter()
                        .map(|(k, f)| format!("{} = {}", name(k), quote(f)))
                        .collect::<Vec<_>>()
                        .join(", ")
                );
            }
            if let Some(d) = &o.doc {
                let _ = write!(line, " {}", quote(d));
            }
            let _ = writeln!(s, "{line}");
        }
        s.push_str("}\n");
    }
    s.push('\n');
    emit(&mut s, &comments.before(p.output.span), "");
    let _ = writeln!(s, "output {}", name(&p.output));
    let rest = comments.rest();
    if !rest.is_empty() {
        emit(&mut s, &rest, "");
    }
    s
}
