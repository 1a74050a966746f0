//! Unique names: declarations of one kind, variant options, and the keys of the small maps
//! inside passes and options (`bind`, `limits`, `shaders`). The IR keeps duplicates as
//! written so that they are reported here, once for every front end.

use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::Pipeline;
use crate::span::Spanned;

fn duplicates<'a>(what: &str, names: impl IntoIterator<Item = &'a Spanned<String>>, diags: &mut Diagnostics) {
    // By hash: a file of tens of thousands of parameters is checked in linear time.
    let mut seen: std::collections::HashMap<&str, &Spanned<String>> = Default::default();
    for n in names {
        match seen.get(n.value.as_str()) {
            Some(first) => diags.push(
                Diagnostic::error(Code::DuplicateName, format!("{what} `{}` is declared twice", n.value), n.span)
                    .with_secondary(first.span, "first declared here"),
            ),
            None => {
                seen.insert(&n.value, n);
            }
        }
    }
}

pub(super) fn check(p: &Pipeline, diags: &mut Diagnostics) {
    duplicates("parameter", p.params.iter().map(|x| &x.name), diags);
    duplicates("sampler", p.samplers.iter().map(|x| &x.name), diags);
    duplicates("resource", p.resources.iter().map(|x| &x.name), diags);
    // The copies of a pass written with choices share its name.
    duplicates("pass", p.written_passes().map(|x| &x.name), diags);
    duplicates("variant", p.variants.iter().map(|x| &x.name), diags);
    for v in &p.variants {
        duplicates("variant option", v.options.iter().map(|o| &o.name), diags);
        for o in &v.options {
            duplicates("limit", o.limits.iter().map(|(k, _)| k), diags);
            duplicates("shader substitution", o.shaders.iter().map(|(k, _)| k), diags);
        }
    }
    for pass in &p.passes {
        duplicates("binding", pass.bind.iter().map(|(k, _)| k), diags);
    }
}
