//! IR -> RON text in the pipeline file schema (what `lightbench convert --to ron` writes).
//! Comments from an LBP source are kept before the item that followed them.

use crate::front::comments::{emit, Comments};
use crate::front::lbp::print::{main_file, quote};
use crate::ir::*;
use std::fmt::Write;

fn num(x: f64) -> String {
    // RON floats need a decimal point or exponent to stay floats.
    let s = format!("{x}");
    if s.contains('.') || s.contains('e') || s.contains("inf") || s.contains("NaN") {
        s
    } else {
        format!("{s}.0")
    }
}

fn value(v: &ParamValue) -> String {
    match v {
        ParamValue::Float(f) => num(*f),
        ParamValue::Int(i) => i.to_string(),
        ParamValue::Bool(b) => b.to_string(),
        ParamValue::Vec(v) => format!("({})", v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")),
        ParamValue::Enum(s) => quote(s),
    }
}

fn list(items: impl IntoIterator<Item = String>) -> String {
    format!("[{}]", items.into_iter().collect::<Vec<_>>().join(", "))
}

fn kinds(k: &[LightKind]) -> String {
    list(k.iter().map(|k| k.name().to_string()))
}

pub fn cond(c: &Condition) -> String {
    match c {
        Condition::Light(k) => format!("Light({})", k.name()),
        Condition::Effect(e) => format!("Effect({})", e.name()),
        Condition::Reflective => "Reflective".into(),
        Condition::Toggle(p) => format!("Toggle({})", quote(p)),
        Condition::Variant(v, o) => format!("Variant({}, {})", quote(v), quote(o)),
        Condition::Not(c) => format!("Not({})", cond(c)),
        Condition::All(cs) => format!("All({})", list(cs.iter().map(|c| cond(c)))),
        Condition::Any(cs) => format!("Any({})", list(cs.iter().map(|c| cond(c)))),
    }
}

fn layer(l: LayerSel) -> Option<String> {
    match l {
        LayerSel::Base => None,
        LayerSel::Face => Some("layer: Face".into()),
        LayerSel::All => Some("layer: All".into()),
        LayerSel::Index(i) => Some(format!("layer: Index({i})")),
    }
}

fn stage(key: &str, r: &ShaderRef, file: Option<&str>, stage: naga::ShaderStage, default_applies: bool) -> Option<String> {
    written_entry(r, file, stage, default_applies).map(|t| format!("{key}: {}", quote(&t)))
}

pub fn print(p: &Pipeline, source: Option<&str>) -> String {
    let mut comments = Comments::new(source);
    let mut s = String::new();
    emit(&mut s, &comments.before(p.name.span), "");
    let _ = writeln!(s, "Pipeline(\n    name: {},", quote(&p.name));
    if !p.params.is_empty() {
        s.push_str("    params: {\n");
        for prm in &p.params {
            emit(&mut s, &comments.before(prm.span), "        ");
            let mut fields = vec![];
            if let ParamType::Enum(opts) = &prm.ty.value {
                fields.push(format!("options: {}", list(opts.iter().map(|o| quote(o)))));
            }
            fields.push(format!("default: {}", value(&prm.default)));
            if let Some(m) = &prm.min {
                fields.push(format!("min: {}", value(m)));
            }
            if let Some(m) = &prm.max {
                fields.push(format!("max: {}", value(m)));
            }
            if let Some(d) = &prm.doc {
                fields.push(format!("doc: {}", quote(d)));
            }
            let _ = writeln!(s, "        {}: {}({}),", quote(&prm.name), prm.ty.name(), fields.join(", "));
        }
        s.push_str("    },\n");
    }
    if !p.samplers.is_empty() {
        s.push_str("    samplers: {\n");
        for smp in &p.samplers {
            emit(&mut s, &comments.before(smp.span), "        ");
            let mut fields = vec![
                format!("filter: {:?}", smp.filter),
                format!("mipmap: {:?}", smp.mipmap),
                format!("address: {:?}", smp.address),
            ];
            if let Some(c) = smp.compare {
                fields.push(format!("compare: {c:?}"));
            }
            let _ = writeln!(s, "        {}: Sampler({}),", quote(&smp.name), fields.join(", "));
        }
        s.push_str("    },\n");
    }
    if !p.resources.is_empty() {
        s.push_str("    resources: {\n");
        for r in &p.resources {
            emit(&mut s, &comments.before(r.span), "        ");
            let mut fields = vec![];
            let kind = match &r.kind {
                ResourceKind::Texture(t) => {
                    fields.push(format!("format: {}", t.format.value.name()));
                    fields.push(match &t.size.value {
                        SizeSpec::Viewport { scale } if *scale == 1.0 => "size: Viewport".to_string(),
                        SizeSpec::Viewport { scale } => format!("size: Viewport({})", num(*scale)),
                        SizeSpec::Fixed { width, height } => format!("size: Fixed({width}, {height})"),
                    });
                    if t.layers.value != 1 {
                        fields.push(format!("layers: {}", t.layers.value));
                    }
                    if t.view.value != ViewDim::D2 {
                        fields.push(format!("view: {}", t.view.value.name()));
                    }
                    if t.mips.value != 1 {
                        fields.push(format!("mips: {}", t.mips.value));
                    }
                    "Texture"
                }
                ResourceKind::Buffer(b) => {
                    fields.push(format!("size: {}", b.size.value));
                    "Buffer"
                }
            };
            if let Some(k) = r.per_light() {
                fields.push(format!("per_light: {}", kinds(k)));
            }
            if r.history() {
                fields.push("history: true".into());
            }
            if r.external() {
                fields.push("external: true".into());
            }
            let _ = writeln!(s, "        {}: {kind}({}),", quote(&r.name), fields.join(", "));
        }
        s.push_str("    },\n");
    }
    s.push_str("    passes: [\n");
    for pass in &p.passes {
        emit(&mut s, &comments.before(pass.span), "        ");
        emit(
            &mut s,
            &comments.before(crate::span::Span {
                file: pass.span.file,
                start: pass.span.end,
                end: pass.span.end,
            }),
            "        ",
        );
        let file = main_file(pass);
        let mut f = vec![format!("name: {}", quote(&pass.name))];
        if let Some(file) = file {
            f.push(format!("shader: {}", quote(file)));
        }
        let kind = match &pass.kind {
            PassKind::Raster {
                draw,
                cull,
                instances,
                multiview,
            } => {
                f.extend(
                    pass.vertex
                        .as_ref()
                        .and_then(|r| stage("vertex", r, file, naga::ShaderStage::Vertex, true)),
                );
                let has_color = !pass.color.is_empty();
                match &pass.fragment {
                    None if has_color => f.push("fragment: None".into()),
                    None => {}
                    Some(r) => f.extend(stage("fragment", r, file, naga::ShaderStage::Fragment, has_color)),
                }
                if let Draw::Vertices(n) = draw {
                    f.push(format!("draw: Vertices({n})"));
                }
                if *cull != CullMode::Back {
                    f.push(format!("cull: {cull:?}"));
                }
                if *instances != 1 {
                    f.push(format!("instances: {instances}"));
                }
                if let Some(m) = multiview {
                    f.push(format!("multiview: {}", m.value));
                }
                "Raster"
            }
            PassKind::Fullscreen => {
                f.extend(
                    pass.fragment
                        .as_ref()
                        .and_then(|r| stage("fragment", r, file, naga::ShaderStage::Fragment, true)),
                );
                "Fullscreen"
            }
            PassKind::Compute { .. } => {
                f.extend(
                    pass.compute
                        .as_ref()
                        .and_then(|r| stage("entry", r, file, naga::ShaderStage::Compute, true)),
                );
                "Compute"
            }
        };
        if let Some(k) = &pass.per_light {
            f.push(format!("per_light: {}", kinds(k)));
        }
        if pass.per_face {
            f.push("per_face: true".into());
        }
        if !pass.reads.is_empty() {
            f.push(format!(
                "reads: {}",
                list(pass.reads.iter().map(|r| if r.is_prev() {
                    format!("Prev({})", quote(r.name()))
                } else {
                    quote(r.name())
                }))
            ));
        }
        if !pass.writes.is_empty() {
            f.push(format!("writes: {}", list(pass.writes.iter().map(|w| quote(w)))));
        }
        if !pass.color.is_empty() {
            let ts = pass.color.iter().map(|c| {
                let mut t = vec![format!("resource: {}", quote(&c.resource))];
                match &c.load {
                    LoadOp::Load => t.push("load: Load".into()),
                    LoadOp::Clear(v) if v.len() == 4 && v.iter().all(|x| *x == 0.0) => {}
                    LoadOp::Clear(v) => t.push(format!("clear: ({})", v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", "))),
                }
                if let Some(b) = &c.blend {
                    t.push(format!("blend: {:?}", b.value));
                }
                t.extend(layer(c.layer));
                if t.len() == 1 {
                    quote(&c.resource)
                } else {
                    format!("Target({})", t.join(", "))
                }
            });
            f.push(format!("color: {}", list(ts)));
        }
        if let Some(d) = &pass.depth {
            let mut t = vec![format!("resource: {}", quote(&d.resource))];
            match &d.load {
                LoadOp::Load => t.push("load: Load".into()),
                LoadOp::Clear(v) if v.len() == 1 && v[0] == 1.0 => {}
                LoadOp::Clear(v) => t.push(format!("clear: {}", num(v.first().copied().unwrap_or(1.0)))),
            }
            if d.compare != CompareFn::Less {
                t.push(format!("compare: {:?}", d.compare));
            }
            if !d.write {
                t.push("write: false".into());
            }
            t.extend(layer(d.layer));
            f.push(if t.len() == 1 {
                format!("depth: {}", quote(&d.resource))
            } else {
                format!("depth: Depth({})", t.join(", "))
            });
        }
        if !pass.params.is_empty() {
            f.push(format!("params: {}", list(pass.params.iter().map(|w| quote(w)))));
        }
        if pass.param_block.value != "params" {
            f.push(format!("param_block: {}", quote(&pass.param_block)));
        }
        if !pass.bind.is_empty() {
            f.push(format!(
                "bind: {{{}}}",
                pass.bind
                    .iter()
                    .map(|(k, v)| format!("{}: {}", quote(k), quote(v)))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        if let Some(w) = &pass.when {
            f.push(format!("when: {}", cond(w)));
        }
        if let PassKind::Compute { dispatch } = &pass.kind {
            f.push(match dispatch {
                Dispatch::Groups(x, y, z) => format!("dispatch: Groups({x}, {y}, {z})"),
                Dispatch::Size(r) => format!("dispatch: Size({})", quote(r)),
            });
        }
        let _ = writeln!(
            s,
            "        {kind}(\n{}\n        ),",
            f.iter().map(|x| format!("            {x},")).collect::<Vec<_>>().join("\n")
        );
    }
    s.push_str("    ],\n");
    if !p.variants.is_empty() {
        s.push_str("    variants: {\n");
        for v in &p.variants {
            emit(&mut s, &comments.before(v.span), "        ");
            let _ = writeln!(s, "        {}: Variant(", quote(&v.name));
            let _ = writeln!(s, "            default: {},", quote(&v.default));
            if let Some(d) = &v.doc {
                let _ = writeln!(s, "            doc: {},", quote(d));
            }
            s.push_str("            options: {\n");
            for o in &v.options {
                emit(&mut s, &comments.before(o.span), "                ");
                let mut f = vec![];
                if !o.requires.is_empty() {
                    f.push(format!("requires: {}", list(o.requires.iter().map(|r| r.value.name().to_string()))));
                }
                if !o.limits.is_empty() {
                    f.push(format!(
                        "limits: {{{}}}",
                        o.limits
                            .iter()
                            .map(|(k, n)| format!("{}: {}", quote(k), n.value))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ));
                }
                if let Some(fb) = &o.fallback {
                    f.push(format!("fallback: {}", quote(fb)));
                }
                if !o.shaders.is_empty() {
                    f.push(format!(
                        "shaders: {{{}}}",
                        o.shaders
                            .iter()
                            .map(|(k, n)| format!("{}: {}", quote(k), quote(n)))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ));
                }
                if let Some(d) = &o.doc {
                    f.push(format!("doc: {}", quote(d)));
                }
                let _ = writeln!(s, "                {}: ({}),", quote(&o.name), f.join(", "));
            }
            s.push_str("            },\n        ),\n");
        }
        s.push_str("    },\n");
    }
    emit(&mut s, &comments.before(p.output.span), "    ");
    let _ = writeln!(s, "    output: {},\n)", quote(&p.output));
    let rest = comments.rest();
    emit(&mut s, &rest, "");
    s
}
