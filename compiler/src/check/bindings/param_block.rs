//! Sub-stage `param-block`: the shader struct behind the parameter block against the pass's
//! parameters. Offsets come from the struct as naga laid it out, so the runtime writes
//! values there with no Rust struct per pass.

use super::{Ctx, Used};
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::{shader_ident, ParamType, ParamValue};
use crate::layout::{FieldSource, FieldType, ParamId, UniformBlock, UniformField};
use crate::shader::reflect;
use crate::span::Spanned;

/// The field types a parameter type can be written to.
fn fits(ty: &ParamType, f: FieldType) -> bool {
    use FieldType as F;
    match ty {
        ParamType::Float => f == F::F32,
        ParamType::Int => matches!(f, F::I32 | F::U32),
        ParamType::Bool | ParamType::Enum(_) => f == F::U32,
        ParamType::Vec2 => f == F::Vec2F32,
        ParamType::Vec3 => f == F::Vec3F32,
        ParamType::Vec4 => f == F::Vec4F32,
        ParamType::Color => matches!(f, F::Vec3F32 | F::Vec4F32),
    }
}

fn wanted(ty: &ParamType) -> &'static str {
    match ty {
        ParamType::Float => "f32",
        ParamType::Int => "i32 or u32",
        ParamType::Bool => "u32 (WGSL bool is not host-shareable)",
        ParamType::Enum(_) => "u32 (the option index)",
        ParamType::Vec2 => "vec2<f32>",
        ParamType::Vec3 => "vec3<f32>",
        ParamType::Vec4 => "vec4<f32>",
        ParamType::Color => "vec3<f32> or vec4<f32>",
    }
}

/// A per-pass value as the 32-bit words of a field of type `f`, or why it does not fit.
fn value_words(v: &ParamValue, f: FieldType) -> Result<Vec<u32>, String> {
    use FieldType as F;
    let whole = |x: f64, lo: f64, hi: f64| x.fract() == 0.0 && x >= lo && x <= hi;
    match (v, f) {
        (ParamValue::Float(x), F::F32) => Ok(vec![(*x as f32).to_bits()]),
        (ParamValue::Float(x), F::I32) if whole(*x, i32::MIN as f64, i32::MAX as f64) => Ok(vec![(*x as i32) as u32]),
        (ParamValue::Float(x), F::U32) if whole(*x, 0.0, u32::MAX as f64) => Ok(vec![*x as u32]),
        (ParamValue::Float(x), F::I32 | F::U32) => Err(format!("`{x}` is not a whole number that fits `{}`", f.wgsl())),
        (ParamValue::Bool(b), F::U32) => Ok(vec![*b as u32]),
        (ParamValue::Vec(c), _) if c.len() == f.components() && f.components() > 1 => Ok(c.iter().map(|x| (*x as f32).to_bits()).collect()),
        (v, f) => Err(format!("{} does not fit `{}`", v.describe(), f.wgsl())),
    }
}

impl Ctx<'_> {
    /// The pass parameter a block field is named after: its full identifier first, else
    /// its last segment.
    fn param_for_field(&self, field: &str) -> Option<&Spanned<String>> {
        let params = &self.pass.params;
        params.iter().find(|prm| shader_ident(prm) == field).or_else(|| {
            params
                .iter()
                .find(|prm| shader_ident(prm.value.rsplit('.').next().unwrap_or(&prm.value)) == field)
        })
    }

    /// A block field fixed by the pass's `values`: its words, or `None` after reporting.
    fn fixed_field(
        &self,
        u: &Used,
        mem: &naga::StructMember,
        key: &Spanned<String>,
        v: &Spanned<ParamValue>,
        diags: &mut Diagnostics,
    ) -> Option<UniformField> {
        let module = &u.stage.module;
        let tname = reflect::type_name(&module.module, mem.ty);
        let words = FieldType::from_wgsl(&tname)
            .ok_or_else(|| format!("field type `{tname}` cannot hold a per-pass value"))
            .and_then(|ty| value_words(&v.value, ty).map(|w| (ty, w)));
        match words {
            Ok((ty, words)) => Some(UniformField {
                name: key.value.clone(),
                source: FieldSource::Fixed(words),
                offset: mem.offset,
                size: module.layouter[mem.ty].size,
                ty,
            }),
            Err(why) => {
                diags.push(
                    Diagnostic::error(Code::ValueType, format!("value for `{}`: {why}", key.value), v.span)
                        .with_secondary(module.global_span(u.g.handle), format!("`{}.{}` is `{tname}`", u.g.name, key.value)),
                );
                None
            }
        }
    }

    /// Per-pass values naming no field of the block; `false` if any.
    fn unmatched_values(&self, u: &Used, members: &[naga::StructMember], diags: &mut Diagnostics) -> bool {
        let names: Vec<&str> = members.iter().filter_map(|m| m.name.as_deref()).collect();
        let mut ok = true;
        for (k, _) in &self.pass.values {
            if !names.contains(&k.value.as_str()) {
                let mut d = Diagnostic::error(
                    Code::ValueField,
                    format!("parameter block `{}` has no field `{}`", u.g.name, k.value),
                    k.span,
                )
                .with_secondary(u.stage.module.global_span(u.g.handle), "block declared here");
                if let Some(s) = crate::diag::did_you_mean(&k.value, names.iter().copied()) {
                    d = d.with_note(format!("did you mean `{s}`?"));
                }
                diags.push(d);
                ok = false;
            }
        }
        ok
    }

    pub(super) fn param_block(
        &mut self,
        u: &Used,
        ty: naga::Handle<naga::Type>,
        size: u32,
        diags: &mut Diagnostics,
    ) -> Option<UniformBlock> {
        let (g, module) = (&u.g, &u.stage.module);
        let gspan = module.global_span(g.handle);
        let naga::TypeInner::Struct { members, .. } = &module.module.types[ty].inner else {
            diags.push(Diagnostic::error(
                Code::ParamBlock,
                format!("parameter block `{}` must be a struct", g.name),
                gspan,
            ));
            return None;
        };
        let mut fields = vec![];
        let mut matched: Vec<&str> = vec![];
        let mut ok = true;
        for mem in members {
            let fname = mem.name.clone().unwrap_or_default();
            if let Some((k, v)) = self.pass.values.iter().find(|(k, _)| k.value == fname) {
                match self.fixed_field(u, mem, k, v, diags) {
                    Some(f) => fields.push(f),
                    None => ok = false,
                }
                continue;
            }
            let Some(param_ref) = self.param_for_field(&fname) else {
                if fname.starts_with('_') {
                    continue; // explicit padding
                }
                diags.push(
                    Diagnostic::error(
                        Code::ParamMissing,
                        format!(
                            "field `{fname}` of parameter block `{}` has no parameter in pass `{}`",
                            g.name, self.pass.name.value
                        ),
                        gspan,
                    )
                    .with_secondary(self.pass.name.span, "pass declared here")
                    .with_note(
                        "list the parameter under the pass's `params`, set it under `values`, or name padding fields with a leading `_`",
                    ),
                );
                ok = false;
                continue;
            };
            matched.push(&param_ref.value);
            match self.field(u, mem, &fname, param_ref, diags) {
                Some(Some(f)) => fields.push(f),
                Some(None) => {}
                None => ok = false,
            }
        }
        ok &= self.unmatched_params(u, &matched, diags);
        ok &= self.unmatched_values(u, members, diags);
        ok.then(|| UniformBlock {
            global: g.name.clone(),
            group: g.group,
            binding: g.binding,
            size,
            align: module.layouter[ty].alignment.round_up(1),
            fields,
        })
    }

    /// One block field against its parameter: `None` on a type error, `Some(None)` when the
    /// parameter is undeclared (reported by `declarations`).
    fn field(
        &self,
        u: &Used,
        mem: &naga::StructMember,
        fname: &str,
        param_ref: &Spanned<String>,
        diags: &mut Diagnostics,
    ) -> Option<Option<UniformField>> {
        let (p, module) = (self.p, &u.stage.module);
        let Some(idx) = p.params.iter().position(|q| q.name.value == param_ref.value) else {
            return Some(None);
        };
        let prm = &p.params[idx];
        let tname = reflect::type_name(&module.module, mem.ty);
        let field_ty = FieldType::from_wgsl(&tname).filter(|f| fits(&prm.ty.value, *f));
        let Some(field_ty) = field_ty else {
            diags.push(
                Diagnostic::error(
                    Code::ParamTypeMismatch,
                    format!(
                        "parameter `{}` is {} but shader field `{fname}` is `{tname}`",
                        prm.name.value,
                        prm.ty.name()
                    ),
                    param_ref.span,
                )
                .with_secondary(
                    module.global_span(u.g.handle),
                    format!("`{}.{fname}` declared in this block", u.g.name),
                )
                .with_secondary(prm.ty.span, "parameter type declared here")
                .with_note(format!("a {} parameter needs a `{}` field", prm.ty.name(), wanted(&prm.ty.value))),
            );
            return None;
        };
        if prm.ty.value == ParamType::Int && field_ty == FieldType::U32 {
            let min_ok = prm.min.as_ref().is_some_and(|m| m.as_floats().first().is_some_and(|v| *v >= 0.0));
            if !min_ok {
                diags.push(
                    Diagnostic::warning(
                        Code::ParamSign,
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
        Some(Some(UniformField {
            name: fname.to_string(),
            source: FieldSource::Param(ParamId(idx as u32)),
            offset: mem.offset,
            size: module.layouter[mem.ty].size,
            ty: field_ty,
        }))
    }

    /// Parameters of the pass with no field in the block; `false` if any.
    fn unmatched_params(&self, u: &Used, matched: &[&str], diags: &mut Diagnostics) -> bool {
        let mut ok = true;
        for prm in &self.pass.params {
            if !matched.contains(&prm.value.as_str()) && self.p.param(prm).is_some() {
                let last = shader_ident(prm.value.rsplit('.').next().unwrap_or(&prm.value));
                let taken = self.param_for_field(&last).filter(|other| other.value != prm.value);
                let mut d = Diagnostic::error(
                    Code::ParamMissing,
                    format!("parameter `{}` has no field `{last}` in shader block `{}`", prm.value, u.g.name),
                    prm.span,
                )
                .with_secondary(u.stage.module.global_span(u.g.handle), "block declared here");
                if let Some(other) = taken {
                    d = Diagnostic::error(
                        Code::ParamMissing,
                        format!(
                            "parameter `{}` has no field in shader block `{}`: field `{last}` is taken by parameter `{}` (same last segment)",
                            prm.value, u.g.name, other.value
                        ),
                        prm.span,
                    )
                    .with_secondary(other.span, format!("`{}` took field `{last}`", other.value))
                    .with_secondary(u.stage.module.global_span(u.g.handle), "block declared here")
                    .with_note(format!(
                        "name a field after the full parameter (`{}`) to bind it, or fix the field per pass with `values`",
                        shader_ident(prm)
                    ));
                }
                diags.push(d);
                ok = false;
            }
        }
        ok
    }
}
