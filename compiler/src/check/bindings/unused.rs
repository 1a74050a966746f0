//! Sub-stage `unused`: declared reads no entry point uses, and parameters for a pass whose
//! shaders have no parameter block (warnings: the pipeline still runs).

use super::Ctx;
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::{history_ident, shader_ident};

impl Ctx<'_> {
    pub(super) fn warn_unused(&self, diags: &mut Diagnostics) {
        let pass = self.pass;
        for r in &pass.reads {
            if self.used_reads.contains(&r.name().value) || self.p.resource(r.name()).is_none() {
                continue;
            }
            let ident = if r.is_prev() {
                history_ident(r.name())
            } else {
                shader_ident(r.name())
            };
            diags.push(
                Diagnostic::warning(
                    Code::UnusedRead,
                    format!("pass `{}` reads `{}` but no entry point uses it", pass.name.value, r.name().value),
                    r.name().span,
                )
                .with_note(format!("the shader would bind it as `{ident}`")),
            );
        }
        if let (Some((first, _)), false) = (pass.values.first(), self.params_used) {
            // Unlike unused parameters, a value with nowhere to go is a mistake: error.
            diags.push(Diagnostic::error(
                Code::ValueField,
                format!(
                    "pass `{}` sets `values` but its shaders use no `{}` block",
                    pass.name.value, pass.param_block.value
                ),
                first.span,
            ));
        }
        if let (Some(first), Some(last)) = (pass.params.first(), pass.params.last()) {
            if !self.params_used {
                diags.push(Diagnostic::warning(
                    Code::UnusedParams,
                    format!(
                        "pass `{}` declares parameters but its shaders use no `{}` block",
                        pass.name.value, pass.param_block.value
                    ),
                    first.span.to(last.span),
                ));
            }
        }
    }
}
