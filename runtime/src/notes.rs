//! What a command says once about a Plan before rendering with it: the effects it could run
//! that the scene does not call for (and the flag that asks for them), and those the scene
//! calls for that no kept pass serves.

/// What a command says once about a Plan's effects: those the pipeline serves that the scene
/// does not call for, and how to ask for them (a model rendered on its own otherwise silently
/// does no GI); and those the scene calls for that no kept pass serves, with why.
pub fn effect_notes(plan: &lightbench_compiler::plan::Plan) -> Vec<String> {
    let unserved = plan.unserved_effects.iter().map(|u| {
        format!(
            "note: {}: the scene `{}` calls for {}, but every pass serving it is culled: `{}` {}",
            plan.pipeline,
            plan.scene,
            u.effect.name(),
            u.pass,
            u.reason
        )
    });
    uncalled_effects_note(plan).into_iter().chain(unserved).collect()
}

fn uncalled_effects_note(plan: &lightbench_compiler::plan::Plan) -> Option<String> {
    if plan.uncalled_effects.is_empty() {
        return None;
    }
    let names: Vec<&str> = plan.uncalled_effects.iter().map(|e| e.name()).collect();
    let flags: Vec<String> = names.iter().map(|n| format!("--effect {n}")).collect();
    Some(format!(
        "note: {}: the passes for {} are culled: the scene `{}` does not call for {}; add {} to run them",
        plan.pipeline,
        names.join(", "),
        plan.scene,
        if names.len() == 1 { "it" } else { "them" },
        flags.join(" ")
    ))
}
