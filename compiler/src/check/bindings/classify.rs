//! Sub-stage `classify`: what each used global binds to, in this order: the pass's parameter
//! block, a standard runtime block, a per-draw slot, a declared sampler, a declared resource.

use super::{Ctx, Used};
use crate::diag::{did_you_mean, Code, Diagnostic, Diagnostics};
use crate::ir::{history_ident, shader_ident, PassKind, SamplerKind};
use crate::layout::{
    BindSource, BindingType, DrawSlot, SampleType, ShaderDim, AREA_LIGHTS, FRAME, HIT_CORNERS, HIT_EMITTERS, HIT_MAPS, HIT_MATERIALS,
    HIT_TRIANGLES, INSTANCE, LIGHTS, LIGHT_VOLUMES, TRIANGLES,
};
use crate::shader::reflect::{BindingTy, TexKind};

/// The standard blocks and buffers, bound by their global's name: the two uniform blocks,
/// the read-only storage buffers (`STORAGE`), then the per-triangle tables (`TABLES`).
const STANDARD: [&str; 11] = [
    FRAME,
    INSTANCE,
    LIGHTS,
    LIGHT_VOLUMES,
    AREA_LIGHTS,
    HIT_MATERIALS,
    TRIANGLES,
    HIT_TRIANGLES,
    HIT_EMITTERS,
    HIT_CORNERS,
    HIT_MAPS,
];
const STORAGE: &[&str] = STANDARD.split_at(2).1.split_at(4).0;
/// Per-triangle records as the texels of a `texture_2d_array<u32>` (`shaders/lib/table.wgsl`):
/// a texture holds what a storage binding's size limit would cut off.
const TABLES: &[&str] = STANDARD.split_at(6).1;

impl Ctx<'_> {
    pub(super) fn bind(&mut self, u: &Used, diags: &mut Diagnostics) {
        let target: Option<&str> = self.explicit.get(u.g.name.as_str()).map(|s| s.value.as_str());
        if target == Some("params") || (target.is_none() && u.g.name == self.pass.param_block.value) {
            return self.bind_params(u, diags);
        }
        if target.is_none() && STANDARD.contains(&u.g.name.as_str()) {
            return self.bind_standard(u, diags);
        }
        if let (None, Some(slot)) = (target, DrawSlot::from_name(&u.g.name)) {
            return self.bind_draw(u, slot, diags);
        }
        if let BindingTy::Sampler { comparison } = u.g.ty {
            return self.bind_sampler(u, target, comparison, diags);
        }
        self.bind_resource(u, target, diags);
    }

    fn bind_params(&mut self, u: &Used, diags: &mut Diagnostics) {
        self.params_used = true;
        let g = &u.g;
        match &g.ty {
            BindingTy::Uniform { ty, size } => {
                if let Some(block) = self.param_block(u, *ty, *size, diags) {
                    self.uniform_blocks.push(block);
                }
                self.push(g, BindSource::Params, BindingType::Uniform { min_binding_size: *size }, &u.stages);
            }
            _ => diags.push(Diagnostic::error(
                Code::BindingType,
                format!("parameter block `{}` must be `var<uniform>`", g.name),
                u.stage.module.global_span(g.handle),
            )),
        }
    }

    fn bind_standard(&mut self, u: &Used, diags: &mut Diagnostics) {
        let g = &u.g;
        let (source, ty) = match (&g.ty, g.name.as_str()) {
            (BindingTy::Uniform { size, .. }, FRAME) => (BindSource::Frame, BindingType::Uniform { min_binding_size: *size }),
            (BindingTy::Uniform { size, .. }, INSTANCE) => (BindSource::Instance, BindingType::Uniform { min_binding_size: *size }),
            (BindingTy::Storage { read_only: true, size }, name) if STORAGE.contains(&name) => (
                match name {
                    LIGHTS => BindSource::Lights,
                    AREA_LIGHTS => BindSource::AreaLights,
                    HIT_MATERIALS => BindSource::HitMaterials,
                    _ => BindSource::LightVolumes,
                },
                BindingType::Storage {
                    read_only: true,
                    min_binding_size: *size,
                },
            ),
            (
                BindingTy::Texture {
                    kind: TexKind::Uint,
                    dim: ShaderDim::D2Array,
                    multisampled: false,
                },
                name,
            ) if TABLES.contains(&name) => {
                let source = match name {
                    TRIANGLES => BindSource::Triangles,
                    HIT_TRIANGLES => BindSource::HitTriangles,
                    HIT_EMITTERS => BindSource::HitEmitters,
                    HIT_CORNERS => BindSource::HitCorners,
                    _ => BindSource::HitMaps,
                };
                let ty = BindingType::Texture {
                    sample_type: SampleType::Uint,
                    view_dimension: ShaderDim::D2Array,
                    multisampled: false,
                };
                (source, ty)
            }
            (_, name) => {
                let want = match name {
                    _ if STORAGE.contains(&name) => "`var<storage, read>`",
                    _ if TABLES.contains(&name) => "a `texture_2d_array<u32>`, a table of texels (`shaders/lib/table.wgsl`)",
                    _ => "`var<uniform>`",
                };
                let what = match name {
                    LIGHTS => "the light array",
                    TRIANGLES => "the scene's triangle array",
                    LIGHT_VOLUMES => "the light-volume meshes",
                    AREA_LIGHTS => "the area-light array",
                    HIT_TRIANGLES => "the traced triangles' hit data",
                    HIT_MATERIALS => "the traced meshes' materials",
                    HIT_EMITTERS => "the traced emitters",
                    HIT_CORNERS => "the traced triangles' texture coordinates",
                    HIT_MAPS => "the scene's maps for ray hits",
                    _ => "standard block",
                };
                diags.push(Diagnostic::error(
                    Code::BindingType,
                    format!("{what} `{name}` must be {want}"),
                    u.stage.module.global_span(g.handle),
                ));
                return;
            }
        };
        self.push(g, source, ty, &u.stages);
    }

    fn bind_draw(&mut self, u: &Used, slot: DrawSlot, diags: &mut Diagnostics) {
        let g = &u.g;
        let gspan = u.stage.module.global_span(g.handle);
        if !matches!(&self.pass.kind, PassKind::Raster(r) if r.draw.uses_scene()) {
            diags.push(
                Diagnostic::error(
                    Code::BindingUnsatisfied,
                    format!("per-draw binding `{}` is only provided to `draw: Scene` raster passes", g.name),
                    gspan,
                )
                .with_secondary(self.pass.name.span, "in this pass"),
            );
            return;
        }
        let ty = match (&g.ty, slot) {
            (BindingTy::Uniform { size, .. }, DrawSlot::Mesh | DrawSlot::Material) => BindingType::Uniform { min_binding_size: *size },
            (BindingTy::Sampler { comparison: false }, DrawSlot::MaterialSampler) => BindingType::Sampler(SamplerKind::Filtering),
            (
                BindingTy::Texture {
                    kind: TexKind::Float,
                    dim: ShaderDim::D2,
                    multisampled: false,
                },
                DrawSlot::BaseColorMap
                | DrawSlot::NormalMap
                | DrawSlot::MetallicRoughnessMap
                | DrawSlot::EmissiveMap
                | DrawSlot::OcclusionMap,
            ) => BindingType::Texture {
                sample_type: SampleType::Float { filterable: true },
                view_dimension: ShaderDim::D2,
                multisampled: false,
            },
            _ => {
                diags.push(Diagnostic::error(
                    Code::BindingType,
                    format!(
                        "per-draw binding `{}` has type `{}`; see docs/pipelines.md \"Standard bindings\"",
                        g.name, g.type_name
                    ),
                    gspan,
                ));
                return;
            }
        };
        self.push(g, BindSource::Draw(slot), ty, &u.stages);
    }

    fn bind_sampler(&mut self, u: &Used, target: Option<&str>, comparison: bool, diags: &mut Diagnostics) {
        let (p, g) = (self.p, &u.g);
        let gspan = u.stage.module.global_span(g.handle);
        let decl = match target {
            Some(t) => p.sampler(t),
            None => p.samplers.iter().find(|s| shader_ident(&s.name) == g.name),
        };
        let Some(decl) = decl else {
            let names: Vec<String> = p.samplers.iter().map(|s| shader_ident(&s.name)).collect();
            let mut d = Diagnostic::error(
                Code::BindingUnsatisfied,
                format!(
                    "sampler `{}` (@group({}) @binding({})) matches no declared sampler",
                    g.name, g.group, g.binding
                ),
                gspan,
            )
            .with_secondary(self.pass.name.span, "used by this pass");
            if let Some(s) = did_you_mean(&g.name, names.iter().map(|s| s.as_str())) {
                d = d.with_note(format!("did you mean `{s}`?"));
            }
            diags.push(d.with_note("declare it under `samplers: { ... }` in the pipeline"));
            return;
        };
        let kind = decl.binding_kind();
        if comparison != (kind == SamplerKind::Comparison) {
            let msg = if comparison {
                format!(
                    "`{}` is a `sampler_comparison` but sampler `{}` has no `compare`",
                    g.name, decl.name.value
                )
            } else {
                format!(
                    "`{}` is a plain `sampler` but sampler `{}` is a comparison sampler",
                    g.name, decl.name.value
                )
            };
            diags.push(Diagnostic::error(Code::SamplerType, msg, gspan).with_secondary(decl.span, "declared here"));
            return;
        }
        self.count(&u.stages, |c| c.samplers += 1);
        self.push(
            g,
            BindSource::Sampler(decl.name.value.clone()),
            BindingType::Sampler(kind),
            &u.stages,
        );
    }

    /// A declared read (current or previous frame) or storage write.
    fn bind_resource(&mut self, u: &Used, target: Option<&str>, diags: &mut Diagnostics) {
        let (pass, g) = (self.pass, &u.g);
        let read = pass.reads.iter().find(|r| match target {
            Some(t) => r.name().value == t,
            None if r.is_prev() => history_ident(r.name()) == g.name,
            None => shader_ident(r.name()) == g.name,
        });
        let write = pass.writes.iter().find(|w| match target {
            Some(t) => w.value == t,
            None => shader_ident(w) == g.name,
        });
        let (res_name, prev, writable) = match (read, write) {
            (_, Some(w)) => (w.value.clone(), false, true),
            (Some(r), None) => (r.name().value.clone(), r.is_prev(), false),
            (None, None) => return self.unsatisfied(u, diags),
        };
        let Some(ty) = self.resource_type(u, &res_name, writable, diags) else {
            return;
        };
        let source = if prev {
            BindSource::Prev(res_name)
        } else {
            BindSource::Resource(res_name)
        };
        self.push(g, source, ty, &u.stages);
    }

    fn unsatisfied(&mut self, u: &Used, diags: &mut Diagnostics) {
        let (p, g) = (self.p, &u.g);
        let decl = p
            .resources
            .iter()
            .find(|r| shader_ident(&r.name) == g.name || history_ident(&r.name) == g.name);
        let d = Diagnostic::error(
            Code::BindingUnsatisfied,
            format!(
                "shader global `{}` (@group({}) @binding({})) is not bound by pass `{}`",
                g.name, g.group, g.binding, self.pass.name.value
            ),
            u.stage.module.global_span(g.handle),
        )
        .with_label_text("used by the pass's entry points")
        .with_secondary(self.pass.name.span, "pass declared here");
        let pass = self.pass;
        let attached =
            |name: &str| pass.color().iter().any(|c| c.resource.value == name) || pass.depth().is_some_and(|d| d.resource.value == name);
        let d = match decl {
            Some(r) if attached(&r.name.value) => d.with_note(format!(
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
    }
}
