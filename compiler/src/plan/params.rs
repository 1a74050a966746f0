//! Parameter values: the pipeline's defaults, overrides checked against each parameter's
//! type and range, and packing into a pass's parameter block at the offsets the Plan gives
//! (so the runtime writes bytes, not per-type logic).

use super::PlanParam;
use crate::diag::did_you_mean;
use crate::ir::{out_of_range, Param, ParamType, ParamValue, Pipeline};
use crate::layout::{FieldSource, FieldType, ParamId, UniformBlock};
use std::collections::BTreeMap;

/// A parameter as declared: its own default, sizing nothing yet.
pub fn declared_param(p: &Param) -> PlanParam {
    PlanParam {
        name: p.name.value.clone(),
        ty: p.ty.value.clone(),
        default: p.default.value.clone(),
        min: p.min.as_ref().map(|m| m.value.clone()),
        max: p.max.as_ref().map(|m| m.value.clone()),
        doc: p.doc.clone(),
        preset: None,
        sizes: None,
        pass: None,
    }
}

/// A parameter as this configuration has it: `default` is the chosen preset's value where
/// one sets it; `sizes` the value resources were sized with.
pub fn plan_param(p: &Param, pipeline: &crate::ir::Pipeline, cfg: &super::Config) -> PlanParam {
    let sizes = sizing(pipeline).contains(p.name.value.as_str());
    plan_param_with(p, sizes, cfg.default_of(pipeline, p), cfg)
}

/// Every parameter of the pipeline as `plan_param` plans it, the facts they share (what
/// sizes, what the chosen options preset) worked out once.
pub(super) fn plan_params(pipeline: &crate::ir::Pipeline, cfg: &super::Config) -> Vec<PlanParam> {
    let sizing = sizing(pipeline);
    let mut presets: BTreeMap<&str, (ParamValue, Option<String>)> = Default::default();
    // As `Config::default_of`: the first variant (in declaration order) whose chosen option
    // sets the parameter to a valid value.
    for v in &pipeline.variants {
        let Some(o) = cfg.selection.chosen.get(&v.name.value).and_then(|o| v.option(o)) else {
            continue;
        };
        for (k, lit) in &o.params {
            if presets.contains_key(k.value.as_str()) {
                continue;
            }
            if let Some(value) = crate::check::declarations::preset_value(pipeline, &k.value, &lit.value) {
                presets.insert(&k.value, (value, Some(format!("{}={}", v.name.value, o.name.value))));
            }
        }
    }
    pipeline
        .params
        .iter()
        .map(|prm| {
            let name = prm.name.value.as_str();
            let default = presets.get(name).cloned().unwrap_or_else(|| (prm.default.value.clone(), None));
            plan_param_with(prm, sizing.contains(name), default, cfg)
        })
        .collect()
}

/// The parameters whose values the Plan fixes: those sizing a resource or repeating a
/// pass, and those a shader constant is baked from.
fn sizing(pipeline: &crate::ir::Pipeline) -> std::collections::BTreeSet<&str> {
    let sizes = pipeline
        .resources
        .iter()
        .filter_map(|r| r.texture())
        .filter_map(|t| t.size.value.param());
    let repeats = pipeline
        .passes
        .iter()
        .filter_map(|pass| match pass.repeat.as_ref().map(|r| &r.value) {
            Some(crate::ir::Repeat::Param(n)) => Some(n.as_str()),
            _ => None,
        });
    let constants = pipeline
        .passes
        .iter()
        .flat_map(|pass| &pass.constants)
        .filter_map(|(_, c)| match &c.value {
            crate::ir::Constant::Param(n) => Some(n.as_str()),
            _ => None,
        });
    sizes.chain(repeats).chain(constants).collect()
}

fn plan_param_with(p: &Param, sizes: bool, (default, preset): (ParamValue, Option<String>), cfg: &super::Config) -> PlanParam {
    PlanParam {
        sizes: sizes.then(|| cfg.params.get(&p.name.value).unwrap_or(&default).clone()),
        default,
        preset,
        ..declared_param(p)
    }
}

/// Stage `pass-values`: each per-pass value becomes a parameter named `PASS.KEY`, typed by
/// the block field it fills and defaulting to the pipeline's value, so `--param`, sweeps
/// and diff sides set a post pass's strength like any parameter. A name a declared
/// parameter already has stays a fixed value (`check` reports the clash).
pub fn lift_pass_values(
    pipeline: &Pipeline,
    chosen: &std::collections::BTreeMap<String, String>,
    passes: &mut [super::PlanPass],
    params: &mut Vec<PlanParam>,
) {
    for pp in passes {
        let Some((_, pass)) = pipeline.pass_chosen(&pp.name, chosen) else {
            continue;
        };
        for f in pp.uniform_blocks.iter_mut().flat_map(|b| b.fields.iter_mut()) {
            let FieldSource::Fixed(_) = f.source else { continue };
            let Some((_, v)) = pass.values.iter().find(|(k, _)| k.value == f.name) else {
                continue;
            };
            let name = format!("{}.{}", pp.name, f.name);
            let id = match params.iter().position(|p| p.name == name) {
                Some(i) if params[i].pass.as_deref() == Some(pp.name.as_str()) => i,
                Some(_) => continue,
                None => {
                    params.push(pass_value_param(&name, &pp.name, &v.value, f.ty));
                    params.len() - 1
                }
            };
            f.source = FieldSource::Param(ParamId(id as u32));
        }
    }
}

/// The per-pass values of a checked pipeline as parameters (every version's fields), for
/// checking `--param PASS.KEY=VALUE` without a scene.
pub fn pass_value_params(checked: &crate::check::Checked) -> Vec<PlanParam> {
    let mut out: Vec<PlanParam> = vec![];
    for (pass, versions) in checked.pipeline.passes.iter().zip(&checked.versions) {
        let fields = versions
            .iter()
            .flat_map(|v| v.resolved.uniform_blocks.iter())
            .flat_map(|b| b.fields.iter());
        for f in fields {
            let Some((_, v)) = pass.values.iter().find(|(k, _)| k.value == f.name) else {
                continue;
            };
            let name = format!("{}.{}", pass.name.value, f.name);
            if !out.iter().any(|p| p.name == name) {
                out.push(pass_value_param(&name, &pass.name.value, &v.value, f.ty));
            }
        }
    }
    out
}

/// A per-pass value as a parameter of the type its field holds: whole numbers as Int
/// within the field's range, a 0/1 `u32` written as a bool as Bool.
fn pass_value_param(name: &str, pass: &str, v: &ParamValue, field: FieldType) -> PlanParam {
    use FieldType as F;
    let int = |x: f64, lo: i64, hi: i64| {
        (
            ParamType::Int,
            ParamValue::Int(x as i64),
            Some(ParamValue::Int(lo)),
            Some(ParamValue::Int(hi)),
        )
    };
    let (ty, default, min, max) = match (field, v) {
        (F::U32, ParamValue::Bool(b)) => (ParamType::Bool, ParamValue::Bool(*b), None, None),
        (F::I32, ParamValue::Float(x)) => int(*x, i32::MIN as i64, i32::MAX as i64),
        (F::U32, ParamValue::Float(x)) => int(*x, 0, u32::MAX as i64),
        (F::Vec2F32, _) => (ParamType::Vec2, v.clone(), None, None),
        (F::Vec3F32, _) => (ParamType::Vec3, v.clone(), None, None),
        (F::Vec4F32, _) => (ParamType::Vec4, v.clone(), None, None),
        _ => (ParamType::Float, v.clone(), None, None),
    };
    PlanParam {
        name: name.to_string(),
        ty,
        default,
        min,
        max,
        doc: Some(format!("per-pass value of pass `{pass}`")),
        preset: None,
        sizes: None,
        pass: Some(pass.to_string()),
    }
}

/// Why an override cannot be applied.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ParamError {
    Unknown { name: String, suggestion: Option<String> },
    Type { name: String, why: String },
    Range { name: String, why: String },
}

impl std::fmt::Display for ParamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParamError::Unknown { name, suggestion: Some(s) } => write!(f, "no parameter `{name}`; did you mean `{s}`?"),
            ParamError::Unknown { name, suggestion: None } => write!(f, "no parameter `{name}`"),
            ParamError::Type { name, why } | ParamError::Range { name, why } => write!(f, "parameter `{name}`: {why}"),
        }
    }
}

impl std::error::Error for ParamError {}

/// The parameter a name refers to, or `Unknown` with the nearest name as a suggestion.
fn find<'a>(params: &'a [PlanParam], name: &str) -> Result<&'a PlanParam, ParamError> {
    params.iter().find(|p| p.name == name).ok_or_else(|| ParamError::Unknown {
        name: name.to_string(),
        suggestion: did_you_mean(name, params.iter().map(|p| p.name.as_str())).map(str::to_string),
    })
}

/// Parameter overrides by name; every parameter without one has its default.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParamValues {
    values: BTreeMap<String, ParamValue>,
}

impl ParamValues {
    pub fn new() -> Self {
        Self::default()
    }

    /// Check a value against the parameter it names: it exists, has its type, lies in its range.
    pub fn check(params: &[PlanParam], name: &str, value: &ParamValue) -> Result<(), ParamError> {
        let p = find(params, name)?;
        p.ty.accepts(value).map_err(|why| ParamError::Type {
            name: name.to_string(),
            why,
        })?;
        if value.as_floats().iter().any(|x| !x.is_finite()) {
            return Err(ParamError::Range {
                name: name.to_string(),
                why: "the value is not finite".into(),
            });
        }
        if let Some((bound, b)) = out_of_range(value, p.min.as_ref(), p.max.as_ref()) {
            let side = if bound == "min" { "below its min" } else { "above its max" };
            return Err(ParamError::Range {
                name: name.to_string(),
                why: format!("{} is {side} {}", value.describe(), b.describe()),
            });
        }
        Ok(())
    }

    /// A value written as text (a command line's `--param`), parsed by the type of the
    /// parameter it names and checked against its range.
    pub fn parse_text(params: &[PlanParam], name: &str, text: &str) -> Result<ParamValue, ParamError> {
        let p = find(params, name)?;
        let value = ParamValue::parse(&p.ty, text).map_err(|why| ParamError::Type {
            name: name.to_string(),
            why,
        })?;
        Self::check(params, name, &value)?;
        Ok(value)
    }

    /// Override a parameter after checking the value.
    pub fn set(&mut self, params: &[PlanParam], name: &str, value: ParamValue) -> Result<(), ParamError> {
        Self::check(params, name, &value)?;
        self.values.insert(name.to_string(), value);
        Ok(())
    }

    pub fn get(&self, name: &str) -> Option<&ParamValue> {
        self.values.get(name)
    }

    pub fn iter(&self) -> impl Iterator<Item = (&String, &ParamValue)> {
        self.values.iter()
    }

    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The value a parameter has: its override, else its default.
    pub fn value_of<'a>(&'a self, p: &'a PlanParam) -> &'a ParamValue {
        self.values.get(&p.name).unwrap_or(&p.default)
    }

    /// Keep the overrides that still apply to `params` (after a new Plan replaced the old
    /// one); returns the dropped ones with the reason.
    pub fn retain_applicable(&mut self, params: &[PlanParam]) -> Vec<(String, String)> {
        let mut dropped = vec![];
        self.values.retain(|name, v| match Self::check(params, name, v) {
            Ok(()) => true,
            Err(e) => {
                dropped.push((name.clone(), e.to_string()));
                false
            }
        });
        dropped
    }
}

impl UniformBlock {
    /// The block's bytes: each field's parameter (override or default) at its offset, as
    /// the field's type (bools and enum indices as `u32`; a colour without alpha gets 1).
    pub fn pack(&self, params: &[PlanParam], values: &ParamValues) -> Vec<u8> {
        let mut bytes = vec![];
        self.pack_into(params, values, &mut bytes);
        bytes
    }

    /// `pack` into `bytes` (cleared first), allocating nothing once `bytes` has the block's
    /// size: an executor packs every block every frame.
    pub fn pack_into(&self, params: &[PlanParam], values: &ParamValues, bytes: &mut Vec<u8>) {
        bytes.clear();
        bytes.resize(self.size as usize, 0);
        for f in &self.fields {
            let mut put = |i: usize, w: u32| {
                let at = f.offset as usize + 4 * i;
                if let Some(dst) = bytes.get_mut(at..at + 4) {
                    dst.copy_from_slice(&w.to_le_bytes());
                }
            };
            match &f.source {
                FieldSource::Fixed(w) => w.iter().enumerate().for_each(|(i, w)| put(i, *w)),
                FieldSource::Param(id) => {
                    if let Some(p) = params.get(id.0 as usize) {
                        words(&p.ty, values.value_of(p), f.ty, put);
                    }
                }
            }
        }
    }
}

/// A value as the 32-bit words of a field, each given to `put(index, word)`.
fn words(ty: &ParamType, v: &ParamValue, field: FieldType, mut put: impl FnMut(usize, u32)) {
    match v {
        ParamValue::Float(x) => put(0, (*x as f32).to_bits()),
        ParamValue::Int(x) if field == FieldType::U32 => put(0, *x as u32),
        ParamValue::Int(x) => put(0, (*x as i32) as u32),
        ParamValue::Bool(b) => put(0, *b as u32),
        ParamValue::Vec(c) => {
            for i in 0..field.components() {
                put(i, (*c.get(i).unwrap_or(&1.0) as f32).to_bits());
            }
        }
        ParamValue::Enum(s) => {
            let idx = match ty {
                ParamType::Enum(opts) => opts.iter().position(|o| o == s).unwrap_or(0),
                _ => 0,
            };
            put(0, idx as u32)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::UniformField;

    fn param(name: &str, ty: ParamType, default: ParamValue) -> PlanParam {
        PlanParam {
            name: name.into(),
            ty,
            default,
            min: Some(ParamValue::Float(0.0)),
            max: None,
            doc: None,
            sizes: None,
            preset: None,
            pass: None,
        }
    }

    fn field(name: &str, param: u32, offset: u32, ty: FieldType) -> UniformField {
        UniformField {
            name: name.into(),
            source: FieldSource::Param(ParamId(param)),
            offset,
            size: 4 * ty.components() as u32,
            ty,
        }
    }

    #[test]
    fn packs_each_type_at_its_offset() {
        let params = vec![
            param("a.bias", ParamType::Float, ParamValue::Float(0.5)),
            param("a.pcf", ParamType::Bool, ParamValue::Bool(true)),
            param(
                "a.mode",
                ParamType::Enum(vec!["x".into(), "y".into()]),
                ParamValue::Enum("y".into()),
            ),
            param("a.tint", ParamType::Color, ParamValue::Vec(vec![0.25, 0.5, 0.75])),
            param("a.count", ParamType::Int, ParamValue::Int(-3)),
        ];
        let block = UniformBlock {
            global: "params".into(),
            group: 2,
            binding: 0,
            size: 48,
            align: 16,
            fields: vec![
                field("bias", 0, 0, FieldType::F32),
                field("pcf", 1, 4, FieldType::U32),
                field("mode", 2, 8, FieldType::U32),
                field("count", 4, 12, FieldType::I32),
                field("tint", 3, 16, FieldType::Vec4F32),
                UniformField {
                    name: "dir".into(),
                    source: FieldSource::Fixed(vec![0.5f32.to_bits(), 2.0f32.to_bits()]),
                    offset: 32,
                    size: 8,
                    ty: FieldType::Vec2F32,
                },
            ],
        };
        let b = block.pack(&params, &ParamValues::new());
        let word = |i: usize| u32::from_le_bytes(b[4 * i..4 * i + 4].try_into().unwrap());
        let float = |i: usize| f32::from_bits(word(i));
        assert_eq!(b.len(), 48);
        assert_eq!(float(0), 0.5);
        assert_eq!(word(1), 1);
        assert_eq!(word(2), 1, "enum option index");
        assert_eq!(word(3) as i32, -3);
        assert_eq!(
            [float(4), float(5), float(6), float(7)],
            [0.25, 0.5, 0.75, 1.0],
            "alpha defaults to 1"
        );
        assert_eq!([float(8), float(9)], [0.5, 2.0], "a per-pass value");
        assert!(b[40..].iter().all(|x| *x == 0), "padding stays zero");
        let mut over = ParamValues::new();
        over.set(&params, "a.bias", ParamValue::Float(2.0)).unwrap();
        assert_eq!(
            f32::from_bits(u32::from_le_bytes(block.pack(&params, &over)[0..4].try_into().unwrap())),
            2.0
        );
    }

    #[test]
    fn overrides_are_checked_and_dropped_when_they_no_longer_apply() {
        let params = vec![param("a.bias", ParamType::Float, ParamValue::Float(0.5))];
        let mut v = ParamValues::new();
        assert!(
            matches!(v.set(&params, "a.bais", ParamValue::Float(1.0)), Err(ParamError::Unknown { suggestion: Some(s), .. }) if s == "a.bias")
        );
        assert!(matches!(
            v.set(&params, "a.bias", ParamValue::Bool(true)),
            Err(ParamError::Type { .. })
        ));
        assert!(matches!(
            v.set(&params, "a.bias", ParamValue::Float(-1.0)),
            Err(ParamError::Range { .. })
        ));
        assert!(matches!(
            v.set(&params, "a.bias", ParamValue::Float(f64::NAN)),
            Err(ParamError::Range { .. })
        ));
        v.set(&params, "a.bias", ParamValue::Float(1.0)).unwrap();
        assert!(v.retain_applicable(&params).is_empty());
        let other = vec![param("b.key", ParamType::Float, ParamValue::Float(0.1))];
        let dropped = v.retain_applicable(&other);
        assert_eq!(dropped.len(), 1);
        assert!(v.is_empty());
    }
}
