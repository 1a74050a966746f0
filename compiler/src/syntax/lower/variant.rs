//! Lowering of variants and their options.

use super::{Lowerer, Res};
use crate::diag::{Code, Diagnostic};
use crate::ir::{Literal, Variant, VariantOption};
use crate::profile::Feature;
use crate::span::Spanned;
use crate::tree::Node;

impl Lowerer<'_> {
    pub(super) fn variants(&mut self, n: &Node) -> Res<Vec<Variant>> {
        let entries = self.string_map(n)?;
        Some(entries.into_iter().filter_map(|(name, v)| self.variant(name, &v)).collect())
    }

    fn variant(&mut self, name: Spanned<String>, node: &Node) -> Res<Variant> {
        let mut o = self.obj(node, &["Variant"], "variant")?;
        o.what = format!("variant `{}`", name.value);
        let default = self.required(&mut o, "default").and_then(|n| self.string(&n));
        let doc = o.take("doc").and_then(|n| self.string(&n)).map(|s| s.value);
        let options = self.required(&mut o, "options").and_then(|n| self.variant_options(&n));
        let span = o.span;
        self.finish(o, &["default", "doc", "options"], &[]);
        Some(Variant {
            name,
            options: options?,
            default: default?,
            doc,
            span,
        })
    }

    fn variant_options(&mut self, n: &Node) -> Res<Vec<VariantOption>> {
        let entries = self.string_map(n)?;
        Some(entries.into_iter().filter_map(|(name, v)| self.variant_option(name, &v)).collect())
    }

    fn variant_option(&mut self, name: Spanned<String>, node: &Node) -> Res<VariantOption> {
        let mut o = self.obj(node, &["Option"], "variant option")?;
        o.what = format!("variant option `{}`", name.value);
        if let Some(why) = unnameable(&name.value) {
            let msg = format!("option `{}`: a name may not {why}", name.value);
            self.err(Diagnostic::error(Code::TypeMismatch, msg, name.span));
        }
        let requires = o.get("requires").and_then(|n| {
            let items = self.list(&n)?.to_vec();
            items
                .iter()
                .map(|i| {
                    self.ident(i, "feature", Feature::NAMES, Feature::from_name)
                        .map(|f| Spanned::new(f, i.span))
                })
                .collect::<Option<Vec<_>>>()
        });
        let limits = o.get("limits").and_then(|n| {
            let entries = self.string_map(&n)?;
            entries
                .into_iter()
                .map(|(k, v)| self.u64(&v).map(|v| (k, v)))
                .collect::<Option<Vec<_>>>()
        });
        let fallback = match o.take("fallback") {
            Some(n) => Some(self.string(&n)?),
            None => None,
        };
        let shaders = o.get("shaders").and_then(|n| self.string_pairs(&n));
        let params = o.get("params").and_then(|n| self.presets(&n));
        let jitter = o.get("jitter").and_then(|n| self.bool(&n));
        let doc = o.take("doc").and_then(|n| self.string(&n)).map(|s| s.value);
        let span = o.span;
        self.finish(o, &["requires", "limits", "fallback", "shaders", "params", "jitter", "doc"], &[]);
        Some(VariantOption {
            name,
            requires: requires?,
            limits: limits?,
            fallback,
            shaders: shaders?,
            params: params?,
            jitter: jitter?,
            doc,
            span,
        })
    }

    /// `params: {"name": value}`: a preset's parameter values, typed by the check against
    /// each parameter's declaration.
    fn presets(&mut self, n: &Node) -> Res<Vec<(Spanned<String>, Spanned<Literal>)>> {
        let mut out = vec![];
        for (k, v) in self.string_map(n)? {
            match self.literal(&v)? {
                Literal::Other(_) => return self.type_err("a number, `true`/`false`, a string or a tuple of numbers", &v),
                lit => out.push((k, Spanned::new(lit, v.span))),
            }
        }
        Some(out)
    }
}

/// Why an option of this name could not be named where options are (`variant(v, a | b)`,
/// a choice's arm `a | b: ...`, `_: ...`), if so.
fn unnameable(name: &str) -> Option<&'static str> {
    if name.contains('|') {
        Some("contain `|`, which separates options (`a | b`)")
    } else if name.is_empty() || name.trim() != name {
        Some("be empty or begin or end with blanks: where options are named (`a | b`) each name is trimmed")
    } else if name == "_" {
        Some("be `_`, which stands for every option an arm of a choice does not name")
    } else {
        None
    }
}
