//! Stage `bindings`: every shader global an entry point uses is satisfied by a declared
//! read, write, sampler, parameter block or a standard runtime block, with a compatible type.
//! Produces the pass's bind group layouts and uniform block layouts.

use super::StageShader;
use crate::diag::{did_you_mean, Diagnostic, Diagnostics};
use crate::format::{ScalarKind, TextureFormat};
use crate::ir::*;
use crate::plan::{BindSource, BindingType, PlanBindGroup, PlanBinding, SampleType, SamplerKind, UniformBlock, UniformField};
use crate::profile::Profile;
use crate::shader::reflect::{self, BindingTy, GlobalBinding, ShaderDim, TexKind};
use std::collections::BTreeMap;

/// Names the runtime always provides (see README "Standard bindings").
pub const FRAME: &str = "frame";
pub const INSTANCE: &str = "instance";
pub const LIGHTS: &str = "lights";
/// Per-draw slots bound for each mesh in `draw: Scene` passes.
pub const DRAW_SLOTS: [&str; 7] = [
    "mesh",
    "material",
    "base_color_map",
    "normal_map",
    "metallic_roughness_map",
    "emissive_map",
    "material_sampler",
];

pub struct Resolved {
    pub groups: Vec<PlanBindGroup>,
    pub uniform_blocks: Vec<UniformBlock>,
    /// Per stage: counts for limit checks.
    pub per_stage: BTreeMap<&'static str, StageCounts>,
}

#[derive(Default, Clone, Copy)]
pub struct StageCounts {
    pub sampled_textures: u64,
    pub samplers: u64,
    pub storage_textures: u64,
    pub uniform_buffers: u64,
    pub storage_buffers: u64,
}

struct Used<'a> {
    g: GlobalBinding,
    stage: &'a StageShader,
    stages: Vec<&'static str>,
}

pub fn resolve(p: &Pipeline, pass: &Pass, stages: &[StageShader], profile: &Profile, diags: &mut Diagnostics) -> Option<Resolved> {
    let before = diags.error_count();
    // Gather used globals across stages, keyed by (group, binding).
    let mut used: BTreeMap<(u32, u32), Used> = BTreeMap::new();
    for st in stages {
        for g in st.module.globals.iter().cloned() {
            if !reflect::used_by(&st.module, st.entry, g.handle) {
                continue;
            }
            let word = super::entry::stage_word(st.stage);
            match used.get_mut(&(g.group, g.binding)) {
                Some(u)
                    if u.g.name != g.name
                        || u.g.ty != g.ty && !matches!((&u.g.ty, &g.ty), (BindingTy::Uniform { .. }, BindingTy::Uniform { .. })) =>
                {
                    diags.push(
                        Diagnostic::error(
                            "binding-conflict",
                            format!(
                                "@group({}) @binding({}) is `{}` in one stage and `{}` in another",
                                g.group, g.binding, u.g.name, g.name
                            ),
                            st.module.global_span(g.handle),
                        )
                        .with_secondary(u.stage.module.global_span(u.g.handle), "other declaration"),
                    );
                }
                Some(u) => {
                    if !u.stages.contains(&word) {
                        u.stages.push(word)
                    }
                }
                None => {
                    used.insert(
                        (g.group, g.binding),
                        Used {
                            g,
                            stage: st,
                            stages: vec![word],
                        },
                    );
                }
            }
        }
    }

    // Which sampler each texture is sampled with (per entry point).
    let mut sampled_with: Vec<(String, String)> = vec![];
    for st in stages {
        for (img, smp) in reflect::sampling_pairs(&st.module, st.entry) {
            let name = |h: naga::Handle<naga::GlobalVariable>| st.module.module.global_variables[h].name.clone().unwrap_or_default();
            sampled_with.push((name(img), name(smp)));
        }
    }

    let explicit: BTreeMap<&str, &crate::span::Spanned<String>> = pass.bind.iter().map(|(k, v)| (k.value.as_str(), v)).collect();
    let scene_draw = matches!(pass.kind, PassKind::Raster { draw: Draw::Scene, .. });
    let attachments: Vec<&str> = pass
        .color
        .iter()
        .map(|c| c.resource.value.as_str())
        .chain(pass.depth.iter().map(|d| d.resource.value.as_str()))
        .collect();
    let mut groups: BTreeMap<u32, Vec<PlanBinding>> = BTreeMap::new();
    let mut uniform_blocks = vec![];
    let mut per_stage: BTreeMap<&'static str, StageCounts> = BTreeMap::new();
    let mut used_reads: Vec<String> = vec![];
    let mut params_used = false;

    for u in used.values() {
        let g = &u.g;
        let gspan = u.stage.module.global_span(g.handle);
        let target: Option<&str> = explicit.get(g.name.as_str()).map(|s| s.value.as_str());
        // 1. parameter block
        if target == Some("params") || (target.is_none() && g.name == pass.param_block.value) {
            params_used = true;
            match &g.ty {
                BindingTy::Uniform { ty, size } => {
                    if let Some(block) = param_block(p, pass, u.stage, g, *ty, *size, diags) {
                        uniform_blocks.push(block);
                    }
                    push(
                        &mut groups,
                        g,
                        BindSource::Params,
                        BindingType::Uniform { min_binding_size: *size },
                        &u.stages,
                    );
                }
                _ => diags.push(Diagnostic::error(
                    "binding-type",
                    format!("parameter block `{}` must be `var<uniform>`", g.name),
                    gspan,
                )),
            }
            continue;
        }
        // 2. standard runtime blocks
        if target.is_none() && (g.name == FRAME || g.name == INSTANCE) {
            match &g.ty {
                BindingTy::Uniform { size, .. } => {
                    let src = if g.name == FRAME { BindSource::Frame } else { BindSource::Instance };
                    push(&mut groups, g, src, BindingType::Uniform { min_binding_size: *size }, &u.stages);
                }
                _ => diags.push(Diagnostic::error(
                    "binding-type",
                    format!("standard block `{}` must be `var<uniform>`", g.name),
                    gspan,
                )),
            }
            continue;
        }
        if target.is_none() && g.name == LIGHTS {
            match &g.ty {
                BindingTy::Storage { read_only: true, size } => push(
                    &mut groups,
                    g,
                    BindSource::Lights,
                    BindingType::Storage {
                        read_only: true,
                        min_binding_size: *size,
                    },
                    &u.stages,
                ),
                _ => diags.push(Diagnostic::error(
                    "binding-type",
                    "the light array `lights` must be `var<storage, read>`",
                    gspan,
                )),
            }
            continue;
        }
        if target.is_none() && DRAW_SLOTS.contains(&g.name.as_str()) {
            if !scene_draw {
                diags.push(
                    Diagnostic::error(
                        "binding-unsatisfied",
                        format!("per-draw binding `{}` is only provided to `draw: Scene` raster passes", g.name),
                        gspan,
                    )
                    .with_secondary(pass.name.span, "in this pass"),
                );
                continue;
            }
            let ty = match &g.ty {
                BindingTy::Uniform { size, .. } if g.name == "material" || g.name == "mesh" => {
                    BindingType::Uniform { min_binding_size: *size }
                }
                BindingTy::Texture {
                    kind: TexKind::Float,
                    dim: ShaderDim::D2,
                    multisampled: false,
                } if g.name.ends_with("_map") => BindingType::Texture {
                    sample_type: SampleType::Float { filterable: true },
                    view_dimension: ShaderDim::D2,
                    multisampled: false,
                },
                BindingTy::Sampler { comparison: false } if g.name == "material_sampler" => BindingType::Sampler(SamplerKind::Filtering),
                _ => {
                    diags.push(Diagnostic::error(
                        "binding-type",
                        format!(
                            "per-draw binding `{}` has type `{}`; see README \"Standard bindings\"",
                            g.name, g.type_name
                        ),
                        gspan,
                    ));
                    continue;
                }
            };
            push(&mut groups, g, BindSource::Draw(g.name.clone()), ty, &u.stages);
            continue;
        }
        // 3. samplers
        if let BindingTy::Sampler { comparison } = g.ty {
            let decl = match target {
                Some(t) => p.sampler(t),
                None => p.samplers.iter().find(|s| shader_ident(&s.name) == g.name),
            };
            let Some(decl) = decl else {
                let names: Vec<String> = p.samplers.iter().map(|s| shader_ident(&s.name)).collect();
                let mut d = Diagnostic::error(
                    "binding-unsatisfied",
                    format!(
                        "sampler `{}` (@group({}) @binding({})) matches no declared sampler",
                        g.name, g.group, g.binding
                    ),
                    gspan,
                )
                .with_secondary(pass.name.span, "used by this pass");
                if let Some(s) = did_you_mean(&g.name, names.iter().map(|s| s.as_str())) {
                    d = d.with_note(format!("did you mean `{s}`?"));
                }
                diags.push(d.with_note("declare it under `samplers: { ... }` in the pipeline"));
                continue;
            };
            let kind = decl.binding_kind();
            if comparison != (kind == SamplerKind::Comparison) {
                diags.push(
                    Diagnostic::error(
                        "sampler-type",
                        if comparison {
                            format!(
                                "`{}` is a `sampler_comparison` but sampler `{}` has no `compare`",
                                g.name, decl.name.value
                            )
                        } else {
                            format!(
                                "`{}` is a plain `sampler` but sampler `{}` is a comparison sampler",
                                g.name, decl.name.value
                            )
                        },
                        gspan,
                    )
                    .with_secondary(decl.span, "declared here"),
                );
                continue;
            }
            per_stage_count(&mut per_stage, &u.stages, |c| c.samplers += 1);
            push(
                &mut groups,
                g,
                BindSource::Sampler(decl.name.value.clone()),
                BindingType::Sampler(kind),
                &u.stages,
            );
            continue;
        }
        // 4. resources: reads, Prev reads, storage writes
        let read = pass.reads.iter().find(|r| match target {
            Some(t) => r.name().value == t,
            None => {
                if r.is_prev() {
                    history_ident(r.name()) == g.name
                } else {
                    shader_ident(r.name()) == g.name
                }
            }
        });
        let write = pass.writes.iter().find(|w| match target {
            Some(t) => w.value == t,
            None => shader_ident(w) == g.name,
        });
        let (res_name, prev, writable) = match (read, write) {
            (_, Some(w)) => (w.value.clone(), false, true),
            (Some(r), None) => (r.name().value.clone(), r.is_prev(), false),
            (None, None) => {
                let decl = p
                    .resources
                    .iter()
                    .find(|r| shader_ident(&r.name) == g.name || history_ident(&r.name) == g.name);
                let mut d = Diagnostic::error(
                    "binding-unsatisfied",
                    format!(
                        "shader global `{}` (@group({}) @binding({})) is not bound by pass `{}`",
                        g.name, g.group, g.binding, pass.name.value
                    ),
                    gspan,
                )
                .with_label_text("used by the pass's entry points")
                .with_secondary(pass.name.span, "pass declared here");
                d = match decl {
                    Some(r) if attachments.contains(&r.name.value.as_str()) => d.with_note(format!(
                        "`{}` is an attachment of this pass; a pass cannot sample what it renders to (feedback loop)",
                        r.name.value
                    )),
                    Some(r) => d.with_note(format!("add `{}` to the pass's `reads` (or `writes` for storage)", r.name.value)),
                    None => {
                        let names: Vec<String> = p.resources.iter().map(|r| shader_ident(&r.name)).collect();
                        match did_you_mean(&g.name, names.iter().map(|s| s.as_str())) {
                            Some(s) => d.with_note(format!("no declared resource maps to `{}`; did you mean `{s}`?", g.name)),
                            None => d.with_note(format!(
                                "no declared resource maps to `{}`: resources bind by name with `.` as `_` (`gbuf.normal` -> `gbuf_normal`), or map it with `bind: {{\"{}\": \"resource\"}}`",
                                g.name, g.name
                            )),
                        }
                    }
                };
                diags.push(d);
                continue;
            }
        };
        let Some(res) = p.resource(&res_name) else {
            continue;
        }; // reported by declarations
        let decl_span = res.span;
        let ty = match (&g.ty, &res.kind) {
            (BindingTy::Texture { kind, dim, multisampled }, ResourceKind::Texture(t)) => {
                used_reads.push(res_name.clone());
                if *multisampled {
                    diags.push(Diagnostic::error(
                        "texture-type",
                        format!("`{}` is multisampled; lightbench resources are single-sampled", g.name),
                        gspan,
                    ));
                    continue;
                }
                let f = t.format.value;
                let sample_type = match texture_kind_ok(*kind, f) {
                    Ok(st) => st,
                    Err(why) => {
                        diags.push(
                            Diagnostic::error(
                                "texture-type",
                                format!(
                                    "`{}` is `{}` but `{}` has format {}: {why}",
                                    g.name,
                                    g.type_name,
                                    res_name,
                                    f.name()
                                ),
                                gspan,
                            )
                            .with_secondary(t.format.span, "format declared here"),
                        );
                        continue;
                    }
                };
                // Filterable where the format is filterable without optional features; 32-bit
                // floats only when a filtering sampler needs it (which needs Float32Filterable).
                let with_filtering_sampler = sampled_with.iter().any(|(img, smp)| {
                    img == &g.name
                        && p.samplers
                            .iter()
                            .find(|s| shader_ident(&s.name) == *smp || explicit.get(smp.as_str()).is_some_and(|t| t.value == s.name.value))
                            .is_some_and(|s| s.binding_kind() == SamplerKind::Filtering)
                });
                let sample_type = match sample_type {
                    SampleType::Float { .. } if f.is_depth() => SampleType::Float { filterable: false },
                    SampleType::Float { .. } if f.is_32bit_float() => SampleType::Float {
                        filterable: with_filtering_sampler && f.filterable(profile),
                    },
                    SampleType::Float { .. } => SampleType::Float {
                        filterable: f.filterable(profile),
                    },
                    s => s,
                };
                if let Err(why) = dim_ok(*dim, t) {
                    diags.push(
                        Diagnostic::error(
                            "texture-type",
                            format!(
                                "`{}` is `{}` but `{}` is declared with view {} and {} layer(s): {why}",
                                g.name,
                                g.type_name,
                                res_name,
                                t.view.value.name(),
                                t.layers.value
                            ),
                            gspan,
                        )
                        .with_secondary(t.view.span, "view declared here"),
                    );
                    continue;
                }
                // A filtering sampler on a non-filterable format is invalid in wgpu.
                for (img, smp) in &sampled_with {
                    if img != &g.name {
                        continue;
                    }
                    let decl = p
                        .samplers
                        .iter()
                        .find(|s| shader_ident(&s.name) == *smp || explicit.get(smp.as_str()).is_some_and(|t| t.value == s.name.value));
                    if let (Some(decl), SampleType::Float { filterable: false }) = (decl, sample_type) {
                        if decl.binding_kind() == SamplerKind::Filtering {
                            diags.push(
                                Diagnostic::error(
                                    "not-filterable",
                                    format!(
                                        "`{}` ({}) is sampled with filtering sampler `{}`, but {} is not filterable{}",
                                        g.name,
                                        res_name,
                                        decl.name.value,
                                        f.name(),
                                        if f.is_32bit_float() {
                                            " without the Float32Filterable feature"
                                        } else {
                                            ""
                                        }
                                    ),
                                    gspan,
                                )
                                .with_secondary(decl.span, "filtering sampler declared here")
                                .with_note("use a sampler with `filter: Nearest, mipmap: Nearest`, or `textureLoad`"),
                            );
                        }
                    }
                }
                per_stage_count(&mut per_stage, &u.stages, |c| c.sampled_textures += 1);
                BindingType::Texture {
                    sample_type,
                    view_dimension: *dim,
                    multisampled: false,
                }
            }
            (
                BindingTy::StorageTexture {
                    format,
                    write: w,
                    read: r,
                    dim,
                },
                ResourceKind::Texture(t),
            ) => {
                let f = t.format.value;
                let expected = storage_format_name(*format);
                if expected != Some(f.name()) {
                    diags.push(
                        Diagnostic::error(
                            "texture-type",
                            format!(
                                "storage texture `{}` has format `{}` but `{}` is {}",
                                g.name,
                                g.type_name,
                                res_name,
                                f.name()
                            ),
                            gspan,
                        )
                        .with_secondary(t.format.span, "format declared here"),
                    );
                    continue;
                }
                if !f.storage() {
                    diags.push(Diagnostic::error(
                        "texture-type",
                        format!("{} cannot be a storage texture", f.name()),
                        t.format.span,
                    ));
                    continue;
                }
                if *w && !writable {
                    diags.push(
                        Diagnostic::error(
                            "binding-access",
                            format!(
                                "`{}` is written by the shader but the pass lists `{}` under `reads`",
                                g.name, res_name
                            ),
                            gspan,
                        )
                        .with_note("list it under `writes`"),
                    );
                    continue;
                }
                if let Err(why) = dim_ok(*dim, t) {
                    diags.push(
                        Diagnostic::error("texture-type", format!("`{}` is `{}`: {why}", g.name, g.type_name), gspan)
                            .with_secondary(t.view.span, "view declared here"),
                    );
                    continue;
                }
                per_stage_count(&mut per_stage, &u.stages, |c| c.storage_textures += 1);
                let access = match (r, w) {
                    (true, true) => "ReadWrite",
                    (true, false) => "ReadOnly",
                    _ => "WriteOnly",
                };
                BindingType::StorageTexture {
                    format: f.name().to_string(),
                    access: access.into(),
                    view_dimension: *dim,
                }
            }
            (BindingTy::Storage { read_only, size }, ResourceKind::Buffer(b)) => {
                if !read_only && !writable {
                    diags.push(
                        Diagnostic::error(
                            "binding-access",
                            format!("`{}` is `read_write` but the pass lists `{}` under `reads`", g.name, res_name),
                            gspan,
                        )
                        .with_note("list it under `writes`, or declare it `var<storage, read>`"),
                    );
                    continue;
                }
                if b.size.value < *size as u64 {
                    diags.push(
                        Diagnostic::error(
                            "buffer-too-small",
                            format!("`{}` needs at least {size} bytes but `{}` has {}", g.name, res_name, b.size.value),
                            gspan,
                        )
                        .with_secondary(b.size.span, "size declared here"),
                    );
                    continue;
                }
                if *read_only {
                    used_reads.push(res_name.clone());
                }
                per_stage_count(&mut per_stage, &u.stages, |c| c.storage_buffers += 1);
                BindingType::Storage {
                    read_only: *read_only,
                    min_binding_size: *size,
                }
            }
            (BindingTy::Uniform { size, .. }, ResourceKind::Buffer(b)) => {
                used_reads.push(res_name.clone());
                if b.size.value < *size as u64 {
                    diags.push(Diagnostic::error(
                        "buffer-too-small",
                        format!("`{}` needs at least {size} bytes but `{}` has {}", g.name, res_name, b.size.value),
                        gspan,
                    ));
                    continue;
                }
                per_stage_count(&mut per_stage, &u.stages, |c| c.uniform_buffers += 1);
                BindingType::Uniform { min_binding_size: *size }
            }
            (sty, _) => {
                let (what, decl) = match &res.kind {
                    ResourceKind::Texture(t) => (format!("a {} texture", t.format.value.name()), t.format.span),
                    ResourceKind::Buffer(_) => ("a buffer".to_string(), decl_span),
                };
                let shader_what = match sty {
                    BindingTy::Texture { .. } => "a sampled texture",
                    BindingTy::StorageTexture { .. } => "a storage texture",
                    BindingTy::Storage { .. } => "a storage buffer",
                    BindingTy::Uniform { .. } => "a uniform buffer",
                    _ => "an unsupported binding",
                };
                diags.push(
                    Diagnostic::error(
                        "binding-type",
                        format!("`{}` is {shader_what} (`{}`) but `{}` is {what}", g.name, g.type_name, res_name),
                        gspan,
                    )
                    .with_secondary(decl, "declared here"),
                );
                continue;
            }
        };
        let src = if prev {
            BindSource::Prev(res_name)
        } else {
            BindSource::Resource(res_name)
        };
        push(&mut groups, g, src, ty, &u.stages);
    }
    for u in used.values() {
        if matches!(u.g.ty, BindingTy::Uniform { .. }) {
            per_stage_count(&mut per_stage, &u.stages, |c| c.uniform_buffers += 1);
        }
    }

    // Declared reads no entry point uses.
    for r in &pass.reads {
        if !used_reads.contains(&r.name().value) && p.resource(r.name()).is_some() {
            diags.push(
                Diagnostic::warning(
                    "unused-read",
                    format!("pass `{}` reads `{}` but no entry point uses it", pass.name.value, r.name().value),
                    r.name().span,
                )
                .with_note(format!(
                    "the shader would bind it as `{}`",
                    if r.is_prev() {
                        history_ident(r.name())
                    } else {
                        shader_ident(r.name())
                    }
                )),
            );
        }
    }
    if !pass.params.is_empty() && !params_used {
        diags.push(Diagnostic::warning(
            "unused-params",
            format!(
                "pass `{}` declares parameters but its shaders use no `{}` block",
                pass.name.value, pass.param_block.value
            ),
            pass.params[0].span.to(pass.params[pass.params.len() - 1].span),
        ));
    }
    if diags.error_count() > before {
        return None;
    }
    let groups = groups.into_iter().map(|(group, mut entries)| {
        entries.sort_by_key(|e| e.binding);
        PlanBindGroup { group, entries }
    });
    Some(Resolved {
        groups: groups.collect(),
        uniform_blocks,
        per_stage,
    })
}

fn per_stage_count(map: &mut BTreeMap<&'static str, StageCounts>, stages: &[&'static str], f: impl Fn(&mut StageCounts)) {
    for s in stages {
        f(map.entry(s).or_default());
    }
}

fn push(groups: &mut BTreeMap<u32, Vec<PlanBinding>>, g: &GlobalBinding, source: BindSource, ty: BindingType, stages: &[&'static str]) {
    let mut vis: Vec<String> = stages.iter().map(|s| s.to_string()).collect();
    vis.sort();
    groups.entry(g.group).or_default().push(PlanBinding {
        binding: g.binding,
        name: g.name.clone(),
        source,
        ty,
        visibility: vis,
    });
}

/// Sample type for a shader texture kind reading a declared format, or why they do not fit.
fn texture_kind_ok(kind: TexKind, f: TextureFormat) -> Result<SampleType, String> {
    match (kind, f.kind()) {
        (TexKind::Depth, ScalarKind::Depth) => Ok(SampleType::Depth),
        (TexKind::Depth, _) => Err("a depth texture binding needs a depth format".into()),
        // Depth formats can be read as unfilterable floats (textureLoad / nearest sampling).
        (TexKind::Float, ScalarKind::Float | ScalarKind::Depth) => Ok(SampleType::Float { filterable: true }),
        (TexKind::Uint, ScalarKind::Uint) => Ok(SampleType::Uint),
        (TexKind::Sint, ScalarKind::Sint) => Ok(SampleType::Sint),
        (TexKind::Float, k) => Err(format!(
            "a float texture cannot read {k:?} texels; use texture_2d<{}>",
            if k == ScalarKind::Uint { "u32" } else { "i32" }
        )),
        (TexKind::Uint | TexKind::Sint, _) => Err("the texel type does not match the format".into()),
    }
}

fn dim_ok(dim: ShaderDim, t: &TextureDesc) -> Result<(), String> {
    // A per-light resource is bound one instance (light) at a time, so it looks like a single texture.
    let ok = matches!(
        (dim, t.view.value),
        (ShaderDim::D2, ViewDim::D2) | (ShaderDim::D2Array, ViewDim::D2Array | ViewDim::Cube) | (ShaderDim::Cube, ViewDim::Cube)
    );
    if ok {
        Ok(())
    } else {
        Err(format!("a `texture_{}` binding cannot view it", dim.wgsl_word()))
    }
}

fn storage_format_name(f: naga::StorageFormat) -> Option<&'static str> {
    use naga::StorageFormat as S;
    Some(match f {
        S::Rgba8Unorm => "Rgba8Unorm",
        S::Rgba16Float => "Rgba16Float",
        S::R32Float => "R32Float",
        S::Rg32Float => "Rg32Float",
        S::Rgba32Float => "Rgba32Float",
        S::R32Uint => "R32Uint",
        S::Rg32Uint => "Rg32Uint",
        S::Rgba32Uint => "Rgba32Uint",
        S::R32Sint => "R32Sint",
        S::Rgba16Uint => "Rgba16Uint",
        _ => return None,
    })
}

/// Stage `param-block`: the shader struct behind the parameter block against the pass's params.
/// Offsets come from the struct as naga laid it out, so the runtime writes values there with
/// no Rust struct per pass.
fn param_block(
    p: &Pipeline,
    pass: &Pass,
    st: &StageShader,
    g: &GlobalBinding,
    ty: naga::Handle<naga::Type>,
    size: u32,
    diags: &mut Diagnostics,
) -> Option<UniformBlock> {
    let m = &st.module.module;
    let gspan = st.module.global_span(g.handle);
    let naga::TypeInner::Struct { members, .. } = &m.types[ty].inner else {
        diags.push(Diagnostic::error(
            "param-block",
            format!("parameter block `{}` must be a struct", g.name),
            gspan,
        ));
        return None;
    };
    let layouter = &st.module.layouter;
    let align = layouter[ty].alignment.round_up(1);
    let mut fields = vec![];
    let mut matched: Vec<&str> = vec![];
    let mut ok = true;
    for mem in members {
        let fname = mem.name.clone().unwrap_or_default();
        let param_ref = pass.params.iter().find(|prm| {
            let last = prm.value.rsplit('.').next().unwrap_or(&prm.value);
            shader_ident(last) == fname || shader_ident(prm) == fname
        });
        let tname = reflect::type_name(m, mem.ty);
        let Some(param_ref) = param_ref else {
            if fname.starts_with('_') {
                continue; // explicit padding
            }
            diags.push(
                Diagnostic::error(
                    "param-missing",
                    format!(
                        "field `{fname}` of parameter block `{}` has no parameter in pass `{}`",
                        g.name, pass.name.value
                    ),
                    gspan,
                )
                .with_secondary(pass.name.span, "pass declared here")
                .with_note("list the parameter under the pass's `params`, or name padding fields with a leading `_`"),
            );
            ok = false;
            continue;
        };
        matched.push(&param_ref.value);
        let Some(prm) = p.param(param_ref) else {
            continue;
        };
        let fits = match &prm.ty.value {
            ParamType::Float => tname == "f32",
            ParamType::Int => tname == "i32" || tname == "u32",
            ParamType::Bool | ParamType::Enum(_) => tname == "u32",
            ParamType::Vec2 => tname == "vec2<f32>",
            ParamType::Vec3 => tname == "vec3<f32>",
            ParamType::Vec4 => tname == "vec4<f32>",
            ParamType::Color => tname == "vec3<f32>" || tname == "vec4<f32>",
        };
        if !fits {
            let want = match &prm.ty.value {
                ParamType::Float => "f32",
                ParamType::Int => "i32 or u32",
                ParamType::Bool => "u32 (WGSL bool is not host-shareable)",
                ParamType::Enum(_) => "u32 (the option index)",
                ParamType::Vec2 => "vec2<f32>",
                ParamType::Vec3 => "vec3<f32>",
                ParamType::Vec4 => "vec4<f32>",
                ParamType::Color => "vec3<f32> or vec4<f32>",
            };
            diags.push(
                Diagnostic::error(
                    "param-type-mismatch",
                    format!(
                        "parameter `{}` is {} but shader field `{fname}` is `{tname}`",
                        prm.name.value,
                        prm.ty.name(),
                    ),
                    param_ref.span,
                )
                .with_secondary(gspan, format!("`{}.{fname}` declared in this block", g.name))
                .with_secondary(prm.ty.span, "parameter type declared here")
                .with_note(format!("a {} parameter needs a `{want}` field", prm.ty.name())),
            );
            ok = false;
            continue;
        }
        if let (ParamType::Int, "u32") = (&prm.ty.value, tname.as_str()) {
            let min_ok = prm.min.as_ref().is_some_and(|m| m.as_floats().first().is_some_and(|v| *v >= 0.0));
            if !min_ok {
                diags.push(
                    Diagnostic::warning(
                        "param-sign",
                        format!(
                            "Int parameter `{}` goes to `u32` field `{fname}` but has no `min` of 0 or more",
                            prm.name.value
                        ),
                        prm.span,
                    )
                    .with_note("give it `min: 0`, or make the field i32"),
                );
            }
        }
        fields.push(UniformField {
            name: fname,
            param: prm.name.value.clone(),
            offset: mem.offset,
            size: layouter[mem.ty].size,
            ty: tname,
        });
    }
    for prm in &pass.params {
        if !matched.contains(&prm.value.as_str()) && p.param(prm).is_some() {
            let last = prm.value.rsplit('.').next().unwrap_or(&prm.value).to_string();
            diags.push(
                Diagnostic::error(
                    "param-missing",
                    format!(
                        "parameter `{}` has no field `{}` in shader block `{}`",
                        prm.value,
                        shader_ident(&last),
                        g.name
                    ),
                    prm.span,
                )
                .with_secondary(gspan, "block declared here"),
            );
            ok = false;
        }
    }
    ok.then(|| UniformBlock {
        global: g.name.clone(),
        group: g.group,
        binding: g.binding,
        size,
        align,
        fields,
    })
}
