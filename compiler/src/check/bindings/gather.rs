//! Sub-stage `gather`: the globals the pass's entry points use, across stages, and the
//! texture/sampler pairs they sample with.

use super::Used;
use crate::check::StageShader;
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::shader::reflect::{self, BindingTy};
use std::collections::BTreeMap;

/// Used globals keyed by (group, binding); two stages declaring one slot differently is an error.
pub(super) fn used_globals<'a>(stages: &'a [StageShader], diags: &mut Diagnostics) -> BTreeMap<(u32, u32), Used<'a>> {
    let mut used: BTreeMap<(u32, u32), Used> = BTreeMap::new();
    for st in stages {
        immediates(st, diags);
        for g in st.module.globals.iter().cloned() {
            if !reflect::used_by(&st.module, st.entry, g.handle) {
                continue;
            }
            match used.get_mut(&(g.group, g.binding)) {
                Some(u) if u.g.name != g.name || u.g.ty != g.ty && !both_uniform(&u.g.ty, &g.ty) => {
                    diags.push(
                        Diagnostic::error(
                            Code::BindingConflict,
                            format!(
                                "@group({}) @binding({}) is `{}` in one stage and `{}` in another",
                                g.group, g.binding, u.g.name, g.name
                            ),
                            st.module.global_span(g.handle),
                        )
                        .with_secondary(u.stage.module.global_span(u.g.handle), "other declaration"),
                    );
                }
                Some(u) => {
                    if !u.stages.contains(&st.stage) {
                        u.stages.push(st.stage)
                    }
                }
                None => {
                    used.insert(
                        (g.group, g.binding),
                        Used {
                            g,
                            stage: st,
                            stages: vec![st.stage],
                        },
                    );
                }
            }
        }
    }
    used
}

/// Immediate data (`var<immediate>`, wgpu's push constants) validates where the profile has
/// `Immediates`, but no pass sets it: the draw would fail at the GPU. Said at the variable.
fn immediates(st: &StageShader, diags: &mut Diagnostics) {
    let m = &st.module.module;
    for (h, g) in m.global_variables.iter() {
        if g.space == naga::AddressSpace::Immediate && reflect::used_by(&st.module, st.entry, h) {
            let name = g.name.clone().unwrap_or_default();
            diags.push(
                Diagnostic::error(
                    Code::BindingType,
                    format!("`{name}` is immediate data (`var<immediate>`), which no lightbench pass supplies"),
                    st.module.global_span(h),
                )
                .with_note("put the value in the pass's parameter block (`var<uniform>`, filled from `params` or `values`)"),
            );
        }
    }
}

fn both_uniform(a: &BindingTy, b: &BindingTy) -> bool {
    matches!((a, b), (BindingTy::Uniform { .. }, BindingTy::Uniform { .. }))
}

/// Which sampler each texture is sampled with, by global name (per entry point).
pub(super) fn sampling_pairs(stages: &[StageShader]) -> Vec<(String, String)> {
    let mut out = vec![];
    for st in stages {
        for (img, smp) in reflect::sampling_pairs(&st.module, st.entry) {
            let name = |h: naga::Handle<naga::GlobalVariable>| st.module.module.global_variables[h].name.clone().unwrap_or_default();
            out.push((name(img), name(smp)));
        }
    }
    out
}
