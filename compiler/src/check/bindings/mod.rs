//! Stage `bindings`: every shader global an entry point uses is satisfied by a declared
//! read, write, sampler, parameter block or a standard runtime block, with a compatible
//! type. Produces the pass's bind group layouts and parameter-block layouts.
//!
//! Sub-stages: `gather` (globals the entry points use, across stages), `classify` (what each
//! binds to), `types` (resource type compatibility), `param_block` (block fields against the
//! pass's parameters), `unused` (declared reads and parameters no shader uses).

mod classify;
mod gather;
mod param_block;
mod types;
mod unused;

use super::StageShader;
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::{Pass, Pipeline, Stage};
use crate::layout::{BindGroupLayout, BindSource, Binding, BindingType, UniformBlock};
use crate::profile::Profile;
use crate::shader::reflect::GlobalBinding;
use crate::span::Spanned;
use std::collections::BTreeMap;

/// Layouts while checking name resources and samplers by their declared names.
pub type NamedGroup = BindGroupLayout<String, String>;
pub type NamedBinding = Binding<String, String>;
pub type NamedSource = BindSource<String, String>;

pub struct Resolved {
    pub groups: Vec<NamedGroup>,
    pub uniform_blocks: Vec<UniformBlock>,
    /// Per stage: counts for limit checks.
    pub per_stage: BTreeMap<Stage, StageCounts>,
}

#[derive(Default, Clone, Copy)]
pub struct StageCounts {
    pub sampled_textures: u64,
    pub samplers: u64,
    pub storage_textures: u64,
    pub uniform_buffers: u64,
    pub storage_buffers: u64,
}

/// A global some entry point of the pass uses, with the stages that use it.
pub(crate) struct Used<'a> {
    pub g: GlobalBinding,
    pub stage: &'a StageShader,
    pub stages: Vec<Stage>,
}

/// What resolving one pass builds up.
struct Ctx<'a> {
    p: &'a Pipeline,
    pass: &'a Pass,
    profile: &'a Profile,
    /// `bind: {...}`: shader global -> declared name.
    explicit: BTreeMap<&'a str, &'a Spanned<String>>,
    /// (texture global, sampler global) pairs the entry points sample with.
    sampled_with: Vec<(String, String)>,
    groups: BTreeMap<u32, Vec<NamedBinding>>,
    uniform_blocks: Vec<UniformBlock>,
    per_stage: BTreeMap<Stage, StageCounts>,
    used_reads: Vec<String>,
    params_used: bool,
}

impl Ctx<'_> {
    fn push(&mut self, g: &GlobalBinding, source: NamedSource, ty: BindingType, stages: &[Stage]) {
        let mut visibility = stages.to_vec();
        visibility.sort();
        self.groups.entry(g.group).or_default().push(Binding {
            binding: g.binding,
            name: g.name.clone(),
            source,
            ty,
            visibility,
        });
    }

    fn count(&mut self, stages: &[Stage], f: impl Fn(&mut StageCounts)) {
        for s in stages {
            f(self.per_stage.entry(*s).or_default());
        }
    }
}

pub fn resolve(p: &Pipeline, pass: &Pass, stages: &[StageShader], profile: &Profile, diags: &mut Diagnostics) -> Option<Resolved> {
    let before = diags.error_count();
    let used = gather::used_globals(stages, diags);
    let mut cx = Ctx {
        p,
        pass,
        profile,
        explicit: pass.bind.iter().map(|(k, v)| (k.value.as_str(), v)).collect(),
        sampled_with: gather::sampling_pairs(stages),
        groups: BTreeMap::new(),
        uniform_blocks: vec![],
        per_stage: BTreeMap::new(),
        used_reads: vec![],
        params_used: false,
    };
    for u in used.values() {
        cx.bind(u, diags);
    }
    for u in used.values() {
        if matches!(u.g.ty, crate::shader::reflect::BindingTy::Uniform { .. }) {
            cx.count(&u.stages, |c| c.uniform_buffers += 1);
        }
    }
    cx.warn_unused(diags);
    let groups: Vec<NamedGroup> = std::mem::take(&mut cx.groups)
        .into_iter()
        .map(|(group, mut entries)| {
            entries.sort_by_key(|e| e.binding);
            BindGroupLayout { group, entries }
        })
        .collect();
    per_draw_groups_alone(&groups, &used, diags);
    if diags.error_count() > before {
        return None;
    }
    Some(Resolved {
        groups,
        uniform_blocks: cx.uniform_blocks,
        per_stage: cx.per_stage,
    })
}

/// The runtime binds per-draw slots once per mesh: their group may hold nothing else.
fn per_draw_groups_alone(groups: &[NamedGroup], used: &BTreeMap<(u32, u32), Used>, diags: &mut Diagnostics) {
    for g in groups {
        let per_draw = g.entries.iter().filter(|e| matches!(e.source, BindSource::Draw(_))).count();
        if per_draw > 0 && per_draw < g.entries.len() {
            let other = g.entries.iter().find(|e| !matches!(e.source, BindSource::Draw(_)));
            let span = other
                .and_then(|e| used.get(&(g.group, e.binding)))
                .map(|u| u.stage.module.global_span(u.g.handle));
            if let Some(span) = span {
                diags.push(
                    Diagnostic::error(
                        Code::BindingType,
                        format!("@group({}) mixes per-draw bindings with others", g.group),
                        span,
                    )
                    .with_note("keep the per-draw slots (`mesh`, `material`, the material maps and sampler) in a group of their own"),
                );
            }
        }
    }
}
