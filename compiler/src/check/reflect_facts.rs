//! Stage `shaders` (facts for the planner): what a pass version's modules say about the
//! resources it binds, worked out once per version so that planning reads no naga module.

use super::bindings::Resolved;
use super::StageShader;
use crate::layout::BindSource;
use std::collections::{BTreeMap, BTreeSet};

/// Per declared resource a version binds, the scalar kinds of every shader global bound to it.
pub(super) fn buffer_scalars(stages: &[StageShader], resolved: &Resolved) -> BTreeMap<String, BTreeSet<naga::ScalarKind>> {
    let mut out: BTreeMap<String, BTreeSet<naga::ScalarKind>> = BTreeMap::new();
    for g in &resolved.groups {
        for e in &g.entries {
            let BindSource::Resource(name) = &e.source else { continue };
            for st in stages {
                let m = &st.module.module;
                let bound = |b: &naga::ResourceBinding| b.group == g.group && b.binding == e.binding;
                if let Some((_, v)) = m.global_variables.iter().find(|(_, v)| v.binding.as_ref().is_some_and(bound)) {
                    leaf_kinds(m, v.ty, out.entry(name.clone()).or_default());
                }
            }
        }
    }
    out
}

fn leaf_kinds(m: &naga::Module, ty: naga::Handle<naga::Type>, out: &mut BTreeSet<naga::ScalarKind>) {
    use naga::TypeInner as T;
    match &m.types[ty].inner {
        T::Scalar(s) | T::Vector { scalar: s, .. } | T::Matrix { scalar: s, .. } | T::Atomic(s) => {
            out.insert(s.kind);
        }
        T::Array { base, .. } | T::BindingArray { base, .. } => leaf_kinds(m, *base, out),
        T::Struct { members, .. } => members.iter().for_each(|mem| leaf_kinds(m, mem.ty, out)),
        _ => {
            out.insert(naga::ScalarKind::Float);
        }
    }
}
