//! Sub-stage `types`: a resource's declared kind and format against the shader's binding
//! type: sample type and filterability from the format (and the samplers that read it),
//! view dimension, storage format and access, buffer sizes.

use super::{Ctx, Used};
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::format::{ScalarKind, TextureFormat};
use crate::ir::{shader_ident, ResourceKind, SamplerDecl, SamplerKind, TextureDesc, ViewDim};
use crate::layout::{BindingType, SampleType, ShaderDim, StorageAccess};
use crate::shader::reflect::{BindingTy, TexKind};

impl Ctx<'_> {
    pub(super) fn resource_type(&mut self, u: &Used, res_name: &str, writable: bool, diags: &mut Diagnostics) -> Option<BindingType> {
        let res = self.p.resource(res_name)?; // unknown names are reported by `declarations`
        match (&u.g.ty, &res.kind) {
            (BindingTy::Texture { kind, dim, multisampled }, ResourceKind::Texture(t)) => {
                self.used_reads.push(res_name.to_string());
                self.sampled(u, res_name, t, (*kind, *dim, *multisampled), diags)
            }
            (BindingTy::StorageTexture { format, write, read, dim }, ResourceKind::Texture(t)) => {
                // Bound, so used: a wrong access is `binding-access`, never also `unused-read`.
                self.used_reads.push(res_name.to_string());
                self.storage_texture(u, res_name, t, (*format, *write, *read, *dim), writable, diags)
            }
            (BindingTy::Storage { read_only, size }, ResourceKind::Buffer(b)) => {
                // Bound, so used: a wrong access is `binding-access`, never also `unused-read`.
                self.used_reads.push(res_name.to_string());
                let gspan = u.stage.module.global_span(u.g.handle);
                if !read_only && !writable {
                    diags.push(
                        Diagnostic::error(
                            Code::BindingAccess,
                            format!("`{}` is `read_write` but the pass lists `{res_name}` under `reads`", u.g.name),
                            gspan,
                        )
                        .with_note("list it under `writes`, or declare it `var<storage, read>`"),
                    );
                    return None;
                }
                too_small(u, res_name, b.size.value, *size, Some(b.size.span), diags)?;
                self.count(&u.stages, |c| c.storage_buffers += 1);
                Some(BindingType::Storage {
                    read_only: *read_only,
                    min_binding_size: *size,
                })
            }
            (BindingTy::Uniform { size, .. }, ResourceKind::Buffer(b)) => {
                self.used_reads.push(res_name.to_string());
                too_small(u, res_name, b.size.value, *size, None, diags)?;
                self.count(&u.stages, |c| c.uniform_buffers += 1);
                Some(BindingType::Uniform { min_binding_size: *size })
            }
            (BindingTy::AccelerationStructure, ResourceKind::AccelerationStructure) => {
                self.used_reads.push(res_name.to_string());
                if writable {
                    let msg = format!("`{res_name}` is built from the scene by the executor; no pass writes it");
                    let gspan = u.stage.module.global_span(u.g.handle);
                    diags.push(Diagnostic::error(Code::BindingAccess, msg, gspan).with_note("list it under `reads`"));
                    return None;
                }
                Some(BindingType::AccelerationStructure)
            }
            (sty, kind) => {
                mismatch(u, res_name, sty, kind, res.span, diags);
                None
            }
        }
    }

    fn sampled(
        &mut self,
        u: &Used,
        res_name: &str,
        t: &TextureDesc,
        (kind, dim, multisampled): (TexKind, ShaderDim, bool),
        diags: &mut Diagnostics,
    ) -> Option<BindingType> {
        let g = &u.g;
        let gspan = u.stage.module.global_span(g.handle);
        if multisampled {
            diags.push(Diagnostic::error(
                Code::TextureType,
                format!("`{}` is multisampled; lightbench resources are single-sampled", g.name),
                gspan,
            ));
            return None;
        }
        let f = t.format.value;
        let sample_type = match texture_kind_ok(kind, f) {
            Ok(st) => st,
            Err(why) => {
                diags.push(
                    Diagnostic::error(
                        Code::TextureType,
                        format!("`{}` is `{}` but `{res_name}` has format {}: {why}", g.name, g.type_name, f.name()),
                        gspan,
                    )
                    .with_secondary(t.format.span, "format declared here"),
                );
                return None;
            }
        };
        let samplers = self.samplers_of(&g.name);
        let sample_type = self.filterability(sample_type, f, &samplers);
        // `Layer("x", n)` binds one layer: a plain 2D texture whatever the declared view.
        let one_layer = self.pass.reads.iter().any(|r| r.layer().is_some() && r.name().value == res_name);
        let dim_check = if one_layer {
            (dim == ShaderDim::D2)
                .then_some(())
                .ok_or_else(|| "one layer is read (`Layer`): bind it as `texture_2d`".to_string())
        } else {
            dim_ok(dim, t)
        };
        if let Err(why) = dim_check {
            diags.push(
                Diagnostic::error(
                    Code::TextureType,
                    format!(
                        "`{}` is `{}` but `{res_name}` is declared with view {} and {} layer(s): {why}",
                        g.name,
                        g.type_name,
                        t.view.value.name(),
                        t.layers.value
                    ),
                    gspan,
                )
                .with_secondary(t.view.span, "view declared here"),
            );
            return None;
        }
        if let Some(d) = not_filterable(u, res_name, f, sample_type, &samplers) {
            diags.push(d);
        }
        self.count(&u.stages, |c| c.sampled_textures += 1);
        Some(BindingType::Texture {
            sample_type,
            view_dimension: dim,
            multisampled: false,
        })
    }

    /// Filterable where the format is filterable without optional features; 32-bit floats
    /// only when a filtering sampler needs it (which needs Float32Filterable); depth never.
    fn filterability(&self, st: SampleType, f: TextureFormat, samplers: &[&SamplerDecl]) -> SampleType {
        let with_filtering = samplers.iter().any(|s| s.binding_kind() == SamplerKind::Filtering);
        match st {
            SampleType::Float { .. } if f.is_depth() => SampleType::Float { filterable: false },
            SampleType::Float { .. } if f.is_32bit_float() => SampleType::Float {
                filterable: with_filtering && f.filterable(self.profile),
            },
            SampleType::Float { .. } => SampleType::Float {
                filterable: f.filterable(self.profile),
            },
            s => s,
        }
    }

    /// The declared samplers a texture global is sampled with.
    fn samplers_of(&self, texture: &str) -> Vec<&SamplerDecl> {
        let explicit = &self.explicit;
        self.sampled_with
            .iter()
            .filter(|(img, _)| img == texture)
            .filter_map(|(_, smp)| {
                self.p
                    .samplers
                    .iter()
                    .find(|s| shader_ident(&s.name) == *smp || explicit.get(smp.as_str()).is_some_and(|t| t.value == s.name.value))
            })
            .collect()
    }

    fn storage_texture(
        &mut self,
        u: &Used,
        res_name: &str,
        t: &TextureDesc,
        (format, w, r, dim): (naga::StorageFormat, bool, bool, ShaderDim),
        writable: bool,
        diags: &mut Diagnostics,
    ) -> Option<BindingType> {
        let g = &u.g;
        let gspan = u.stage.module.global_span(g.handle);
        let f = t.format.value;
        if storage_format(format) != Some(f) {
            diags.push(
                Diagnostic::error(
                    Code::TextureType,
                    format!(
                        "storage texture `{}` has format `{}` but `{res_name}` is {}",
                        g.name,
                        g.type_name,
                        f.name()
                    ),
                    gspan,
                )
                .with_secondary(t.format.span, "format declared here"),
            );
            return None;
        }
        if !f.storage() {
            diags.push(Diagnostic::error(
                Code::TextureType,
                format!("{} cannot be a storage texture", f.name()),
                t.format.span,
            ));
            return None;
        }
        if w && !writable {
            diags.push(
                Diagnostic::error(
                    Code::BindingAccess,
                    format!(
                        "`{}` is written by the shader but the pass lists `{res_name}` under `reads`",
                        g.name
                    ),
                    gspan,
                )
                .with_note("list it under `writes`"),
            );
            return None;
        }
        if let Err(why) = dim_ok(dim, t) {
            diags.push(
                Diagnostic::error(Code::TextureType, format!("`{}` is `{}`: {why}", g.name, g.type_name), gspan)
                    .with_secondary(t.view.span, "view declared here"),
            );
            return None;
        }
        self.count(&u.stages, |c| c.storage_textures += 1);
        let access = match (r, w) {
            (true, true) => StorageAccess::ReadWrite,
            (true, false) => StorageAccess::ReadOnly,
            _ => StorageAccess::WriteOnly,
        };
        Some(BindingType::StorageTexture {
            format: f,
            access,
            view_dimension: dim,
        })
    }
}

/// A filtering sampler on a non-filterable format is invalid in wgpu.
fn not_filterable(u: &Used, res_name: &str, f: TextureFormat, st: SampleType, samplers: &[&SamplerDecl]) -> Option<Diagnostic> {
    if st != (SampleType::Float { filterable: false }) {
        return None;
    }
    let decl = samplers.iter().find(|s| s.binding_kind() == SamplerKind::Filtering)?;
    Some(
        Diagnostic::error(
            Code::NotFilterable,
            format!(
                "`{}` ({res_name}) is sampled with filtering sampler `{}`, but {} is not filterable{}",
                u.g.name,
                decl.name.value,
                f.name(),
                if f.is_32bit_float() {
                    " without the Float32Filterable feature"
                } else {
                    ""
                }
            ),
            u.stage.module.global_span(u.g.handle),
        )
        .with_secondary(decl.span, "filtering sampler declared here")
        .with_note("use a sampler with `filter: Nearest, mipmap: Nearest`, or `textureLoad`"),
    )
}

fn too_small(u: &Used, res_name: &str, have: u64, need: u32, decl: Option<crate::span::Span>, diags: &mut Diagnostics) -> Option<()> {
    if have >= need as u64 {
        return Some(());
    }
    let mut d = Diagnostic::error(
        Code::BufferTooSmall,
        format!("`{}` needs at least {need} bytes but `{res_name}` has {have}", u.g.name),
        u.stage.module.global_span(u.g.handle),
    );
    if let Some(s) = decl {
        d = d.with_secondary(s, "size declared here");
    }
    diags.push(d);
    None
}

fn mismatch(u: &Used, res_name: &str, sty: &BindingTy, kind: &ResourceKind, decl_span: crate::span::Span, diags: &mut Diagnostics) {
    let (what, decl) = match kind {
        ResourceKind::Texture(t) => (format!("a {} texture", t.format.value.name()), t.format.span),
        ResourceKind::Buffer(_) => ("a buffer".to_string(), decl_span),
        ResourceKind::AccelerationStructure => ("an acceleration structure".to_string(), decl_span),
    };
    let shader_what = match sty {
        BindingTy::Texture { .. } => "a sampled texture",
        BindingTy::StorageTexture { .. } => "a storage texture",
        BindingTy::Storage { .. } => "a storage buffer",
        BindingTy::Uniform { .. } => "a uniform buffer",
        BindingTy::AccelerationStructure => "an `acceleration_structure`",
        BindingTy::Sampler { .. } => "a sampler",
        BindingTy::Unsupported => {
            // Not a mismatch: no resource could be bound there.
            let d = Diagnostic::error(
                Code::BindingType,
                format!("`{}` is a `{}`, which lightbench does not bind", u.g.name, u.g.type_name),
                u.stage.module.global_span(u.g.handle),
            )
            .with_note("binding arrays and external textures are not supported: declare one global per texture or buffer");
            return diags.push(d);
        }
    };
    diags.push(
        Diagnostic::error(
            Code::BindingType,
            format!("`{}` is {shader_what} (`{}`) but `{res_name}` is {what}", u.g.name, u.g.type_name),
            u.stage.module.global_span(u.g.handle),
        )
        .with_secondary(decl, "declared here"),
    );
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

/// The declared format a WGSL storage format names.
fn storage_format(f: naga::StorageFormat) -> Option<TextureFormat> {
    use naga::StorageFormat as S;
    use TextureFormat as T;
    Some(match f {
        S::Rgba8Unorm => T::Rgba8Unorm,
        S::Rgba16Float => T::Rgba16Float,
        S::R32Float => T::R32Float,
        S::Rg32Float => T::Rg32Float,
        S::Rgba32Float => T::Rgba32Float,
        S::R32Uint => T::R32Uint,
        S::Rg32Uint => T::Rg32Uint,
        S::Rgba32Uint => T::Rgba32Uint,
        S::R32Sint => T::R32Sint,
        S::Rgba16Uint => T::Rgba16Uint,
        _ => return None,
    })
}
