//! Human-readable and Graphviz renderings of a Plan.

use super::*;
use std::fmt::Write;

/// How a pass's work reads in plans: `Scene`, `Vertices(3)`, `Fullscreen`, `Groups(2, 1, 1) from Size(hdr)`.
pub fn work_word(w: &Work) -> String {
    match w {
        Work::Scene => "Scene".into(),
        Work::Vertices(n) => format!("Vertices({n})"),
        Work::Fullscreen => "Fullscreen".into(),
        Work::Dispatch {
            groups: [x, y, z],
            sized_from: None,
        } => format!("Groups({x}, {y}, {z})"),
        Work::Dispatch {
            groups: [x, y, z],
            sized_from: Some(r),
        } => format!("Groups({x}, {y}, {z}) from Size({r})"),
    }
}

fn mib(bytes: u64) -> String {
    format!("{:.2} MiB", bytes as f64 / (1024.0 * 1024.0))
}

fn binding_word(t: &BindingType) -> String {
    match t {
        BindingType::Texture {
            sample_type,
            view_dimension,
            ..
        } => {
            let st = match sample_type {
                SampleType::Float { filterable: true } => "float, filterable",
                SampleType::Float { filterable: false } => "float, unfilterable",
                SampleType::Depth => "depth",
                SampleType::Uint => "uint",
                SampleType::Sint => "sint",
            };
            format!("texture {} ({st})", view_dimension.wgsl_word())
        }
        BindingType::StorageTexture {
            format,
            access,
            view_dimension,
        } => format!("storage texture {} {format} {access}", view_dimension.wgsl_word()),
        BindingType::Sampler(k) => format!("sampler ({k:?})"),
        BindingType::Uniform { min_binding_size } => format!("uniform ({min_binding_size} B)"),
        BindingType::Storage {
            read_only,
            min_binding_size,
        } => format!("storage {} (≥{min_binding_size} B)", if *read_only { "read" } else { "read_write" }),
    }
}

fn source_word(s: &BindSource) -> String {
    match s {
        BindSource::Resource(n) => n.clone(),
        BindSource::Prev(n) => format!("Prev({n})"),
        BindSource::Sampler(n) => format!("sampler {n}"),
        BindSource::Params => "params".into(),
        BindSource::Frame => "<frame>".into(),
        BindSource::Instance => "<instance>".into(),
        BindSource::Lights => "<lights>".into(),
        BindSource::Draw(n) => format!("<draw.{n}>"),
    }
}

/// The plan as text. `explain` adds why each variant option was chosen and each pass culled,
/// and the full layouts.
pub fn to_text(plan: &Plan, explain: bool) -> String {
    let mut s = String::new();
    let lights: Vec<String> = plan.lights.iter().map(|(k, n)| format!("{n} {}", k.name())).collect();
    let _ = writeln!(
        s,
        "plan for pipeline `{}` (profile {}, scene {}, {}×{}, lights: {})",
        plan.pipeline,
        plan.profile,
        plan.scene,
        plan.resolution.0,
        plan.resolution.1,
        if lights.is_empty() { "none".into() } else { lights.join(", ") }
    );
    if !plan.variants.is_empty() {
        let _ = writeln!(s, "\nvariants:");
        for v in &plan.variants {
            match (&v.reason, explain) {
                (Some(r), true) => {
                    let _ = writeln!(s, "  {} = {}  ({r})", v.variant, v.option);
                }
                _ => {
                    let _ = writeln!(s, "  {} = {}", v.variant, v.option);
                }
            }
        }
    }
    let _ = writeln!(s, "\npasses ({} kept, in order):", plan.passes.len());
    for (i, p) in plan.passes.iter().enumerate() {
        let rep = match (p.per_light.is_empty(), p.per_face) {
            (true, false) => String::new(),
            _ => {
                let kinds: Vec<&str> = p.per_light.iter().map(|k| k.name()).collect();
                let mut r = String::from(" ×");
                r += &p.repetitions.to_string();
                r += " (";
                if !kinds.is_empty() {
                    r += &format!("per {} light", kinds.join("/"));
                }
                if p.per_face {
                    r += if kinds.is_empty() { "per face" } else { ", per face" };
                }
                r + ")"
            }
        };
        let targets: Vec<String> = p
            .color
            .iter()
            .map(|c| c.resource.clone())
            .chain(p.depth.iter().map(|d| format!("depth {}", d.resource)))
            .chain(p.writes.iter().map(|w| format!("storage {w}")))
            .collect();
        let _ = writeln!(s, "  {:>2}. {:<22} {:<10} {}{rep}", i + 1, p.name, p.kind, work_word(&p.work));
        let _ = writeln!(s, "      reads [{}] -> writes [{}]", p.reads.join(", "), targets.join(", "));
        if explain {
            for st in &p.stages {
                let _ = writeln!(s, "      {} {}#{}", st.stage, st.file, st.entry);
            }
            if !p.after.is_empty() {
                let _ = writeln!(s, "      after: {}", p.after.join(", "));
            }
            for g in &p.bind_groups {
                for e in &g.entries {
                    let _ = writeln!(
                        s,
                        "      @group({}) @binding({}) {:<20} {:<34} <- {}  [{}]",
                        g.group,
                        e.binding,
                        e.name,
                        binding_word(&e.ty),
                        source_word(&e.source),
                        e.visibility.join(", ")
                    );
                }
            }
            for b in &p.uniform_blocks {
                let _ = writeln!(s, "      block `{}`: {} bytes, align {}", b.global, b.size, b.align);
                for f in &b.fields {
                    let _ = writeln!(s, "        +{:<4} {:<12} {:<10} = {}", f.offset, f.name, f.ty, f.param);
                }
            }
        }
    }
    if !plan.culled.is_empty() {
        let _ = writeln!(s, "\nculled ({}):", plan.culled.len());
        for c in &plan.culled {
            if explain {
                let _ = writeln!(s, "  {:<26} {}", c.name, c.reason);
            } else {
                let _ = writeln!(s, "  {}", c.name);
            }
        }
    }
    let _ = writeln!(s, "\nresources:");
    for r in &plan.resources {
        let mut shape = match &r.format {
            Some(f) => format!("{f} {} ({}×{})", r.size, r.extent.0, r.extent.1),
            None => r.size.clone(),
        };
        if r.layers > 1 {
            shape += &format!(" ×{} layers", r.layers);
        }
        if let Some(v) = &r.view {
            if v != "D2" {
                shape += &format!(" {v}");
            }
        }
        if r.mips > 1 {
            shape += &format!(" {} mips", r.mips);
        }
        let mut extra = String::new();
        if !r.per_light.is_empty() {
            let k: Vec<&str> = r.per_light.iter().map(|k| k.name()).collect();
            extra += &format!(" per {} light ×{}", k.join("/"), r.instances);
        }
        if r.history {
            extra += " history ×2";
        }
        if r.external {
            extra += " external";
        }
        let _ = writeln!(
            s,
            "  {:<18} {:<44}{extra}  {}  [{}]",
            r.name,
            shape,
            mib(r.bytes),
            r.usage.join(" | ")
        );
    }
    let _ = writeln!(
        s,
        "\nmemory: {} at {}×{}",
        mib(plan.memory_bytes),
        plan.resolution.0,
        plan.resolution.1
    );
    let _ = writeln!(s, "output: {}", plan.output);
    s
}

/// Graphviz: passes as boxes, resources as ellipses, culled passes dashed.
pub fn to_dot(plan: &Plan) -> String {
    let mut s = String::new();
    let q = |x: &str| format!("\"{}\"", x.replace('"', "\\\""));
    let _ = writeln!(s, "digraph {} {{", q(&plan.pipeline));
    let _ = writeln!(s, "  rankdir=LR;\n  node [fontname=\"sans-serif\"];");
    for p in &plan.passes {
        let _ = writeln!(
            s,
            "  {} [shape=box, style=filled, fillcolor=\"#dde8f5\", label={}];",
            q(&format!("pass:{}", p.name)),
            q(&format!("{}\\n{}", p.name, p.kind))
        );
        for r in &p.reads {
            let name = r.trim_start_matches("Prev(").trim_end_matches(')');
            let style = if r.starts_with("Prev(") {
                " [style=dashed, label=\"prev\"]"
            } else {
                ""
            };
            let _ = writeln!(s, "  {} -> {}{style};", q(&format!("res:{name}")), q(&format!("pass:{}", p.name)));
        }
        for w in p
            .color
            .iter()
            .map(|c| &c.resource)
            .chain(p.depth.iter().map(|d| &d.resource))
            .chain(p.writes.iter())
        {
            let _ = writeln!(s, "  {} -> {};", q(&format!("pass:{}", p.name)), q(&format!("res:{w}")));
        }
    }
    for r in &plan.resources {
        let shape = if r.name == plan.output { "doubleoctagon" } else { "ellipse" };
        let _ = writeln!(
            s,
            "  {} [shape={shape}, label={}];",
            q(&format!("res:{}", r.name)),
            q(&format!("{}\\n{}", r.name, r.format.clone().unwrap_or_else(|| r.size.clone())))
        );
    }
    for c in &plan.culled {
        let _ = writeln!(
            s,
            "  {} [shape=box, style=dashed, fontcolor=gray, label={}];",
            q(&format!("culled:{}", c.name)),
            q(&format!("{} (culled)\\n{}", c.name, c.reason))
        );
    }
    s.push_str("}\n");
    s
}
