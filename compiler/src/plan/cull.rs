//! Stages `conditions` and `cull`: evaluate each pass's `when` for the configuration,
//! drop passes that repeat over lights the scene lacks or that the output does not need,
//! then order the rest (stage `graph`, in `order`).

use super::order;
use super::Config;
use crate::check::Checked;
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::*;
use crate::span::Spanned;
use std::collections::BTreeMap;

/// Whether a condition holds for the configuration (`eval` says why not, when asked).
fn holds(c: &Condition, p: &Pipeline, cfg: &Config) -> bool {
    match c {
        Condition::Light(k) => cfg.scene.lights.get(k).copied().unwrap_or(0) > 0,
        Condition::Effect(e) => cfg.scene.effects.contains(e),
        Condition::Reflective => cfg.scene.reflective,
        Condition::Blended => cfg.scene.transparent,
        Condition::Toggle(name) => matches!(p.param(name).map(|prm| cfg.default_of(p, prm).0), Some(ParamValue::Bool(true))),
        Condition::Variant(v, o) => cfg.selection.chosen.get(&v.value).map_or("", String::as_str) == o.value,
        Condition::Not(inner) => !holds(inner, p, cfg),
        Condition::All(cs) => cs.iter().all(|c| holds(c, p, cfg)),
        Condition::Any(cs) => cs.iter().any(|c| holds(c, p, cfg)),
        Condition::Named(_, c) => holds(c, p, cfg),
    }
}

/// `Ok(())` if true, else the reason it is false and whether a variant choice decided it
/// (the truth is `holds`'s; this only words it).
fn eval(c: &Condition, p: &Pipeline, cfg: &Config) -> Result<(), (String, bool)> {
    match c.decided() {
        Condition::All(cs) => cs.iter().try_for_each(|c| eval(c, p, cfg)),
        Condition::Any(cs) => {
            if let Some((v, options)) = options_of_one_variant(cs).filter(|_| !holds(c, p, cfg)) {
                // `variant(v, a | b)`: one reason naming the options, not one per option.
                let chosen = cfg.selection.chosen.get(v).map_or("", String::as_str);
                let options: Vec<String> = options.iter().map(|o| format!("`{o}`")).collect();
                let why = format!(
                    "variant not chosen: `{v}` is `{chosen}`, this pass belongs to {}",
                    options.join(" or ")
                );
                return Err((why, true));
            }
            let mut reasons = vec![];
            let mut by_variant = true;
            for c in cs {
                match eval(c, p, cfg) {
                    Ok(()) => return Ok(()),
                    Err((r, v)) => {
                        reasons.push(r);
                        by_variant &= v;
                    }
                }
            }
            Err((format!("none holds: {}", reasons.join("; ")), by_variant && !cs.is_empty()))
        }
        c if holds(c, p, cfg) => Ok(()),
        c => Err(why_false(c, cfg)),
    }
}

/// The variant and its options when every condition of `cs` chooses an option of one variant.
fn options_of_one_variant(cs: &[Spanned<Condition>]) -> Option<(&str, Vec<&str>)> {
    let mut variant = None;
    let mut options = vec![];
    for c in cs {
        let Condition::Variant(v, o) = c.value.decided() else { return None };
        if variant.is_some_and(|name| name != v.value.as_str()) {
            return None;
        }
        variant = Some(v.value.as_str());
        options.push(o.value.as_str());
    }
    Some((variant?, options))
}

/// Why a condition other than `All`/`Any` that does not hold is false, and whether a
/// variant choice decided it.
fn why_false(c: &Condition, cfg: &Config) -> (String, bool) {
    match c.decided() {
        Condition::Light(k) => (format!("the scene has no {} light", k.name()), false),
        Condition::Effect(e) => (format!("the scene does not call for {}", e.name()), false),
        Condition::Reflective => ("the scene has no reflective material".into(), false),
        Condition::Blended => ("the scene has no blended material".into(), false),
        Condition::Toggle(name) => (format!("toggle `{}` is off", name.value), false),
        Condition::Variant(v, o) => {
            let chosen = cfg.selection.chosen.get(&v.value).map_or("", String::as_str);
            let why = format!(
                "variant not chosen: `{}` is `{chosen}`, this pass belongs to `{}`",
                v.value, o.value
            );
            (why, true)
        }
        Condition::Not(inner) => match inner.value.decided() {
            Condition::Variant(v, o) => {
                let why = format!(
                    "variant not chosen: `{}` is `{}`, this pass serves the other options",
                    v.value, o.value
                );
                (why, true)
            }
            _ => (format!("{} holds", inner.describe()), inner.mentions_variant()),
        },
        Condition::All(_) | Condition::Any(_) | Condition::Named(..) => ("its condition is false".into(), c.mentions_variant()),
    }
}

/// Which passes a configuration keeps, in what order, and why the others are culled.
pub struct Schedule {
    pub culled: BTreeMap<usize, Cause>,
    pub ordered: std::sync::Arc<order::Ordered>,
}

/// What culled a pass; `reason` words it (only a diagnostic or a Plan asks, so `check`'s
/// many configurations format nothing).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cause {
    /// Its condition is false.
    Condition,
    /// It repeats per light of kinds the scene has none of (or none casting shadows).
    NoLights,
    /// It draws blended meshes and the scene has none.
    NoBlended,
    /// Nothing on the way to the output reads what it writes.
    Unreachable,
}

/// Why pass `i` was culled, in words.
pub fn reason(p: &Pipeline, cfg: &Config, i: usize, cause: Cause) -> String {
    let pass = &p.passes[i];
    match cause {
        Cause::Condition => {
            let when = pass.choice.as_ref().map_or(&pass.when, |c| &c.when);
            match when.as_ref().map(|w| (w, eval(w, p, cfg))) {
                Some((_, Err((why, true)))) => why,
                Some((w, Err((why, false)))) => format!("condition `{}` is false: {why}", w.describe()),
                _ => "its condition is false".into(),
            }
        }
        Cause::NoLights => {
            let kinds: &[LightKind] = pass.per_light.as_ref().map_or(&[], |k| &k.value);
            let names: Vec<&str> = kinds.iter().map(|k| k.name()).collect();
            // "Directional, Spot or Area"
            let either = match names.split_last() {
                Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
                _ => names.concat(),
            };
            if pass.shadow_casters && cfg.scene.light_count(kinds) > 0 {
                format!("runs per shadow-casting {either} light and no such light casts shadows")
            } else {
                format!("runs per {either} light and the scene has none")
            }
        }
        Cause::NoBlended => "draws the scene's blended meshes and the scene has none".into(),
        Cause::Unreachable => {
            let writes: Vec<String> = pass.written().map(|w| format!("`{}`", w.value)).collect();
            format!(
                "output unreachable: nothing on the way to `{}` reads {}",
                p.output.value,
                writes.join(", ")
            )
        }
    }
}

/// The checks of a configuration without assembling the Plan (what `check` needs).
pub fn schedule(checked: &Checked, cfg: &Config, diags: &mut Diagnostics) -> Option<Schedule> {
    let p = &checked.pipeline;
    let (candidates, mut culled) = conditions(p, cfg);
    let kept = reachable(p, &candidates);
    for &i in candidates.iter().filter(|i| !kept.contains(i)) {
        culled.insert(i, Cause::Unreachable);
    }
    let why = |j: usize| culled.get(&j).map(|&c| reason(p, cfg, j, c));
    for (what, out) in [("output", Some(&p.output)), ("hdr_output", p.hdr_output.as_ref())] {
        let Some(out) = out else { continue };
        if !kept.iter().any(|&i| p.passes[i].written().any(|w| w.value == out.value)) {
            let mut d = Diagnostic::error(
                Code::OutputUnreachable,
                format!("no kept pass writes the {what} `{}`", out.value),
                out.span,
            );
            for &i in culled.keys() {
                if p.passes[i].written().any(|w| w.value == out.value) {
                    let why = why(i).unwrap_or_default();
                    d = d.with_note(format!("its writer `{}` was culled: {why}", p.passes[i].name.value));
                }
            }
            diags.push(d);
            return None;
        }
    }
    let ordered = match cfg.orders {
        Some(orders) => orders.order(p, &kept, &why, diags)?,
        None => std::sync::Arc::new(order::order(p, &kept, &why, diags)?),
    };
    // A pass whose shaders failed to check has no version; its errors are already reported.
    if ordered.order.iter().any(|&i| checked.version(i, &cfg.selection.chosen).is_none()) {
        return None;
    }
    Some(Schedule { culled, ordered })
}

/// Passes whose condition holds and whose light kinds the scene has; the others with why.
fn conditions(p: &Pipeline, cfg: &Config) -> (Vec<usize>, BTreeMap<usize, Cause>) {
    let mut culled: BTreeMap<usize, Cause> = BTreeMap::new();
    let mut candidates = vec![];
    for (i, pass) in p.passes.iter().enumerate() {
        // A copy of a pass written with choices whose arms are not chosen is not culled:
        // another copy of the pass is the one that runs.
        if pass.choice.as_ref().is_some_and(|c| !c.serves(&cfg.selection.chosen)) {
            continue;
        }
        let when = pass.choice.as_ref().map_or(&pass.when, |c| &c.when);
        let cause = if when.as_ref().is_some_and(|w| !holds(w, p, cfg)) {
            Some(Cause::Condition)
        } else if pass
            .per_light
            .as_ref()
            .is_some_and(|k| cfg.scene.repeats_for(k, pass.shadow_casters) == 0)
        {
            Some(Cause::NoLights)
        } else if matches!(&pass.kind, PassKind::Raster(r) if r.draw == Draw::Transparent) && !cfg.scene.transparent {
            Some(Cause::NoBlended)
        } else {
            None
        };
        match cause {
            Some(c) => {
                culled.insert(i, c);
            }
            None => candidates.push(i),
        }
    }
    (candidates, culled)
}

/// Output reachability: the candidates whose writes the output (transitively) needs, in file order.
fn reachable(p: &Pipeline, candidates: &[usize]) -> Vec<usize> {
    let mut needed: Vec<String> = vec![p.output.value.clone()];
    needed.extend(p.hdr_output.as_ref().map(|h| h.value.clone()));
    let mut kept: Vec<usize> = vec![];
    loop {
        let mut changed = false;
        for &i in candidates.iter().rev() {
            let pass = &p.passes[i];
            if kept.contains(&i) || !pass.written().any(|w| needed.contains(&w.value)) {
                continue;
            }
            kept.push(i);
            changed = true;
            for r in pass.touched() {
                if !needed.contains(&r.value) {
                    needed.push(r.value.clone());
                }
            }
        }
        if !changed {
            break;
        }
    }
    kept.sort();
    kept
}
