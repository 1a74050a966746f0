//! Typed parameters: the values a pass's uniform block carries.

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
