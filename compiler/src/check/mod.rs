//! Checks, each a named stage: `declarations`, `shaders` (naga parse + validate),
//! `entry-points`, `bindings` (+ parameter blocks), `stage-io`, `limits`, then per
//! configuration `variants` and `graph` while planning.

pub mod bindings;
mod constants;
pub mod data;
pub mod declarations;
pub mod entry;
pub mod io;
pub mod limits;
mod reflect_facts;
pub mod scene;

use crate::abi::FrameField;
use crate::diag::Diagnostics;
use crate::ir::*;
use crate::layout::BindSource;
use crate::profile::{Feature, Profile};
use crate::shader::{ShaderLoader, ShaderModule};
use crate::span::{SourceMap, Spanned};
use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

/// `(variant, option)`.
type VariantChoice = (String, String);

/// One stage of one version of a pass, resolved to a validated module and entry point.
#[derive(Clone)]
pub struct StageShader {
    pub stage: Stage,
    pub sref: ShaderRef,
    pub module: Arc<ShaderModule>,
    pub entry: usize,
}

/// A pass with a particular set of shaders: its own, or those a variant option substitutes.
pub struct PassVersion {
    /// `Some((variant, option))` when a variant option substitutes this pass's shader.
    pub option: Option<(String, String)>,
    pub stages: Vec<StageShader>,
    pub resolved: bindings::Resolved,
    /// Fields of the frame block its entry points read, through every function they call
    /// (reflection, worked out once here rather than for every Plan).
    pub frame_fields: BTreeSet<FrameField>,
    /// Per declared resource bound as a buffer, the scalar kinds of the globals bound to it
    /// (what its 32-bit words hold).
    pub buffer_scalars: BTreeMap<String, BTreeSet<naga::ScalarKind>>,
    /// The compute entry point's workgroup size (a compute pass).
    pub workgroup_size: Option<[u32; 3]>,
}

/// A pipeline whose passes have been checked; versions that failed are absent.
pub struct Checked {
    pub pipeline: Pipeline,
    /// Index-aligned with `pipeline.resources`: written by shadow-caster passes only
    /// (`Pipeline::written_by_casters_only`, asked once rather than per configuration).
    pub casters_only: Vec<bool>,
    /// Index-aligned with `pipeline.passes`.
    pub versions: Vec<Vec<PassVersion>>,
    /// Resources' initial content, decoded (`data:`).
    pub data: data::ResourceData,
}

impl Checked {
    pub fn version(&self, pass: usize, selection: &BTreeMap<String, String>) -> Option<&PassVersion> {
        let vs = &self.versions[pass];
        vs.iter()
            .find(|v| v.option.as_ref().is_some_and(|(var, opt)| selection.get(var) == Some(opt)))
            .or_else(|| vs.iter().find(|v| v.option.is_none()))
    }
}

/// Variant options a pass's condition mentions; their requirements apply to its shaders.
fn variant_atoms(c: &Condition, out: &mut Vec<(String, String)>) {
    match c {
        Condition::Variant(v, o) => out.push((v.value.clone(), o.value.clone())),
        Condition::Not(c) | Condition::Named(_, c) => variant_atoms(c, out),
        Condition::All(cs) | Condition::Any(cs) => cs.iter().for_each(|c| variant_atoms(c, out)),
        _ => {}
    }
}

fn option_features(p: &Pipeline, var: &str, opt: &str) -> Vec<Feature> {
    p.variant(var)
        .and_then(|v| v.option(opt))
        .map(|o| o.requires.iter().map(|f| f.value).collect())
        .unwrap_or_default()
}

pub fn check_pipeline(
    pipeline: Pipeline,
    profile: &Profile,
    loader: &mut ShaderLoader,
    sources: &mut SourceMap,
    diags: &mut Diagnostics,
) -> Checked {
    declarations::check(&pipeline, profile, diags);
    // Every module the passes will load, compiled ahead on all cores; the checks below then
    // find them in the module cache, and report in file order what failed.
    loader.prewarm(sources, &stage_requests(&pipeline, profile));
    // Loading takes the source map; the checks of each version are independent and run on
    // all cores, each into its own diagnostics, merged in pass order (as a serial run).
    let loaded: Vec<Vec<Loaded>> = pipeline
        .passes
        .iter()
        .map(|pass| load_versions(&pipeline, pass, profile, loader, sources))
        .collect();
    let versions = checked_versions(&pipeline, profile, loaded, diags);
    Checked {
        casters_only: pipeline.resources.iter().map(|r| pipeline.written_by_casters_only(r)).collect(),
        pipeline,
        versions,
        data: Default::default(),
    }
}

/// Only each pass's shaders (parse, validation, entry points): what can be checked of a
/// pipeline some of whose values did not lower.
pub fn check_shaders(p: &Pipeline, profile: &Profile, loader: &mut ShaderLoader, sources: &mut SourceMap, diags: &mut Diagnostics) {
    for pass in &p.passes {
        load_stages(pass, None, &profile.features, loader, sources, diags);
    }
}

/// The pass's own shaders, then each substitution a variant option makes.
fn wanted_versions(p: &Pipeline, pass: &Pass) -> Vec<(Option<VariantChoice>, Option<Spanned<String>>)> {
    let mut wanted = vec![(None, None)];
    for v in &p.variants {
        for o in &v.options {
            for (target, file) in &o.shaders {
                if target.value == pass.name.value {
                    wanted.push((Some((v.name.value.clone(), o.name.value.clone())), Some(file.clone())));
                }
            }
        }
    }
    wanted
}

/// The features a pass's shaders are checked with: the profile's, and the requirements of
/// the variant options its condition mentions.
fn pass_features(p: &Pipeline, pass: &Pass, profile: &Profile) -> BTreeSet<Feature> {
    let mut features: BTreeSet<Feature> = profile.features.clone();
    let mut atoms = vec![];
    if let Some(w) = &pass.when {
        variant_atoms(w, &mut atoms);
    }
    for (v, o) in &atoms {
        features.extend(option_features(p, v, o));
    }
    features
}

/// Every (shader file, features) `pass_versions` will load, for `ShaderLoader::prewarm`.
fn stage_requests(p: &Pipeline, profile: &Profile) -> Vec<(Spanned<String>, BTreeSet<Feature>)> {
    let mut out = vec![];
    for pass in &p.passes {
        let features = pass_features(p, pass, profile);
        for (option, file) in wanted_versions(p, pass) {
            let mut feats = features.clone();
            if let Some((v, o)) = &option {
                feats.extend(option_features(p, v, o));
            }
            for (_, sref) in pass.stages() {
                let f = file.as_ref().filter(|_| sref.file.value != FULLSCREEN_FILE).unwrap_or(&sref.file);
                out.push((f.clone(), feats.clone()));
            }
        }
    }
    out
}

/// A version of a pass with its stages loaded (`None`: one failed) and what loading said.
struct Loaded {
    option: Option<VariantChoice>,
    stages: Option<Vec<StageShader>>,
    diags: Diagnostics,
}

/// Load the stages of every version of a pass.
fn load_versions(p: &Pipeline, pass: &Pass, profile: &Profile, loader: &mut ShaderLoader, sources: &mut SourceMap) -> Vec<Loaded> {
    let features = pass_features(p, pass, profile);
    let mut out = vec![];
    for (option, file) in wanted_versions(p, pass) {
        let mut feats = features.clone();
        if let Some((v, o)) = &option {
            feats.extend(option_features(p, v, o));
        }
        let mut diags = Diagnostics::default();
        let stages = load_stages(pass, file.as_ref(), &feats, loader, sources, &mut diags);
        out.push(Loaded { option, stages, diags });
    }
    out
}

/// Check every loaded version of every pass; versions whose shaders fail are left out.
fn checked_versions(p: &Pipeline, profile: &Profile, loaded: Vec<Vec<Loaded>>, diags: &mut Diagnostics) -> Vec<Vec<PassVersion>> {
    use rayon::prelude::*;
    let jobs: Vec<(usize, Loaded)> = loaded
        .into_iter()
        .enumerate()
        .flat_map(|(i, versions)| versions.into_iter().map(move |l| (i, l)))
        .collect();
    let done: Vec<(usize, Diagnostics, Option<PassVersion>)> = jobs
        .into_par_iter()
        .map(|(i, Loaded { option, stages, mut diags })| {
            let version = stages.and_then(|stages| check_version(p, &p.passes[i], option, stages, profile, &mut diags));
            (i, diags, version)
        })
        .collect();
    let mut versions: Vec<Vec<PassVersion>> = p.passes.iter().map(|_| vec![]).collect();
    for (i, d, version) in done {
        diags.extend(d.list);
        versions[i].extend(version);
    }
    versions
}

/// Check one version of a pass whose stages loaded.
fn check_version(
    p: &Pipeline,
    pass: &Pass,
    option: Option<VariantChoice>,
    stages: Vec<StageShader>,
    profile: &Profile,
    diags: &mut Diagnostics,
) -> Option<PassVersion> {
    io::check(p, pass, &stages, diags);
    constants::check(p, pass, &stages, diags);
    let resolved = bindings::resolve(p, pass, &stages, profile, diags)?;
    limits::check(p, pass, &stages, &resolved, profile, diags);
    let frame_fields = frame_fields(&stages, &resolved);
    let buffer_scalars = reflect_facts::buffer_scalars(&stages, &resolved);
    let workgroup_size = stages
        .iter()
        .find(|s| s.stage == Stage::Compute)
        .map(|s| s.module.module.entry_points[s.entry].workgroup_size);
    Some(PassVersion {
        option,
        stages,
        resolved,
        frame_fields,
        buffer_scalars,
        workgroup_size,
    })
}

/// The frame-block fields a pass version's entry points read (of every stage), by the bytes
/// they read.
fn frame_fields(stages: &[StageShader], resolved: &bindings::Resolved) -> BTreeSet<FrameField> {
    let frame = resolved
        .groups
        .iter()
        .flat_map(|g| &g.entries)
        .filter(|e| matches!(e.source, BindSource::Frame));
    let mut fields = BTreeSet::new();
    for e in frame {
        for st in stages {
            let m = &st.module.module;
            if let Some((h, _)) = m.global_variables.iter().find(|(_, g)| g.name.as_deref() == Some(e.name.as_str())) {
                let read = crate::shader::reflect::members_read(m, st.entry, h);
                fields.extend(read.into_iter().flat_map(|(at, n)| FrameField::overlapping(at, n)));
            }
        }
    }
    fields
}

/// Load and resolve each stage's module and entry point, with `file` substituted for the
/// pass's own shader (GLSL modules have one entry point, `main`; WGSL keeps the pass's names).
fn load_stages(
    pass: &Pass,
    file: Option<&Spanned<String>>,
    features: &BTreeSet<Feature>,
    loader: &mut ShaderLoader,
    sources: &mut SourceMap,
    diags: &mut Diagnostics,
) -> Option<Vec<StageShader>> {
    let mut stages = vec![];
    let mut ok = true;
    for (stage, mut sref) in pass.stages() {
        if let Some(f) = file.filter(|_| sref.file.value != FULLSCREEN_FILE) {
            sref.file = f.clone();
            let entry = if is_glsl(&f.value) {
                "main".to_string()
            } else {
                sref.entry.value.clone()
            };
            sref.entry = Spanned::new(entry, f.span);
        }
        let Some(module) = loader.load(sources, &sref.file, features, diags) else {
            ok = false;
            continue;
        };
        match entry::resolve(&module, &sref, stage, pass.kind.word(), diags) {
            Some(e) => stages.push(StageShader {
                stage,
                sref,
                module,
                entry: e,
            }),
            None => ok = false,
        }
    }
    ok.then_some(stages)
}
