//! Stage `stage-io`: fragment outputs against color attachments, vertex inputs against the
//! scene's vertex layout, and vertex outputs against fragment inputs.

use super::StageShader;
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::format::ScalarKind;
use crate::ir::*;
use crate::shader::reflect::{self, IoVar};

/// The vertex layout the runtime gives `draw: Scene` passes: (location, name, WGSL type).
pub const SCENE_VERTEX: [(u32, &str, naga::ScalarKind, u32); 5] = [
    (0, "position", naga::ScalarKind::Float, 3),
    (1, "normal", naga::ScalarKind::Float, 3),
    (2, "uv", naga::ScalarKind::Float, 2),
    (3, "tangent", naga::ScalarKind::Float, 4),
    (4, "uv1", naga::ScalarKind::Float, 2),
];

fn ty_word(v: &IoVar) -> String {
    let s = match v.scalar {
        naga::ScalarKind::Float => "f32",
        naga::ScalarKind::Uint => "u32",
        naga::ScalarKind::Sint => "i32",
        _ => "bool",
    };
    if v.components == 1 {
        s.to_string()
    } else {
        format!("vec{}<{s}>", v.components)
    }
}

pub fn check(p: &Pipeline, pass: &Pass, stages: &[StageShader], diags: &mut Diagnostics) {
    let find = |s: Stage| stages.iter().find(|st| st.stage == s);
    if let Some(fs) = find(Stage::Fragment) {
        fragment_outputs(p, pass, fs, diags);
        if let Some(vs) = find(Stage::Vertex) {
            interstage(vs, fs, diags);
        }
    }
    if let Some(vs) = find(Stage::Vertex) {
        vertex_inputs(pass, vs, diags);
    }
}

fn fragment_outputs(p: &Pipeline, pass: &Pass, fs: &StageShader, diags: &mut Diagnostics) {
    let mut outs = reflect::outputs(&fs.module, fs.entry);
    let ep_span = fs.sref.entry.span;
    // A dual-source pair (`@blend_src(0)`, `@blend_src(1)`) shares one location: one target.
    let dual = outs.iter().any(|o| o.blend_src == Some(1));
    outs.retain(|o| o.blend_src.unwrap_or(0) == 0);
    dual_source(pass, fs, dual, diags);
    if outs.len() != pass.color().len() {
        let mut d = Diagnostic::error(
            Code::FragmentOutputs,
            format!(
                "fragment entry point `{}` writes {} color output(s) but pass `{}` has {} color target(s)",
                fs.sref.entry.value,
                outs.len(),
                pass.name.value,
                pass.color().len()
            ),
            ep_span,
        )
        .with_secondary(fs.module.entry_span(fs.entry), "the entry point, whose result declares its outputs");
        if let Some(first) = pass.color().first() {
            d = d.with_secondary(first.span.to(pass.color()[pass.color().len() - 1].span), "color targets");
        }
        diags.push(d);
        return;
    }
    for (i, (o, c)) in outs.iter().zip(pass.color()).enumerate() {
        if o.location != i as u32 {
            diags.push(Diagnostic::error(
                Code::FragmentOutputs,
                format!(
                    "fragment outputs must use locations 0..{}; found @location({}) for target `{}`",
                    pass.color().len(),
                    o.location,
                    c.resource.value
                ),
                ep_span,
            ));
            continue;
        }
        let Some(t) = p.resource(&c.resource).and_then(|r| r.texture()) else {
            continue;
        };
        let f = t.format.value;
        let want = match f.kind() {
            ScalarKind::Uint => naga::ScalarKind::Uint,
            ScalarKind::Sint => naga::ScalarKind::Sint,
            _ => naga::ScalarKind::Float,
        };
        if o.scalar != want {
            diags.push(
                Diagnostic::error(
                    Code::FragmentOutputKind,
                    format!(
                        "@location({i}) is `{}` but target `{}` has format {} which needs {} values",
                        ty_word(o),
                        c.resource.value,
                        f.name(),
                        match want {
                            naga::ScalarKind::Uint => "u32",
                            naga::ScalarKind::Sint => "i32",
                            _ => "f32",
                        }
                    ),
                    c.resource.span,
                )
                .with_secondary(ep_span, "fragment entry point")
                .with_secondary(t.format.span, "format declared here"),
            );
        } else if o.components < f.components() {
            diags.push(
                Diagnostic::error(
                    Code::FragmentOutputKind,
                    format!(
                        "@location({i}) has {} component(s) but {} of `{}` has {}",
                        o.components,
                        f.name(),
                        c.resource.value,
                        f.components()
                    ),
                    c.resource.span,
                )
                .with_secondary(ep_span, "fragment entry point"),
            );
        }
    }
}

/// `blend: DualSource` takes its second source from the shader's `@blend_src(1)` output.
fn dual_source(pass: &Pass, fs: &StageShader, dual: bool, diags: &mut Diagnostics) {
    for c in pass.color() {
        let Some(b) = c.blend.as_ref().filter(|b| b.value == crate::ir::Blend::DualSource) else {
            continue;
        };
        if !dual {
            diags.push(
                Diagnostic::error(
                    Code::FragmentOutputs,
                    format!(
                        "target `{}` blends `DualSource`, but entry point `{}` writes no `@blend_src(1)` output",
                        c.resource.value, fs.sref.entry.value
                    ),
                    b.span,
                )
                .with_secondary(fs.module.entry_span(fs.entry), "the entry point, whose result declares its outputs")
                .with_note("write `@location(0) @blend_src(0)` and `@location(0) @blend_src(1)` (`enable dual_source_blending;`), or choose another blend"),
            );
        }
    }
}

fn vertex_inputs(pass: &Pass, vs: &StageShader, diags: &mut Diagnostics) {
    let ins = reflect::inputs(&vs.module, vs.entry);
    match &pass.kind {
        PassKind::Raster(r) if r.draw.uses_scene() => {
            for i in &ins {
                match SCENE_VERTEX.iter().find(|v| v.0 == i.location) {
                    None => diags.push(
                        Diagnostic::error(Code::VertexInput, format!("vertex input @location({}) is not provided by scene meshes", i.location), vs.sref.entry.span)
                            .with_note("scene vertices: @location(0) position: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) uv: vec2<f32>, @location(3) tangent: vec4<f32>"),
                    ),
                    Some(&(_, name, kind, n)) if kind != i.scalar || n != i.components => diags.push(Diagnostic::error(
                        Code::VertexInput,
                        format!("vertex input @location({}) is `{}` but the scene's {name} is vec{n}<f32>", i.location, ty_word(i)),
                        vs.sref.entry.span,
                    )),
                    _ => {}
                }
            }
        }
        _ => {
            if let Some(i) = ins.first() {
                diags.push(Diagnostic::error(
                    Code::VertexInput,
                    format!(
                        "vertex input @location({}) has no vertex buffer: only `draw: Scene` passes get vertex attributes",
                        i.location
                    ),
                    vs.sref.entry.span,
                ));
            }
        }
    }
}

fn interstage(vs: &StageShader, fs: &StageShader, diags: &mut Diagnostics) {
    let outs = reflect::outputs(&vs.module, vs.entry);
    for i in reflect::inputs(&fs.module, fs.entry) {
        match outs.iter().find(|o| o.location == i.location) {
            None => diags.push(
                Diagnostic::error(
                    Code::StageIo,
                    format!(
                        "fragment input @location({}) `{}` is not written by vertex entry point `{}`",
                        i.location, i.name, vs.sref.entry.value
                    ),
                    fs.sref.entry.span,
                )
                .with_secondary(vs.sref.entry.span, "vertex stage"),
            ),
            Some(o) if o.scalar != i.scalar || o.components != i.components => diags.push(Diagnostic::error(
                Code::StageIo,
                format!(
                    "fragment input @location({}) is `{}` but the vertex stage writes `{}`",
                    i.location,
                    ty_word(&i),
                    ty_word(o)
                ),
                fs.sref.entry.span,
            )),
            _ => {}
        }
    }
}
