//! Stage `entry-points`: each stage a pass needs names an entry point of the right stage.

use crate::diag::{suggestion_note, Diagnostic, Diagnostics};
use crate::ir::ShaderRef;
use crate::shader::{reflect, ShaderModule};

pub fn stage_word(s: naga::ShaderStage) -> &'static str {
    match s {
        naga::ShaderStage::Vertex => "vertex",
        naga::ShaderStage::Fragment => "fragment",
        naga::ShaderStage::Compute => "compute",
        _ => "mesh/task",
    }
}

/// The index of the entry point, or a diagnostic at the reference.
pub fn resolve(sm: &ShaderModule, sref: &ShaderRef, stage: naga::ShaderStage, pass_kind: &str, diags: &mut Diagnostics) -> Option<usize> {
    match reflect::find_entry(sm, &sref.entry) {
        None => {
            let names: Vec<&str> = sm
                .module
                .entry_points
                .iter()
                .filter(|e| e.stage == stage)
                .map(|e| e.name.as_str())
                .collect();
            let all: Vec<&str> = sm.module.entry_points.iter().map(|e| e.name.as_str()).collect();
            diags.push(
                Diagnostic::error(
                    "missing-entry-point",
                    format!("shader `{}` has no entry point `{}`", sref.file.value, sref.entry.value),
                    sref.entry.span,
                )
                .with_note(if names.is_empty() {
                    format!(
                        "it has no {} entry point at all (entry points: {})",
                        stage_word(stage),
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
            if ep.stage != stage {
                diags.push(
                    Diagnostic::error(
                        "wrong-stage",
                        format!(
                            "`{}` is a {} entry point, but this {pass_kind} pass needs a {} one here",
                            sref.entry.value,
                            stage_word(ep.stage),
                            stage_word(stage)
                        ),
                        sref.entry.span,
                    )
                    .with_secondary(
                        sm.entry_span(i),
                        format!("`{}` is declared with @{}", ep.name, stage_word(ep.stage)),
                    ),
                );
                return None;
            }
            Some(i)
        }
    }
}
