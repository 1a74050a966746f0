//! Each pass's subresource selections: mip levels that exist at every repetition of a
//! `per_mip` pass, `Rep` only in such a pass, a pass that writes some mips of a texture while
//! reading others never reading the level it writes; layers read one at a time that exist;
//! a `repeat` pass's count within the layers its `Rep` targets have.

use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::span::{Span, Spanned};

/// The repetition levels of a pass: those of `per_mip`, else level 0 once.
fn rep_levels(pass: &Pass) -> Vec<u32> {
    pass.per_mip.as_ref().map(|m| m.value.levels()).unwrap_or_else(|| vec![0])
}

pub(super) fn mips(p: &Pipeline, pass: &Pass, diags: &mut Diagnostics) {
    let targets = pass
        .color()
        .iter()
        .map(|c| (&c.resource, c.mip.clone()))
        .chain(pass.depth().map(|d| (&d.resource, d.mip.clone())));
    let reads = pass.reads.iter().filter_map(|r| match r {
        Read::Mip(n, m) => Some((n, m.clone())),
        _ => None,
    });
    let mut ok = true;
    for (res, sel) in targets.chain(reads) {
        ok &= selection(p, pass, res, sel, diags);
    }
    if ok {
        own_levels(pass, diags);
    }
    for r in &pass.reads {
        if let Read::Layer(name, layer) = r {
            layer_read(p, pass, name, layer, diags);
        }
    }
    if let Some(r) = &pass.repeat {
        repeat(p, pass, r, diags);
    }
}

/// `repeat`: alone (not with `per_mip` or `per_face`), at least once, and — a number, or
/// every value of the Int parameter's range — at most the layers of each target it picks by
/// `Rep(d)` (layer repetition + d must exist).
fn repeat(p: &Pipeline, pass: &Pass, r: &Spanned<Repeat>, diags: &mut Diagnostics) {
    let mut err = |msg: String| diags.push(Diagnostic::error(Code::LayerSelect, msg, r.span));
    if pass.per_mip.is_some() || pass.per_face {
        return err("`repeat` cannot be combined with `per_mip` or `per_face`".into());
    }
    let (lo, hi, what) = match &r.value {
        Repeat::Times(n) => (*n as f64, *n as f64, format!("{n} times")),
        Repeat::Param(name) => match p.param(name) {
            None => return err(format!("`repeat` names parameter `{name}`, which is not declared")),
            Some(prm) if prm.ty.value != ParamType::Int => return err(format!("`repeat` needs an Int parameter; `{name}` is not one")),
            Some(prm) => {
                let bound = |m: &Option<Spanned<ParamValue>>| m.as_ref().and_then(|m| m.value.as_floats().first().copied());
                match (bound(&prm.min), bound(&prm.max)) {
                    (Some(lo), Some(hi)) => (lo, hi, format!("up to {hi} times (`{name}`)")),
                    _ => {
                        return err(format!(
                            "`repeat` by `{name}` needs its range (`min` and `max`) so that every value plans"
                        ))
                    }
                }
            }
        },
    };
    if lo < 1.0 {
        return err("`repeat` must run the pass at least once".into());
    }
    let targets = pass
        .color()
        .iter()
        .map(|c| (&c.resource, c.layer))
        .chain(pass.depth().map(|d| (&d.resource, d.layer)));
    for (res, layer) in targets {
        let (LayerSel::Rep(d), Some(t)) = (layer, p.resource(res).and_then(|x| x.texture())) else {
            continue;
        };
        let (first, last) = (d as f64, hi - 1.0 + d as f64);
        if first < 0.0 || last >= t.layers.value as f64 {
            return err(format!(
                "`repeat` runs {what}, writing layers {first}..={last} of `{}`, which has {}",
                res.value, t.layers.value
            ));
        }
    }
}

/// `Layer("x", n)`: a texture with at least n + 1 layers; `Layer("x", Rep(d))`: a `repeat`
/// pass, reading another layer than the one it writes.
fn layer_read(p: &Pipeline, pass: &Pass, name: &Spanned<String>, layer: &Spanned<LayerSel>, diags: &mut Diagnostics) {
    let Some(r) = p.resource(name) else { return };
    let writes_same = |d: i32| {
        let t = pass
            .color()
            .iter()
            .map(|c| (&c.resource, c.layer))
            .chain(pass.depth().map(|d| (&d.resource, d.layer)));
        t.into_iter().any(|(res, l)| res.value == name.value && l == LayerSel::Rep(d))
    };
    let msg = match (r.texture(), layer.value) {
        (None, _) => format!("`{}` is a buffer: it has no layers", name.value),
        (Some(t), LayerSel::Index(n)) if n >= t.layers.value => {
            format!("layer {n} is out of range: `{}` has {}", name.value, t.layers.value)
        }
        (Some(_), LayerSel::Rep(_)) if pass.repeat.is_none() => "`Layer(.., Rep(..))` needs a pass with `repeat`".to_string(),
        (Some(_), LayerSel::Rep(d)) if writes_same(d) => {
            format!(
                "pass `{}` reads the layer of `{}` it writes (`Rep({d})`)",
                pass.name.value, name.value
            )
        }
        _ => return,
    };
    diags.push(Diagnostic::error(Code::LayerSelect, msg, layer.span));
}

/// One selection against the texture's mip count at every repetition level.
fn selection(p: &Pipeline, pass: &Pass, res: &Spanned<String>, sel: Spanned<MipSel>, diags: &mut Diagnostics) -> bool {
    let Some(r) = p.resource(res) else { return true };
    let mut err = |msg: String| {
        diags.push(Diagnostic::error(Code::MipSelect, msg, sel.span));
        false
    };
    let Some(t) = r.texture() else {
        return err(format!("`{}` is a buffer: it has no mip levels", res.value));
    };
    let mips = t.mips.value;
    if matches!(sel.value, MipSel::Rep(_)) && pass.per_mip.is_none() {
        return err("`Rep` selects the level of a `per_mip` repetition; give the pass `per_mip: (from, to)`".into());
    }
    for rep in rep_levels(pass) {
        let level = sel.value.level(rep);
        if level.is_none_or(|l| l >= mips) {
            let shown = level
                .map(|l| l.to_string())
                .unwrap_or_else(|| format!("{}", rep as i64 + rep_offset(sel.value)));
            let at = if pass.per_mip.is_some() {
                format!(" (at repetition level {rep})")
            } else {
                String::new()
            };
            return err(format!(
                "mip {shown} of `{}` is out of range{at}: it has {mips} mip level(s)",
                res.value
            ));
        }
    }
    true
}

fn rep_offset(m: MipSel) -> i64 {
    match m {
        MipSel::Rep(d) => d as i64,
        MipSel::Level(_) => 0,
    }
}

/// A pass reading mips of a texture it renders into must not read the level it writes.
fn own_levels(pass: &Pass, diags: &mut Diagnostics) {
    for (name, read) in pass.reads.iter().filter_map(|r| match r {
        Read::Mip(n, m) => Some((n, m.clone())),
        _ => None,
    }) {
        let written: Vec<(Spanned<MipSel>, Span)> = pass
            .color()
            .iter()
            .filter(|c| c.resource.value == name.value)
            .map(|c| (c.mip.clone(), c.span))
            .chain(
                pass.depth()
                    .filter(|d| d.resource.value == name.value)
                    .map(|d| (d.mip.clone(), d.span)),
            )
            .collect();
        for rep in rep_levels(pass) {
            if let Some((w, span)) = written.iter().find(|(w, _)| w.value.level(rep) == read.value.level(rep)) {
                let level = w.value.level(rep).unwrap_or(0);
                diags.push(
                    Diagnostic::error(
                        Code::MipSelect,
                        format!("pass `{}` reads mip {level} of `{}`, which it writes", pass.name.value, name.value),
                        read.span,
                    )
                    .with_secondary(*span, "written here"),
                );
                return;
            }
        }
    }
}
