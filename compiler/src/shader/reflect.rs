//! Reflection over a validated naga module: resource globals, entry points, stage IO.

use super::ShaderModule;
pub use crate::layout::ShaderDim;
use naga::{AddressSpace, Binding, Handle, ImageClass, ImageDimension, TypeInner};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TexKind {
    Float,
    Uint,
    Sint,
    Depth,
}

#[derive(Clone, Debug, PartialEq)]
pub enum BindingTy {
    Texture {
        kind: TexKind,
        dim: ShaderDim,
        multisampled: bool,
    },
    StorageTexture {
        format: naga::StorageFormat,
        write: bool,
        read: bool,
        dim: ShaderDim,
    },
    Sampler {
        comparison: bool,
    },
    Uniform {
        ty: Handle<naga::Type>,
        size: u32,
    },
    Storage {
        read_only: bool,
        size: u32,
    },
    /// `acceleration_structure`: the scene's ray-tracing acceleration structure.
    AccelerationStructure,
    Unsupported,
}

#[derive(Clone, Debug)]
pub struct GlobalBinding {
    pub handle: Handle<naga::GlobalVariable>,
    pub name: String,
    pub group: u32,
    pub binding: u32,
    pub ty: BindingTy,
    /// The WGSL spelling of the type, for messages.
    pub type_name: String,
}

pub fn type_name(m: &naga::Module, ty: Handle<naga::Type>) -> String {
    use naga::common::wgsl::TypeContext;
    m.types.type_to_string(ty)
}

fn dim(d: ImageDimension, arrayed: bool) -> ShaderDim {
    match (d, arrayed) {
        (ImageDimension::D1, _) => ShaderDim::D1,
        (ImageDimension::D2, false) => ShaderDim::D2,
        (ImageDimension::D2, true) => ShaderDim::D2Array,
        (ImageDimension::Cube, false) => ShaderDim::Cube,
        (ImageDimension::Cube, true) => ShaderDim::CubeArray,
        (ImageDimension::D3, _) => ShaderDim::D3,
    }
}

/// Every global with a `@group/@binding` (computed once per module: see `ShaderModule::globals`).
pub fn resource_globals_of(m: &naga::Module, layouter: &naga::proc::Layouter) -> Vec<GlobalBinding> {
    let mut out = vec![];
    for (h, g) in m.global_variables.iter() {
        let Some(rb) = &g.binding else { continue };
        let inner = &m.types[g.ty].inner;
        let size = |ty| layouter[ty].size;
        let ty = match (g.space, inner) {
            (AddressSpace::Uniform, _) => BindingTy::Uniform {
                ty: g.ty,
                size: size(g.ty),
            },
            (AddressSpace::Storage { access }, _) => BindingTy::Storage {
                read_only: !access.contains(naga::StorageAccess::STORE),
                size: size(g.ty),
            },
            (AddressSpace::Handle, TypeInner::Image { dim: d, arrayed, class }) => match class {
                ImageClass::Sampled { kind, multi } => BindingTy::Texture {
                    kind: match kind {
                        naga::ScalarKind::Uint => TexKind::Uint,
                        naga::ScalarKind::Sint => TexKind::Sint,
                        _ => TexKind::Float,
                    },
                    dim: dim(*d, *arrayed),
                    multisampled: *multi,
                },
                ImageClass::Depth { multi } => BindingTy::Texture {
                    kind: TexKind::Depth,
                    dim: dim(*d, *arrayed),
                    multisampled: *multi,
                },
                ImageClass::Storage { format, access } => BindingTy::StorageTexture {
                    format: *format,
                    write: access.contains(naga::StorageAccess::STORE),
                    read: access.contains(naga::StorageAccess::LOAD),
                    dim: dim(*d, *arrayed),
                },
                ImageClass::External => BindingTy::Unsupported,
            },
            (AddressSpace::Handle, TypeInner::Sampler { comparison }) => BindingTy::Sampler { comparison: *comparison },
            (AddressSpace::Handle, TypeInner::AccelerationStructure { vertex_return: false }) => BindingTy::AccelerationStructure,
            _ => BindingTy::Unsupported,
        };
        out.push(GlobalBinding {
            handle: h,
            name: g.name.clone().unwrap_or_else(|| format!("<global {}>", h.index())),
            group: rb.group,
            binding: rb.binding,
            ty,
            type_name: type_name(m, g.ty),
        });
    }
    out
}

pub fn find_entry(sm: &ShaderModule, name: &str) -> Option<usize> {
    sm.module.entry_points.iter().position(|e| e.name == name)
}

pub fn used_by(sm: &ShaderModule, ep: usize, h: Handle<naga::GlobalVariable>) -> bool {
    !sm.info.get_entry_point(ep)[h].is_empty()
}

/// (texture, sampler) pairs an entry point samples with, including through helper calls.
pub fn sampling_pairs(sm: &ShaderModule, ep: usize) -> Vec<(Handle<naga::GlobalVariable>, Handle<naga::GlobalVariable>)> {
    let mut pairs: Vec<_> = sm
        .info
        .get_entry_point(ep)
        .sampling_set
        .iter()
        .map(|k| (k.image, k.sampler))
        .collect();
    pairs.sort_by_key(|(a, b)| (a.index(), b.index()));
    pairs
}

#[derive(Clone, Debug, PartialEq)]
pub struct IoVar {
    pub location: u32,
    /// `@blend_src(i)` of a dual-source fragment output.
    pub blend_src: Option<u32>,
    pub scalar: naga::ScalarKind,
    pub components: u32,
    pub name: String,
}

fn io_of(m: &naga::Module, ty: Handle<naga::Type>, binding: Option<&Binding>, name: Option<&str>, out: &mut Vec<IoVar>) {
    match (&m.types[ty].inner, binding) {
        (TypeInner::Struct { members, .. }, None) => {
            for mem in members {
                io_of(m, mem.ty, mem.binding.as_ref(), mem.name.as_deref(), out);
            }
        }
        (inner, Some(Binding::Location { location, blend_src, .. })) => {
            let (scalar, components) = match inner {
                TypeInner::Scalar(s) => (s.kind, 1),
                TypeInner::Vector { size, scalar } => (scalar.kind, *size as u32),
                _ => (naga::ScalarKind::Float, 4),
            };
            out.push(IoVar {
                location: *location,
                blend_src: *blend_src,
                scalar,
                components,
                name: name.unwrap_or("").to_string(),
            });
        }
        _ => {}
    }
}

/// Location outputs of an entry point, sorted by location.
pub fn outputs(sm: &ShaderModule, ep: usize) -> Vec<IoVar> {
    let f = &sm.module.entry_points[ep].function;
    let mut out = vec![];
    if let Some(r) = &f.result {
        io_of(&sm.module, r.ty, r.binding.as_ref(), None, &mut out);
    }
    out.sort_by_key(|v| v.location);
    out
}

/// Location inputs of an entry point, sorted by location.
pub fn inputs(sm: &ShaderModule, ep: usize) -> Vec<IoVar> {
    let f = &sm.module.entry_points[ep].function;
    let mut out = vec![];
    for a in &f.arguments {
        io_of(&sm.module, a.ty, a.binding.as_ref(), a.name.as_deref(), &mut out);
    }
    out.sort_by_key(|v| v.location);
    out
}

/// The bytes (offset, size) of the members of struct global `global` that entry point `entry`
/// reads, through every function it calls; every member when the struct is loaded whole. (A
/// uniform struct can only be reached by member access or a whole load: WGSL passes no
/// pointers to uniform memory into functions.)
pub fn members_read(m: &naga::Module, entry: usize, global: Handle<naga::GlobalVariable>) -> Vec<(usize, usize)> {
    let mut functions = vec![&m.entry_points[entry].function];
    let mut seen = std::collections::BTreeSet::new();
    let mut used = std::collections::BTreeSet::new();
    let mut whole = false;
    while let Some(f) = functions.pop() {
        let is_global = |h: Handle<naga::Expression>| matches!(f.expressions[h], naga::Expression::GlobalVariable(g) if g == global);
        for (_, e) in f.expressions.iter() {
            match *e {
                naga::Expression::AccessIndex { base, index } if is_global(base) => {
                    used.insert(index);
                }
                naga::Expression::Load { pointer } if is_global(pointer) => whole = true,
                _ => {}
            }
        }
        let mut calls = vec![];
        called(&f.body, &mut calls);
        for c in calls {
            if seen.insert(c) {
                functions.push(&m.functions[c]);
            }
        }
    }
    let ty = &m.types[m.global_variables[global].ty].inner;
    let TypeInner::Struct { members, span } = ty else {
        return Default::default();
    };
    let ends = members.iter().skip(1).map(|mem| mem.offset).chain([*span]);
    members
        .iter()
        .zip(ends)
        .enumerate()
        .filter(|(i, _)| whole || used.contains(&(*i as u32)))
        .map(|(_, (mem, end))| {
            // Its type's size, padding after it left out (never past the next member).
            let size = m.types[mem.ty].inner.size(m.to_ctx()).min(end.saturating_sub(mem.offset));
            (mem.offset as usize, size as usize)
        })
        .collect()
}

/// Functions a block calls, directly or in nested blocks.
pub(crate) fn called(b: &naga::Block, out: &mut Vec<Handle<naga::Function>>) {
    statements(b, &mut |s, _| {
        if let naga::Statement::Call { function, .. } = s {
            out.push(*function);
        }
    });
}

/// Every statement of a block and of the blocks nested in it, with its span.
pub(crate) fn statements(b: &naga::Block, visit: &mut impl FnMut(&naga::Statement, &naga::Span)) {
    use naga::Statement as S;
    for (s, span) in b.span_iter() {
        visit(s, span);
        match s {
            S::Block(inner) => statements(inner, visit),
            S::If { accept, reject, .. } => {
                statements(accept, visit);
                statements(reject, visit);
            }
            S::Switch { cases, .. } => cases.iter().for_each(|c| statements(&c.body, visit)),
            S::Loop { body, continuing, .. } => {
                statements(body, visit);
                statements(continuing, visit);
            }
            _ => {}
        }
    }
}
