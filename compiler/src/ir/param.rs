//! Typed parameters: the values a pass's uniform block carries.

use crate::diag::Code;
use crate::span::{Span, Spanned};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ParamType {
    Float,
    Int,
    Bool,
    Vec2,
    Vec3,
    Vec4,
    /// Linear RGB (a `vec3<f32>` or `vec4<f32>` in the shader).
    Color,
    /// One of the named options; the shader receives the option's index as `u32`.
    Enum(Vec<String>),
}

impl ParamType {
    pub fn name(&self) -> &'static str {
        match self {
            ParamType::Float => "Float",
            ParamType::Int => "Int",
            ParamType::Bool => "Bool",
            ParamType::Vec2 => "Vec2",
            ParamType::Vec3 => "Vec3",
            ParamType::Vec4 => "Vec4",
            ParamType::Color => "Color",
            ParamType::Enum(_) => "Enum",
        }
    }
    pub const NAMES: [&'static str; 8] = ["Float", "Int", "Bool", "Vec2", "Vec3", "Vec4", "Color", "Enum"];

    /// The type a kind name gives, for every kind but `Enum` (which needs its options).
    pub fn from_name(s: &str) -> Option<Self> {
        Some(match s {
            "Float" => ParamType::Float,
            "Int" => ParamType::Int,
            "Bool" => ParamType::Bool,
            "Vec2" => ParamType::Vec2,
            "Vec3" => ParamType::Vec3,
            "Vec4" => ParamType::Vec4,
            "Color" => ParamType::Color,
            _ => return None,
        })
    }

    /// Does a value (e.g. a `--param` override) have this type? `Err` says why not.
    pub fn accepts(&self, v: &ParamValue) -> Result<(), String> {
        let ok = match (self, v) {
            (ParamType::Float, ParamValue::Float(_)) | (ParamType::Int, ParamValue::Int(_)) | (ParamType::Bool, ParamValue::Bool(_)) => {
                true
            }
            (ParamType::Enum(opts), ParamValue::Enum(s)) => {
                if !opts.contains(s) {
                    return Err(format!("`{s}` is not one of {}", opts.join(", ")));
                }
                true
            }
            (t, ParamValue::Vec(c)) => t.takes_components(c.len()),
            _ => false,
        };
        if ok {
            Ok(())
        } else {
            Err(format!("a {} parameter cannot take {}", self.name(), v.describe()))
        }
    }

    /// Does a vector-like type take a tuple of `n` numbers? (A colour may carry alpha.)
    pub fn takes_components(&self, n: usize) -> bool {
        self.components() == Some(n) || (matches!(self, ParamType::Color) && n == 4)
    }

    /// Number of components a vector-like type needs in its default.
    pub fn components(&self) -> Option<usize> {
        match self {
            ParamType::Vec2 => Some(2),
            ParamType::Vec3 | ParamType::Color => Some(3),
            ParamType::Vec4 => Some(4),
            _ => None,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ParamValue {
    Float(f64),
    Int(i64),
    Bool(bool),
    Vec(Vec<f64>),
    Enum(String),
}

impl ParamValue {
    /// A value of type `ty` written on a command line: `0.5`, `3`, `true`, `filmic`,
    /// `(1, 0.5, 0)` or `1,0.5,0`. Range checks are `ParamValues::check`'s.
    pub fn parse(ty: &ParamType, text: &str) -> Result<ParamValue, String> {
        let t = text.trim();
        // Every number becomes an f32 on the GPU: NaN, inf and 1e39 (+inf there) are refused.
        let number = |s: &str| match s.trim().parse::<f64>() {
            Ok(v) if (v as f32).is_finite() => Ok(v),
            Ok(_) => Err(format!("`{}` is not a finite 32-bit number", s.trim())),
            Err(_) => Err(format!("`{s}` is not a number")),
        };
        Ok(match ty {
            ParamType::Float => ParamValue::Float(number(t)?),
            ParamType::Int => ParamValue::Int(t.parse().map_err(|_| format!("`{t}` is not a whole number"))?),
            ParamType::Bool => ParamValue::Bool(t.parse().map_err(|_| format!("`{t}` is not `true` or `false`"))?),
            ParamType::Enum(_) => ParamValue::Enum(t.to_string()),
            ParamType::Vec2 | ParamType::Vec3 | ParamType::Vec4 | ParamType::Color => {
                let inner = t.strip_prefix('(').and_then(|r| r.strip_suffix(')')).unwrap_or(t);
                let v: Vec<f64> = inner.split(',').map(number).collect::<Result<_, _>>()?;
                if !ty.takes_components(v.len()) {
                    let n = ty.components().unwrap_or(0);
                    let alpha = if matches!(ty, ParamType::Color) {
                        " (or 4, with alpha)"
                    } else {
                        ""
                    };
                    return Err(format!("`{t}` has {} numbers; {} takes {n}{alpha}", v.len(), ty.name()));
                }
                // A colour's alpha has no range of its own to be held to: it is a fraction.
                if let (ParamType::Color, Some(a)) = (ty, v.get(3)) {
                    if !(0.0..=1.0).contains(a) {
                        return Err(format!("`{t}`: alpha {a} is outside 0..1"));
                    }
                }
                ParamValue::Vec(v)
            }
        })
    }

    pub fn describe(&self) -> String {
        match self {
            ParamValue::Float(f) => format!("{f}"),
            ParamValue::Int(i) => format!("{i}"),
            ParamValue::Bool(b) => format!("{b}"),
            ParamValue::Vec(v) => format!("({})", v.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(", ")),
            ParamValue::Enum(s) => format!("{s:?}"),
        }
    }
    /// Components as floats, for range checks.
    pub fn as_floats(&self) -> Vec<f64> {
        match self {
            ParamValue::Float(f) => vec![*f],
            ParamValue::Int(i) => vec![*i as f64],
            ParamValue::Vec(v) => v.clone(),
            _ => vec![],
        }
    }
}

/// Whether a value lies outside a parameter's `min`/`max` (component-wise): the bound it
/// crosses and which one (`"min"` or `"max"`). One rule for defaults and overrides.
pub fn out_of_range<'a>(
    v: &ParamValue,
    min: Option<&'a ParamValue>,
    max: Option<&'a ParamValue>,
) -> Option<(&'static str, &'a ParamValue)> {
    let x = v.as_floats();
    let below = |b: &ParamValue| x.iter().zip(b.as_floats()).any(|(v, l)| *v < l);
    let above = |b: &ParamValue| x.iter().zip(b.as_floats()).any(|(v, h)| *v > h);
    match (min, max) {
        (Some(lo), _) if below(lo) => Some(("min", lo)),
        (_, Some(hi)) if above(hi) => Some(("max", hi)),
        _ => None,
    }
}

/// A value as a front end read it, before it is checked against the declared type.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Literal {
    Int(i64),
    Float(f64),
    Bool(bool),
    Text(String),
    Tuple(Vec<f64>),
    /// Anything else, described for the message (e.g. "a list").
    Other(String),
}

impl Literal {
    pub fn describe(&self) -> String {
        match self {
            Literal::Int(i) => format!("the integer {i}"),
            Literal::Float(f) => format!("the number {f}"),
            Literal::Bool(b) => format!("`{b}`"),
            Literal::Text(s) => format!("{s:?}"),
            Literal::Tuple(v) => format!("a tuple of {}", v.len()),
            Literal::Other(w) => w.clone(),
        }
    }
}

/// Why a literal does not fit a parameter type: a diagnostic code, message and optional note.
pub struct ValueError {
    pub code: Code,
    pub message: String,
    pub note: Option<String>,
}

impl ParamType {
    /// The value a literal gives this type, with the checks both front ends share.
    pub fn value_of(&self, lit: Literal) -> Result<ParamValue, ValueError> {
        let err = |code, message: String| Err(ValueError { code, message, note: None });
        match (self, lit) {
            (ParamType::Float, Literal::Float(f)) => Ok(ParamValue::Float(f)),
            (ParamType::Float, Literal::Int(i)) => Ok(ParamValue::Float(i as f64)),
            (ParamType::Int, Literal::Int(i)) => Ok(ParamValue::Int(i)),
            (ParamType::Bool, Literal::Bool(b)) => Ok(ParamValue::Bool(b)),
            // Membership in the options is checked with the declarations.
            (ParamType::Enum(_), Literal::Text(s)) => Ok(ParamValue::Enum(s)),
            (t, Literal::Tuple(v)) if t.components().is_some() => {
                let n = t.components().unwrap_or(0);
                if t.takes_components(v.len()) {
                    Ok(ParamValue::Vec(v))
                } else {
                    err(
                        Code::ParamType,
                        format!("a {} value has {n} components, found {}", t.name(), v.len()),
                    )
                }
            }
            (t, lit) => {
                let expected = match t {
                    ParamType::Float => "a number".to_string(),
                    ParamType::Int => "a whole number".to_string(),
                    ParamType::Bool => "`true` or `false`".to_string(),
                    ParamType::Enum(_) => "one of the Enum's options".to_string(),
                    t => format!("a tuple of {} numbers", t.components().unwrap_or(0)),
                };
                err(
                    Code::ParamType,
                    format!("{} parameter: expected {expected}, found {}", t.name(), lit.describe()),
                )
            }
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Param {
    pub name: Spanned<String>,
    pub ty: Spanned<ParamType>,
    pub default: Spanned<ParamValue>,
    pub min: Option<Spanned<ParamValue>>,
    pub max: Option<Spanned<ParamValue>>,
    /// One line shown in `plan --explain` and the viewer.
    pub doc: Option<String>,
    pub span: Span,
}
