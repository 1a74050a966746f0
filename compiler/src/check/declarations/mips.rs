//! Each pass's subresource selections: mip levels that exist at every repetition of a
//! `per_mip` pass, `Rep` only in such a pass, a pass that writes some mips of a texture while
//! reading others never reading the level it writes; layers read one at a time that exist.

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
            layer_read(p, name, layer, diags);
        }
    }
}

/// `Layer("x", n)`: a texture with at least n + 1 layers.
fn layer_read(p: &Pipeline, name: &Spanned<String>, layer: &Spanned<u32>, diags: &mut Diagnostics) {
    let Some(r) = p.resource(name) else { return };
    let msg = match r.texture() {
        None => format!("`{}` is a buffer: it has no layers", name.value),
        Some(t) if layer.value >= t.layers.value => {
            format!("layer {} is out of range: `{}` has {}", layer.value, name.value, t.layers.value)
        }
        Some(_) => return,
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
