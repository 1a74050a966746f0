//! Human-readable and Graphviz renderings of a Plan (`plan --explain`, `plan --dot`).

use super::*;
use crate::layout::{BindingType, SampleType};
use std::fmt::Write;

/// How a pass's work reads in plans: `Scene`, `Vertices(3)`, `Fullscreen`, `Groups(2, 1, 1) from Size(hdr)`.
pub fn work_word(plan: &Plan, w: &Work) -> String {
    match w {
        Work::Raster { draw: Draw::Scene, .. } => "Scene".into(),
        Work::Raster {
            draw: Draw::Transparent, ..
        } => "Transparent".into(),
        Work::Raster {
            draw: Draw::Vertices(n), ..
        } => format!("Vertices({n})"),
        Work::Raster {
            draw: Draw::Triangles(n), ..
        } => format!("Triangles({n}): {n} vertices × each scene triangle (vertex pulling)"),
        Work::Raster {
            draw: Draw::LightVolume, ..
        } => "LightVolume: the bounding volume of each light (standard `light_volumes`)".into(),
        Work::Fullscreen { .. } => "Fullscreen".into(),
        Work::Compute {
            groups: [x, y, z],
            sized_from: None,
            ..
        } => format!("Groups({x}, {y}, {z})"),
        Work::Compute {
            groups: [x, y, z],
            sized_from: Some(r),
            ..
        } => format!("Groups({x}, {y}, {z}) from Size({})", plan.res(*r).name),
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
        } => format!("storage texture {} {} {access:?}", view_dimension.wgsl_word(), format.name()),
        BindingType::Sampler(k) => format!("sampler ({k:?})"),
        BindingType::Uniform { min_binding_size } => format!("uniform ({min_binding_size} B)"),
        BindingType::Storage {
            read_only,
            min_binding_size,
        } => format!("storage {} (≥{min_binding_size} B)", if *read_only { "read" } else { "read_write" }),
        BindingType::AccelerationStructure => "acceleration structure".into(),
    }
}

fn source_word(plan: &Plan, s: &PlanSource) -> String {
    match s {
        BindSource::Resource(r) => plan.res(*r).name.clone(),
        BindSource::Prev(r) => format!("Prev({})", plan.res(*r).name),
        BindSource::Sampler(n) => format!("sampler {}", plan.sampler(*n).name),
        BindSource::Params => "params".into(),
        BindSource::Frame => "<frame>".into(),
        BindSource::Instance => "<instance>".into(),
        BindSource::Lights => "<lights>".into(),
        BindSource::Triangles => "<triangles>".into(),
        BindSource::LightVolumes => "<light_volumes>".into(),
        BindSource::AreaLights => "<area_lights>".into(),
        BindSource::HitTriangles => "<hit_triangles>".into(),
        BindSource::HitMaterials => "<hit_materials>".into(),
        BindSource::HitEmitters => "<hit_emitters>".into(),
        BindSource::HitCorners => "<hit_corners>".into(),
        BindSource::HitMaps => "<hit_maps>".into(),
        BindSource::Draw(d) => format!("<draw.{}>", d.name()),
    }
}

fn read_word(plan: &Plan, r: &PlanRead) -> String {
    let name = &plan.res(r.resource).name;
    match (r.prev, r.mip) {
        (true, _) => format!("Prev({name})"),
        (false, Some(m)) => format!("{name}{}", mip_word(m)),
        (false, None) => match r.layer {
            Some(crate::ir::LayerSel::Rep(0)) => format!("{name} layer rep"),
            Some(crate::ir::LayerSel::Rep(d)) => format!("{name} layer rep{d:+}"),
            Some(l) => format!("{name} layer {}", l.at(0, 1).unwrap_or(0)),
            None => name.clone(),
        },
    }
}

/// ` mip 2`, ` mip rep-1`: a mip selection as LBP writes it (level 0 of a target: nothing).
fn mip_word(m: crate::ir::MipSel) -> String {
    use crate::ir::MipSel;
    match m {
        MipSel::Level(l) => format!(" mip {l}"),
        MipSel::Rep(0) => " mip rep".into(),
        MipSel::Rep(d) => format!(" mip rep{d:+}"),
    }
}

fn words<T>(items: &[T], f: impl Fn(&T) -> String) -> String {
    items.iter().map(f).collect::<Vec<_>>().join(", ")
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
                (Some(r), true) => writeln!(s, "  {} = {}  ({r})", v.variant, v.option),
                _ => writeln!(s, "  {} = {}", v.variant, v.option),
            }
            .ok();
        }
    }
    let preset: Vec<_> = plan.params.iter().filter_map(|p| p.preset.as_ref().map(|o| (p, o))).collect();
    if !preset.is_empty() {
        let _ = writeln!(s, "\npresets:");
        for (p, o) in preset {
            let _ = writeln!(s, "  {} = {}  ({o})", p.name, p.default.describe());
        }
    }
    let _ = writeln!(s, "\npasses ({} kept, in order):", plan.passes.len());
    for (i, p) in plan.passes.iter().enumerate() {
        pass_text(&mut s, plan, i, p);
        if let Some(f) = p.from.as_ref().filter(|_| explain) {
            let _ = writeln!(s, "      from: {f}");
        }
        if let Some(o) = p.origin.as_ref().filter(|_| explain) {
            let _ = writeln!(s, "      written: {o}");
        }
        if explain && p.continues && i > 0 {
            let _ = writeln!(s, "      continues the render pass of `{}`", plan.passes[i - 1].name);
        }
        if explain && !p.arms.is_empty() {
            let arms: Vec<String> = p.arms.iter().map(|(v, o)| format!("{v} = {}", o.join(" | "))).collect();
            let _ = writeln!(s, "      arms: {}", arms.join(", "));
        }
        for st in p.stages.iter().filter(|st| explain && !st.constants.is_empty()) {
            let values: Vec<String> = st.constants.iter().map(|(k, v)| format!("{k} = {v}")).collect();
            let _ = writeln!(s, "      constants ({}): {}", st.stage.word(), values.join(", "));
        }
        if explain {
            pass_layouts(&mut s, plan, p);
        }
    }
    if !plan.culled.is_empty() {
        let _ = writeln!(s, "\nculled ({}):", plan.culled.len());
        for c in &plan.culled {
            match explain {
                true => writeln!(s, "  {:<26} {}", c.name, c.reason),
                false => writeln!(s, "  {}", c.name),
            }
            .ok();
        }
    }
    let _ = writeln!(s, "\nresources:");
    for r in &plan.resources {
        let _ = writeln!(s, "  {}", resource_line(r));
    }
    let _ = writeln!(
        s,
        "\nmemory: {} at {}×{}; {} with transient resources aliased (`plan --memory`)",
        mib(plan.memory_bytes),
        plan.resolution.0,
        plan.resolution.1,
        mib(plan.physical_bytes)
    );
    let _ = writeln!(s, "output: {}", plan.output_resource().name);
    if let Some(h) = plan.hdr_output {
        let _ = writeln!(s, "hdr_output: {}", plan.res(h).name);
    }
    if plan.jitter {
        let _ = writeln!(s, "camera: jittered by a sub-pixel offset each frame (Halton 2, 3 over 16 frames)");
    }
    s
}

/// ` ×6 (per Point light, per face)` for repeated passes.
fn repetitions(p: &PlanPass) -> String {
    if p.per_light.is_empty() && !p.per_face && p.per_mip.is_none() && p.repeat == 1 {
        return String::new();
    }
    let kinds: Vec<&str> = p.per_light.iter().map(|k| k.name()).collect();
    let mut parts = vec![];
    if !kinds.is_empty() {
        let casting = if p.shadow_casters { " casting shadows" } else { "" };
        parts.push(format!("per {} light{casting}", kinds.join("/")));
    }
    if p.per_face {
        parts.push("per face".to_string());
    }
    if let Some(m) = p.per_mip {
        parts.push(format!("per mip {}..{}", m.from, m.to));
    }
    if p.repeat > 1 {
        parts.push(format!("repeated {} times", p.repeat));
    }
    format!(" ×{} ({})", p.repetitions, parts.join(", "))
}

/// When the runtime runs the pass: every frame (and why), or when something it depends on
/// changed since it last ran.
fn reuse_word(p: &PlanPass) -> String {
    let d = &p.depends;
    if let Some(why) = &d.always {
        return format!("runs every frame: {why}");
    }
    let mut on: Vec<String> = vec![];
    let flags = [
        (d.camera, "camera"),
        (d.time, "time"),
        (d.frame_index, "frame index"),
        (d.lights, "lights"),
        (!p.per_light.is_empty(), "its light"),
        (d.scene, "scene meshes"),
        (!p.uniform_blocks.is_empty(), "parameters"),
        (!p.reads.is_empty() || loads(p), "what it reads"),
    ];
    on.extend(flags.iter().filter(|(b, _)| *b).map(|(_, w)| w.to_string()));
    if on.is_empty() {
        return "runs once (depends on nothing that changes)".into();
    }
    let fields = if d.frame_fields.is_empty() {
        String::new()
    } else {
        let names: Vec<&str> = d.frame_fields.iter().map(|f| f.name()).collect();
        format!(" (frame: {})", names.join(", "))
    };
    format!("runs when changed: {}{fields}", on.join(", "))
}

/// Does the pass build on an attachment's earlier content (`load`)?
fn loads(p: &PlanPass) -> bool {
    let t = p.work.targets();
    t.is_some_and(|t| t.color.iter().any(|c| c.load.is_load()) || t.depth.as_ref().is_some_and(|d| d.load.is_load()))
}

/// Everything a pass writes, as text: attachments, then storage. A depth target only tested
/// against (not written, loaded) says so.
fn written(plan: &Plan, p: &PlanPass) -> Vec<String> {
    let t = p.work.targets();
    let level = |m: crate::ir::MipSel| {
        if m == crate::ir::MipSel::Level(0) {
            String::new()
        } else {
            mip_word(m)
        }
    };
    let color = t
        .into_iter()
        .flat_map(|t| &t.color)
        .map(|c| format!("{}{}", plan.res(c.resource).name, level(c.mip)));
    let depth = t.and_then(|t| t.depth.as_ref()).map(|d| {
        let tested = !d.write && matches!(d.load, Load::Load);
        format!("{} {}", if tested { "depth-test" } else { "depth" }, plan.res(d.resource).name)
    });
    color
        .chain(depth)
        .chain(p.writes.iter().map(|w| format!("storage {}", plan.res(*w).name)))
        .collect()
}

/// What a pass is, a fact a line, with names instead of indices (`lightbench diff` compares
/// two Plans' passes by these; the `after:` line is left out, order being compared apart).
pub fn pass_facts(plan: &Plan, p: &PlanPass) -> Vec<String> {
    let mut s = String::new();
    let _ = writeln!(s, "{} {}{}", p.work.kind_word(), work_word(plan, &p.work), repetitions(p));
    let _ = writeln!(
        s,
        "reads [{}] -> writes [{}]",
        words(&p.reads, |r| read_word(plan, r)),
        written(plan, p).join(", ")
    );
    pass_layouts(&mut s, plan, p);
    s.lines()
        .map(|l| l.trim().to_string())
        .filter(|l| !l.is_empty() && !l.starts_with("after:"))
        .collect()
}

/// A resource as `plan` lists it: shape, instances, memory, usage.
pub fn resource_fact(r: &PlanResource) -> String {
    resource_line(r).split_whitespace().collect::<Vec<_>>().join(" ")
}

/// `plan --memory`: each resource's memory, the passes from its first to its last use, and
/// whose memory it shares or why it keeps its own; logical and physical totals.
pub fn memory_text(plan: &Plan) -> String {
    let mut s = String::new();
    let (logical, physical) = (plan.memory_bytes, plan.physical_bytes);
    let ratio = if logical == 0 { 1.0 } else { physical as f64 / logical as f64 };
    let _ = writeln!(
        s,
        "memory at {}×{}: {} logical, {} physical with transient resources aliased ({ratio:.2}×)\n",
        plan.resolution.0,
        plan.resolution.1,
        mib(logical),
        mib(physical)
    );
    let _ = writeln!(s, "  {:<22} {:>11}  {:<40} memory", "resource", "size", "used by passes");
    for (r, (life, kept)) in plan.resources.iter().zip(super::alias::report(plan)) {
        let used = match life {
            Some((a, b)) if a == b => plan.passes[a].name.clone(),
            Some((a, b)) => format!("{} .. {}", plan.passes[a].name, plan.passes[b].name),
            None => "none".into(),
        };
        let memory = match (r.shares, kept) {
            (Some(o), _) => format!("shares `{}`", plan.res(o).name),
            (None, Some(why)) => format!("own ({why})"),
            (None, None) => "own".into(),
        };
        let _ = writeln!(s, "  {:<22} {:>11}  {:<40} {memory}", r.name, mib(r.bytes), used);
    }
    s
}

pub fn mib_text(bytes: u64) -> String {
    mib(bytes)
}

fn pass_text(s: &mut String, plan: &Plan, i: usize, p: &PlanPass) {
    let _ = writeln!(
        s,
        "  {:>2}. {:<22} {:<10} {}{}",
        i + 1,
        p.name,
        p.work.kind_word(),
        work_word(plan, &p.work),
        repetitions(p)
    );
    let _ = writeln!(
        s,
        "      reads [{}] -> writes [{}]",
        words(&p.reads, |r| read_word(plan, r)),
        written(plan, p).join(", ")
    );
}

fn pass_layouts(s: &mut String, plan: &Plan, p: &PlanPass) {
    for st in &p.stages {
        let _ = writeln!(s, "      {} {}#{}", st.stage.word(), st.file, st.entry);
    }
    let _ = writeln!(s, "      {}", reuse_word(p));
    if !p.after.is_empty() {
        let _ = writeln!(s, "      after: {}", words(&p.after, |a| plan.passes[a.0 as usize].name.clone()));
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
                source_word(plan, &e.source),
                words(&e.visibility, |v| v.word().to_string())
            );
        }
    }
    for b in &p.uniform_blocks {
        let _ = writeln!(s, "      block `{}`: {} bytes, align {}", b.global, b.size, b.align);
        for f in &b.fields {
            let _ = writeln!(
                s,
                "        +{:<4} {:<12} {:<10} = {}",
                f.offset,
                f.name,
                f.ty.wgsl(),
                field_source(plan, f)
            );
        }
    }
}

/// A block field's parameter name (a per-pass value's with the pass's value), or a fixed
/// value as the field's type reads it.
fn field_source(plan: &Plan, f: &crate::layout::UniformField) -> String {
    use crate::layout::{FieldSource, FieldType};
    match &f.source {
        FieldSource::Param(id) => match plan.param(*id) {
            p @ crate::plan::PlanParam { pass: Some(_), .. } => format!("{} (per pass: {})", p.name, p.default.describe()),
            p => p.name.clone(),
        },
        FieldSource::Fixed(w) => {
            let show = |x: &u32| match f.ty {
                FieldType::I32 => (*x as i32).to_string(),
                FieldType::U32 => x.to_string(),
                _ => format!("{}", f32::from_bits(*x)),
            };
            let parts: Vec<String> = w.iter().map(show).collect();
            match parts.len() {
                1 => format!("{} (per pass)", parts[0]),
                _ => format!("({}) (per pass)", parts.join(", ")),
            }
        }
    }
}

/// `Rgba16Float viewport (128×128) ×6 layers Cube` or `16 bytes`.
pub fn shape_word(r: &PlanResource) -> String {
    match &r.shape {
        ResourceShape::Texture {
            format,
            size,
            extent,
            layers,
            view,
            mips,
        } => {
            let mut shape = format!("{} {} ({}×{})", format.name(), size.describe(), extent.0, extent.1);
            if *layers > 1 {
                shape += &format!(" ×{layers} layers");
            }
            if *view != ViewDim::D2 {
                shape += &format!(" {}", view.name());
            }
            if *mips > 1 {
                shape += &format!(" {mips} mips");
            }
            shape
        }
        ResourceShape::Buffer { size, .. } => format!("{size} bytes"),
        ResourceShape::AccelerationStructure => "acceleration structure (built from the scene)".into(),
    }
}

fn resource_line(r: &PlanResource) -> String {
    let mut extra = String::new();
    if !r.per_light.is_empty() {
        let k: Vec<&str> = r.per_light.iter().map(|k| k.name()).collect();
        let casting = if r.casters_only { " casting shadows" } else { "" };
        extra += &format!(" per {} light{casting} ×{}", k.join("/"), r.instances);
    }
    if r.history {
        extra += " history ×2";
    }
    if r.data {
        extra += " data";
    }
    if r.external {
        extra += " external";
    }
    let usage: Vec<&str> = r.usage.iter().map(|u| u.name()).collect();
    format!(
        "{:<18} {:<44}{extra}  {}  [{}]",
        r.name,
        shape_word(r),
        mib(r.bytes),
        usage.join(" | ")
    )
}

/// Graphviz: passes as boxes, resources as ellipses, culled passes dashed.
pub fn to_dot(plan: &Plan) -> String {
    let mut s = String::new();
    let q = |x: &str| format!("\"{}\"", x.replace('"', "\\\""));
    let _ = writeln!(s, "digraph {} {{", q(&plan.pipeline));
    let _ = writeln!(s, "  rankdir=LR;\n  node [fontname=\"sans-serif\"];");
    for p in &plan.passes {
        let node = q(&format!("pass:{}", p.name));
        let _ = writeln!(
            s,
            "  {node} [shape=box, style=filled, fillcolor=\"#dde8f5\", label={}];",
            q(&format!("{}\\n{}", p.name, p.work.kind_word()))
        );
        for r in &p.reads {
            let style = if r.prev { " [style=dashed, label=\"prev\"]" } else { "" };
            let _ = writeln!(s, "  {} -> {node}{style};", q(&format!("res:{}", plan.res(r.resource).name)));
        }
        for w in p.written() {
            let _ = writeln!(s, "  {node} -> {};", q(&format!("res:{}", plan.res(w).name)));
        }
    }
    for r in &plan.resources {
        let shape = if r.name == plan.output_resource().name {
            "doubleoctagon"
        } else {
            "ellipse"
        };
        let detail = match &r.shape {
            ResourceShape::Texture { format, .. } => format.name().to_string(),
            ResourceShape::Buffer { size, .. } => format!("{size} bytes"),
            ResourceShape::AccelerationStructure => "acceleration structure".into(),
        };
        let _ = writeln!(
            s,
            "  {} [shape={shape}, label={}];",
            q(&format!("res:{}", r.name)),
            q(&format!("{}\\n{detail}", r.name))
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
