//! Stage `entry-points`: each stage a pass needs names an entry point of the right stage.

use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics};
use crate::ir::{naga_stage_word, ShaderRef, Stage};
use crate::shader::{reflect, ShaderModule};

/// The index of the entry point, or a diagnostic at the reference.
pub fn resolve(sm: &ShaderModule, sref: &ShaderRef, stage: Stage, pass_kind: &str, diags: &mut Diagnostics) -> Option<usize> {
    match reflect::find_entry(sm, &sref.entry) {
        None => {
            let names: Vec<&str> = sm
                .module
                .entry_points
                .iter()
                .filter(|e| e.stage == stage.naga())
                .map(|e| e.name.as_str())
                .collect();
            let all: Vec<&str> = sm.module.entry_points.iter().map(|e| e.name.as_str()).collect();
            diags.push(
                Diagnostic::error(
                    Code::MissingEntryPoint,
                    format!("shader `{}` has no entry point `{}`", sref.file.value, sref.entry.value),
                    sref.entry.span,
                )
                .with_note(if names.is_empty() {
                    format!(
                        "it has no {} entry point at all (entry points: {})",
                        stage.word(),
                        if all.is_empty() { "none".into() } else { all.join(", ") }
                    )
                } else {
                    suggestion_note(&sref.entry, &names)
                }),
            );
            None
        }
        Some(i) => {
            let ep = &sm.module.entry_points[i];
            if ep.stage != stage.naga() {
                diags.push(
                    Diagnostic::error(
                        Code::WrongStage,
                        format!(
                            "`{}` is a {} entry point, but this {pass_kind} pass needs a {} one here",
                            sref.entry.value,
                            naga_stage_word(ep.stage),
                            stage.word()
                        ),
                        sref.entry.span,
                    )
                    .with_secondary(
                        sm.entry_span(i),
                        format!("`{}` is declared with @{}", ep.name, naga_stage_word(ep.stage)),
                    ),
                );
                return None;
            }
            Some(i)
        }
    }
}
