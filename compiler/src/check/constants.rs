//! Stage `constants`: each of a pass's constants names an `override` of its shaders and fits
//! its type. (Whether the values leave the shaders valid depends on the configuration: the
//! plan's stage `constants` applies them.)

use super::StageShader;
use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::ir::{Constant, ParamType, Pass, Pipeline};
use crate::span::Spanned;
use naga::{Scalar, ScalarKind, TypeInner};

/// What a constant's value is, for matching it with an override's type.
enum Kind {
    Bool,
    Whole(f64),
    Number,
    Int,
    Float,
}

fn kind(p: &Pipeline, c: &Constant) -> Option<Kind> {
    Some(match c {
        Constant::Bool(_) | Constant::Variant(..) => Kind::Bool,
        Constant::Number(x) if x.fract() == 0.0 => Kind::Whole(*x),
        Constant::Number(_) => Kind::Number,
        Constant::Param(name) => match p.param(name)?.ty.value {
            ParamType::Int => Kind::Int,
            ParamType::Float => Kind::Float,
            ParamType::Bool => Kind::Bool,
            _ => return None, // reported by the declaration check
        },
    })
}

/// Does a value of this kind fit an override of this scalar type?
fn fits(k: &Kind, s: Scalar) -> bool {
    match (k, s.kind) {
        (Kind::Bool, ScalarKind::Bool) => true,
        (Kind::Whole(x), ScalarKind::Uint) => *x >= 0.0,
        (Kind::Whole(_) | Kind::Int, ScalarKind::Sint | ScalarKind::Uint) => true,
        (Kind::Whole(_) | Kind::Number | Kind::Int | Kind::Float, ScalarKind::Float) => true,
        _ => false,
    }
}

/// `f32`, `u32`, `bool`...
fn scalar_word(s: Scalar) -> String {
    let letter = match s.kind {
        ScalarKind::Bool => return "a bool".into(),
        ScalarKind::Float => "f",
        ScalarKind::Sint => "i",
        ScalarKind::Uint => "u",
        _ => return format!("{s:?}"),
    };
    format!("{letter}{}", u32::from(s.width) * 8)
}

fn describe(c: &Constant) -> String {
    match c {
        Constant::Number(x) => format!("`{x}`"),
        Constant::Bool(b) => format!("`{b}`"),
        Constant::Param(n) => format!("parameter `{n}`"),
        Constant::Variant(v, o) => format!("`Variant(\"{v}\", \"{o}\")` (a bool)"),
    }
}

pub(super) fn check(p: &Pipeline, pass: &Pass, stages: &[StageShader], diags: &mut Diagnostics) {
    for (name, c) in &pass.constants {
        let mut found = false;
        for st in stages {
            let m = &st.module.module;
            for (h, o) in m.overrides.iter() {
                let key = o.id.map(|id| id.to_string());
                if o.name.as_deref() != Some(name.value.as_str()) && key.as_deref() != Some(name.value.as_str()) {
                    continue;
                }
                found = true;
                let TypeInner::Scalar(s) = m.types[o.ty].inner else { continue };
                match kind(p, &c.value) {
                    Some(k) if !fits(&k, s) => {
                        let mut d = Diagnostic::error(
                            Code::ConstantType,
                            format!(
                                "`override {}` of `{}` is {}; {} does not fit it",
                                name.value,
                                st.sref.file.value,
                                scalar_word(s),
                                describe(&c.value)
                            ),
                            c.span,
                        );
                        if let Some(at) = st.module.map_span(m.overrides.get_span(h)) {
                            d = d.with_secondary(at, "declared here");
                        }
                        diags.push(d);
                    }
                    _ => {}
                }
            }
        }
        if !found {
            diags.push(unknown(name, stages));
        }
    }
}

fn unknown(name: &Spanned<String>, stages: &[StageShader]) -> Diagnostic {
    let declared: Vec<&str> = stages
        .iter()
        .flat_map(|st| st.module.module.overrides.iter().filter_map(|(_, o)| o.name.as_deref()))
        .collect();
    let files: Vec<&str> = stages
        .iter()
        .map(|st| st.sref.file.value.as_str())
        .filter(|f| *f != crate::ir::FULLSCREEN_FILE)
        .collect();
    Diagnostic::error(
        Code::ConstantUnknown,
        format!("no `override {}` in the pass's shaders ({})", name.value, files.join(", ")),
        name.span,
    )
    .with_note(suggestion_note(&name.value, &declared))
}
