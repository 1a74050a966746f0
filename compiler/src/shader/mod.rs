//! Shaders: load (with includes), parse with naga's WGSL or GLSL 450 front end, validate,
//! and map every naga error back to the file and line it came from. Compiled modules are
//! kept in a content-hashed cache that a long-running process shares between compilations.

pub mod cache;
pub mod include;
pub mod readable;
pub mod reflect;

use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::profile::Feature;
use crate::span::{FileId, SourceMap, Span, Spanned};
use crate::vfs::Vfs;
pub use cache::{CacheStats, ModuleCache};
use include::{Expanded, ShaderFs};
use std::collections::{BTreeSet, HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use crate::ir::{is_glsl, FULLSCREEN_ENTRY, FULLSCREEN_FILE};
pub const FULLSCREEN_SOURCE: &str = include_str!("fullscreen.wgsl");

pub fn builtin_source(path: &str) -> Option<&'static str> {
    (path == FULLSCREEN_FILE).then_some(FULLSCREEN_SOURCE)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Lang {
    Wgsl,
    Glsl(#[serde(skip)] naga::ShaderStage),
}

fn lang_of(path: &str) -> Result<Lang, String> {
    let ext = Path::new(path).extension().and_then(|e| e.to_str()).unwrap_or("");
    match ext {
        "wgsl" => Ok(Lang::Wgsl),
        "vert" => Ok(Lang::Glsl(naga::ShaderStage::Vertex)),
        "frag" => Ok(Lang::Glsl(naga::ShaderStage::Fragment)),
        "comp" => Ok(Lang::Glsl(naga::ShaderStage::Compute)),
        "geom" => Err("geometry".into()),
        "glsl" => Err("a `.glsl` file does not say its stage: name GLSL 450 shaders `.vert`, `.frag` or `.comp`".into()),
        other => Err(format!(
            "unknown shader language `.{other}`: expected `.wgsl`, or GLSL 450 as `.vert`, `.frag`, `.comp`"
        )),
    }
}

/// What naga produced for a module: independent of where its text came from.
pub struct Compiled {
    pub module: naga::Module,
    pub info: naga::valid::ModuleInfo,
    /// Type layouts (size, alignment) as naga computes them for host-shareable types.
    pub layouter: naga::proc::Layouter,
    /// Resource globals, reflected once.
    pub globals: Vec<reflect::GlobalBinding>,
    /// Constant sets naga's override processing has accepted, per entry point: every
    /// configuration of a pipeline applies the same few, and each is a full validation.
    pub overrides_accepted: std::sync::Mutex<HashSet<OverrideKey>>,
}

/// An entry point and the pipeline constants applied to it (values as bits: exact).
pub type OverrideKey = (String, Vec<(String, u64)>);

/// A parsed and validated shader module, with the source map of this session.
pub struct ShaderModule {
    pub path: String,
    pub lang: Lang,
    /// Identity of the compiled module: language, capabilities and expanded source. Equal
    /// hashes mean the same naga module (the runtime keys its pipeline cache by it).
    pub hash: u64,
    pub compiled: Arc<Compiled>,
    /// The expanded source naga saw, and where each part came from.
    pub expanded: Expanded,
}

impl std::ops::Deref for ShaderModule {
    type Target = Compiled;
    fn deref(&self) -> &Compiled {
        &self.compiled
    }
}

impl ShaderModule {
    /// A span in the shader's own files for a naga span of the expanded source.
    pub fn map_span(&self, span: naga::Span) -> Option<Span> {
        span.to_range().and_then(|r| self.expanded.map(r))
    }
    pub fn root_file(&self) -> FileId {
        self.expanded.files[0]
    }
    /// Best location for a global: its declaration.
    pub fn global_span(&self, h: naga::Handle<naga::GlobalVariable>) -> Span {
        self.map_span(self.module.global_variables.get_span(h))
            .unwrap_or(Span::new(self.root_file(), 0, 0))
    }
    /// Where an entry point is declared: its `fn name` in the source (naga keeps no span on
    /// entry points; its first statement is the next best thing, then the file start).
    pub fn entry_span(&self, index: usize) -> Span {
        let ep = &self.module.entry_points[index];
        self.declaration(&ep.name)
            .or_else(|| ep.function.body.span_iter().next().and_then(|(_, s)| self.map_span(*s)))
            .unwrap_or(Span::new(self.root_file(), 0, 0))
    }

    /// The span of `fn name` (WGSL) or `void name` (GLSL) in the expanded source.
    fn declaration(&self, name: &str) -> Option<Span> {
        readable::declaration(&self.expanded.text, name).and_then(|r| self.expanded.map(r))
    }
}

/// Naga capabilities that wgpu gates behind a feature.
pub fn capabilities(features: &BTreeSet<Feature>) -> naga::valid::Capabilities {
    use naga::valid::Capabilities as C;
    let mut caps = C::default();
    for f in features {
        caps |= feature_capabilities(*f);
    }
    // Binding arrays of storage resources need both the array and the storage feature (as
    // wgpu-core derives them).
    if features.contains(&Feature::StorageResourceBindingArray) {
        if features.contains(&Feature::TextureBindingArray) {
            caps |= C::STORAGE_TEXTURE_BINDING_ARRAY;
        }
        if features.contains(&Feature::BufferBindingArray) {
            caps |= C::STORAGE_BUFFER_BINDING_ARRAY;
        }
    }
    caps
}

/// The naga capabilities one wgpu feature grants (wgpu-core's mapping).
fn feature_capabilities(f: Feature) -> naga::valid::Capabilities {
    use naga::valid::Capabilities as C;
    match f {
        Feature::Multiview => C::MULTIVIEW,
        Feature::ClipDistances => C::CLIP_DISTANCES,
        Feature::ShaderF16 => C::SHADER_FLOAT16,
        Feature::DualSourceBlending => C::DUAL_SOURCE_BLENDING,
        Feature::CubeArrayTextures => C::CUBE_ARRAY_TEXTURES,
        Feature::ShaderF64 => C::FLOAT64,
        Feature::ShaderI16 => C::SHADER_INT16,
        Feature::ShaderInt64 => C::SHADER_INT64,
        Feature::ShaderInt64AtomicMinMax => C::SHADER_INT64_ATOMIC_MIN_MAX,
        Feature::ShaderInt64AtomicAllOps => C::SHADER_INT64_ATOMIC_MIN_MAX | C::SHADER_INT64_ATOMIC_ALL_OPS,
        Feature::ShaderFloat32Atomic => C::SHADER_FLOAT32_ATOMIC,
        Feature::TextureAtomic => C::TEXTURE_ATOMIC,
        Feature::Immediates => C::IMMEDIATES,
        Feature::TextureBindingArray => C::TEXTURE_AND_SAMPLER_BINDING_ARRAY,
        Feature::BufferBindingArray => C::BUFFER_BINDING_ARRAY,
        Feature::SampledTextureAndStorageBufferArrayNonUniformIndexing => {
            C::TEXTURE_AND_SAMPLER_BINDING_ARRAY_NON_UNIFORM_INDEXING | C::STORAGE_BUFFER_BINDING_ARRAY_NON_UNIFORM_INDEXING
        }
        Feature::StorageTextureArrayNonUniformIndexing => C::STORAGE_TEXTURE_BINDING_ARRAY_NON_UNIFORM_INDEXING,
        Feature::UniformBufferBindingArrays => C::BUFFER_BINDING_ARRAY_NON_UNIFORM_INDEXING,
        Feature::ExperimentalRayQuery => C::RAY_QUERY,
        Feature::Subgroup => C::SUBGROUP,
        Feature::SubgroupVertex => C::SUBGROUP | C::SUBGROUP_VERTEX_STAGE,
        Feature::SubgroupBarrier => C::SUBGROUP_BARRIER,
        Feature::PrimitiveIndex => C::PRIMITIVE_INDEX,
        Feature::ShaderEarlyDepthTest => C::EARLY_DEPTH_TEST,
        Feature::ShaderBarycentrics => C::SHADER_BARYCENTRICS,
        Feature::TimestampQuery
        | Feature::Float32Filterable
        | Feature::DepthClipControl
        | Feature::Rg11b10UfloatRenderable
        | Feature::Float32Renderable
        | Feature::StorageResourceBindingArray
        | Feature::GeometryShader => C::empty(),
    }
}

/// Shader files under a root, read through the virtual file system. Every path read (or
/// tried) is recorded: a watcher needs the files that do not exist yet too.
pub struct RootedFs<'a> {
    pub vfs: &'a dyn Vfs,
    pub root: &'a Path,
    pub read: std::cell::RefCell<BTreeSet<PathBuf>>,
    /// What was read, by path: a library file that many shaders include is read (and its
    /// links resolved) once per batch of loads, and each of them sees the same text.
    texts: std::cell::RefCell<HashMap<String, String>>,
}

impl<'a> RootedFs<'a> {
    pub fn new(vfs: &'a dyn Vfs, root: &'a Path) -> Self {
        RootedFs {
            vfs,
            root,
            read: Default::default(),
            texts: Default::default(),
        }
    }
}

impl ShaderFs for RootedFs<'_> {
    fn read(&self, path: &str) -> std::io::Result<String> {
        if let Some(builtin) = builtin_source(path) {
            return Ok(builtin.to_string());
        }
        if let Some(text) = self.texts.borrow().get(path) {
            return Ok(text.clone());
        }
        let full = self.root.join(path);
        self.read.borrow_mut().insert(full.clone());
        // Confined after links: a link inside the root to a file outside it is not read.
        self.vfs.within(self.root, &full)?;
        let text = self.vfs.read(&full)?;
        self.texts.borrow_mut().insert(path.to_string(), text.clone());
        Ok(text)
    }
    fn display(&self, path: &str) -> String {
        if builtin_source(path).is_some() {
            return path.to_string();
        }
        self.root.join(path).display().to_string()
    }
}

/// Loads each shader once per capability set in one compilation; failures are remembered
/// so that a broken shader used by several passes is reported once.
pub struct ShaderLoader {
    pub root: PathBuf,
    vfs: Arc<dyn Vfs>,
    cache: HashMap<(String, u64), Option<Arc<ShaderModule>>>,
    compiled: Arc<ModuleCache>,
    /// Every shader and included file read (or tried).
    pub dependencies: BTreeSet<PathBuf>,
    /// Added to a `shader-not-found` error: where paths resolve, which folders were tried.
    pub not_found_note: Option<String>,
    /// The expansions of the other compilations of a run, if part of one.
    pub expansions: Option<Arc<Expansions>>,
}

impl ShaderLoader {
    pub fn new(root: PathBuf, vfs: Arc<dyn Vfs>, compiled: Arc<ModuleCache>) -> Self {
        ShaderLoader {
            root,
            vfs,
            cache: HashMap::new(),
            compiled,
            dependencies: BTreeSet::new(),
            not_found_note: None,
            expansions: None,
        }
    }

    pub fn load(
        &mut self,
        sources: &mut SourceMap,
        path: &Spanned<String>,
        features: &BTreeSet<Feature>,
        diags: &mut Diagnostics,
    ) -> Option<Arc<ShaderModule>> {
        let caps = capabilities(features);
        let key = (path.value.clone(), caps.bits());
        if let Some(hit) = self.cache.get(&key) {
            return hit.clone();
        }
        let fs = RootedFs::new(self.vfs.as_ref(), &self.root);
        let before = diags.list.len();
        let shared = self.expansions.as_deref();
        let result = load_module(&fs, sources, (path, shared), caps, &self.compiled, diags).map(Arc::new);
        if let (Some(note), Some(d)) = (&self.not_found_note, diags.list.get_mut(before)) {
            if d.code == Code::ShaderNotFound && d.primary_span() == Some(path.span) {
                d.notes.push(note.clone());
            }
        }
        self.dependencies.extend(fs.read.into_inner());
        self.cache.insert(key, result.clone());
        result
    }
}

impl ShaderLoader {
    /// Compile ahead, on all cores, the modules these loads will need, and keep them for
    /// `load` (each file is read and expanded once). Whatever fails here (an unreadable file,
    /// a parse error) is left for `load` to report, in order.
    pub fn prewarm(&mut self, sources: &mut SourceMap, requests: &[(Spanned<String>, BTreeSet<Feature>)]) {
        use rayon::prelude::*;
        let fs = RootedFs::new(self.vfs.as_ref(), &self.root);
        let mut read: Vec<Ahead> = vec![];
        for (path, features) in requests {
            let caps = capabilities(features);
            let at = (path.value.clone(), caps.bits());
            if self.cache.contains_key(&at) || read.iter().any(|r| r.at == at) {
                continue;
            }
            let shared = self.expansions.as_deref();
            let Some((lang, expanded, root, hash)) = read_hashed(&fs, sources, path, shared, &mut Diagnostics::default()) else {
                continue;
            };
            let key = cache::keyed(lang, caps.bits(), hash);
            let fallback = Span::new(root, 0, 0);
            read.push(Ahead {
                at,
                lang,
                expanded,
                caps,
                key,
                fallback,
            });
        }
        self.dependencies.extend(fs.read.into_inner());
        let compiled = &self.compiled;
        let missing: Vec<&Ahead> = read.iter().filter(|r| !compiled.contains(&r.key, &r.expanded.text)).collect();
        // No more than the cache keeps: modules compiled ahead must still be there when read.
        let elsewhere: Vec<&&Ahead> = missing
            .par_iter()
            .take(compiled.capacity)
            .filter(|r| {
                let compile = || compile(r.lang, &r.expanded, r.caps, r.fallback, &mut Diagnostics::default());
                !compiled.try_compile(r.key, &r.expanded.text, compile)
            })
            .collect();
        // Modules another compilation was compiling: theirs, once it is done.
        elsewhere.iter().for_each(|r| compiled.wait_for(&r.key));
        for r in read {
            if let Some(c) = self.compiled.get(&r.key, &r.expanded.text) {
                let module = ShaderModule {
                    path: r.at.0.clone(),
                    lang: r.lang,
                    hash: r.key.hash(),
                    compiled: c,
                    expanded: r.expanded,
                };
                self.cache.insert(r.at, Some(Arc::new(module)));
            }
        }
    }
}

/// A module `ShaderLoader::prewarm` read: the load it stands for (path, capabilities), its
/// text with includes and its cache key.
struct Ahead {
    at: (String, u64),
    lang: Lang,
    expanded: Expanded,
    caps: naga::valid::Capabilities,
    key: cache::Key,
    fallback: Span,
}

/// Shader files as the compilations of one run expanded them, by the name diagnostics show
/// (the path under its root): they read one snapshot of the files, so one expansion, and
/// its hash, serves them all. Only successes are kept.
#[derive(Default)]
pub struct Expansions(crate::memo::Memo<String, Arc<Expansion>>);

/// A shader file's language, its text with includes spliced in and the text's hash.
struct Expansion {
    lang: Lang,
    expanded: Expanded,
    hash: u64,
}

impl Expansions {
    /// The expansion kept for `name`, rebuilt in `sources`: each of its files read again
    /// through `fs` (recorded and link-checked as a fresh expansion's are; the snapshot
    /// gives the same text) and added to the source map unless it holds it already.
    fn take(&self, fs: &dyn ShaderFs, sources: &mut SourceMap, name: &str) -> Option<(Lang, Expanded, FileId, u64)> {
        let kept = self.0.get(name)?;
        let e = &kept.expanded;
        let mut ids = Vec::with_capacity(e.paths.len());
        for path in &e.paths {
            let text = fs.read(path).ok()?;
            let shown = fs.display(path);
            ids.push(match sources.find(&shown) {
                Some(id) if sources.get(id).text == text => id,
                _ => sources.add(shown, text),
            });
        }
        let local = |old: FileId| e.files.iter().position(|&f| f == old).map(|i| ids[i]);
        let segments = e
            .segments
            .iter()
            .map(|s| {
                Some(include::Segment {
                    file: local(s.file)?,
                    ..s.clone()
                })
            })
            .collect::<Option<Vec<_>>>()?;
        let expanded = Expanded {
            text: e.text.clone(),
            segments,
            files: ids.clone(),
            paths: e.paths.clone(),
        };
        Some((kept.lang, expanded, ids[0], kept.hash))
    }

    fn put(&self, name: String, lang: Lang, expanded: &Expanded, hash: u64) {
        let expanded = expanded.clone();
        self.0.put(name, Arc::new(Expansion { lang, expanded, hash }));
    }
}

/// `read_expanded` with the text's hash, or what another compilation of the run made of
/// the same file (`shared`).
fn read_hashed(
    fs: &dyn ShaderFs,
    sources: &mut SourceMap,
    path: &Spanned<String>,
    shared: Option<&Expansions>,
    diags: &mut Diagnostics,
) -> Option<(Lang, Expanded, FileId, u64)> {
    // Without a run to share with, no name is needed.
    let name = shared.map(|_| fs.display(&path.value));
    if let Some(hit) = shared.zip(name.as_deref()).and_then(|(s, name)| s.take(fs, sources, name)) {
        return Some(hit);
    }
    let (lang, expanded, root) = read_expanded(fs, sources, path, diags)?;
    let hash = cache::text_hash(&expanded.text);
    if let Some((s, name)) = shared.zip(name) {
        s.put(name, lang, &expanded, hash);
    }
    Some((lang, expanded, root, hash))
}

/// A shader file's language, and its text with includes spliced in (`None`: the error is
/// in `diags`).
fn read_expanded(
    fs: &dyn ShaderFs,
    sources: &mut SourceMap,
    path: &Spanned<String>,
    diags: &mut Diagnostics,
) -> Option<(Lang, Expanded, FileId)> {
    let lang = match lang_of(&path.value) {
        Ok(l) => l,
        Err(e) if e == "geometry" => {
            diags.push(crate::diag::geometry_shader(path.span));
            return None;
        }
        Err(e) => {
            diags.push(Diagnostic::error(Code::ShaderLanguage, e, path.span));
            return None;
        }
    };
    if let Err(why) = include::confined(&path.value) {
        diags.push(Diagnostic::error(Code::OutsideRoot, why, path.span));
        return None;
    }
    // Read every time (a long-running process must see edits); the source map keeps one copy.
    let root = match fs.read(&path.value) {
        Ok(text) => match sources.find(&fs.display(&path.value)) {
            Some(id) if sources.get(id).text == text => id,
            _ => sources.add(fs.display(&path.value), text),
        },
        Err(e) => {
            let code = match crate::vfs::read_error_code(&e) {
                Code::FileNotFound => Code::ShaderNotFound,
                c => c,
            };
            diags.push(
                Diagnostic::error(code, format!("cannot read shader `{}`: {e}", path.value), path.span).with_label_text("referenced here"),
            );
            return None;
        }
    };
    match include::expand(fs, sources, root, &path.value) {
        Ok(e) => Some((lang, e, root)),
        Err(d) => {
            diags.push(d.with_secondary(path.span, "in the shader used here"));
            None
        }
    }
}

pub fn load_module(
    fs: &dyn ShaderFs,
    sources: &mut SourceMap,
    (path, shared): (&Spanned<String>, Option<&Expansions>),
    caps: naga::valid::Capabilities,
    cache: &ModuleCache,
    diags: &mut Diagnostics,
) -> Option<ShaderModule> {
    let (lang, expanded, root, hash) = read_hashed(fs, sources, path, shared, diags)?;
    let fallback = Span::new(root, 0, 0);
    let key = cache::keyed(lang, caps.bits(), hash);
    let compiled = match cache.get(&key, &expanded.text) {
        Some(c) => c,
        None => {
            let c = compile(lang, &expanded, caps, fallback, diags)?;
            cache.put(key, &expanded.text, c.clone());
            c
        }
    };
    Some(ShaderModule {
        path: path.value.clone(),
        lang,
        hash: key.hash(),
        compiled,
        expanded,
    })
}

/// Parse and validate expanded source, mapping naga's errors back through `expanded`.
fn compile(
    lang: Lang,
    expanded: &Expanded,
    caps: naga::valid::Capabilities,
    fallback: Span,
    diags: &mut Diagnostics,
) -> Option<Arc<Compiled>> {
    let map = |s: naga::Span| s.to_range().and_then(|r| expanded.map(r)).unwrap_or(fallback);
    let module = parse(lang, &expanded.text, &map, diags)?;
    let mut validator = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), caps);
    let info = match validator.validate(&module) {
        Ok(i) => i,
        Err(e) => {
            diags.push(validation_error(&e, &map, (&module, &expanded.text)));
            return None;
        }
    };
    let mut layouter = naga::proc::Layouter::default();
    if let Err(e) = layouter.update(module.to_ctx()) {
        diags.push(Diagnostic::error(
            Code::ShaderValidation,
            format!("cannot lay out types: {e}"),
            fallback,
        ));
        return None;
    }
    let globals = reflect::resource_globals_of(&module, &layouter);
    Some(Arc::new(Compiled {
        module,
        info,
        layouter,
        globals,
        overrides_accepted: Default::default(),
    }))
}

/// naga's WGSL or GLSL front end, with its errors located through `map`.
fn parse(lang: Lang, text: &str, map: &dyn Fn(naga::Span) -> Span, diags: &mut Diagnostics) -> Option<naga::Module> {
    match lang {
        Lang::Wgsl => match naga::front::wgsl::parse_str(text) {
            Ok(m) => Some(m),
            Err(e) => {
                let mut labels = e.labels().map(|(s, t)| (map(s), t.to_string()));
                let (first_span, first_text) = labels.next().unwrap_or((map(naga::Span::UNDEFINED), String::new()));
                let mut d = Diagnostic::error(Code::WgslParse, e.message().to_string(), first_span).with_label_text(first_text);
                for (s, t) in labels {
                    d = d.with_secondary(s, t);
                }
                for n in e.notes() {
                    d = d.with_note(n);
                }
                diags.push(d);
                None
            }
        },
        Lang::Glsl(stage) => match naga::front::glsl::Frontend::default().parse(&naga::front::glsl::Options::from(stage), text) {
            Ok(m) => Some(m),
            Err(errs) => {
                for e in errs.errors {
                    diags.push(Diagnostic::error(Code::GlslParse, e.kind.to_string(), map(e.meta)));
                }
                None
            }
        },
    }
}

/// A validation error with every span naga gives and the chain of causes as notes, in
/// WGSL terms (see `readable`); an operation the stage forbids is located at the operation.
fn validation_error(
    e: &naga::WithSpan<naga::valid::ValidationError>,
    map: &dyn Fn(naga::Span) -> Span,
    (module, text): (&naga::Module, &str),
) -> Diagnostic {
    let func = readable::function_of(e.as_inner(), module);
    let say = |msg: &str| {
        let msg = readable::types(msg, module);
        match func {
            Some(f) => readable::expressions(&msg, f, text),
            None => msg,
        }
    };
    // A label naga writes as a handle (`naga::ir::GlobalVariable [0]`) shows the source there.
    let label = |s: &naga::Span, t: &String| {
        let t = say(t);
        match s.to_range().and_then(|r| text.get(r)) {
            Some(src) if t.starts_with("naga::") => format!("`{}`", src.lines().next().unwrap_or(src).trim()),
            _ => t,
        }
    };
    let mut spans: Vec<(Span, String)> = e.spans().map(|(s, t)| (map(*s), label(s, t))).collect();
    if let naga::valid::ValidationError::EntryPoint {
        stage,
        name,
        source: naga::valid::EntryPointError::ForbiddenStageOperations,
    } = e.as_inner()
    {
        if let Some(ep) = module.entry_points.iter().find(|ep| ep.stage == *stage && ep.name == *name) {
            spans.extend(
                readable::forbidden_operations(module, ep)
                    .into_iter()
                    .map(|(s, label)| (map(s), label.to_string())),
            );
        }
    }
    let mut spans = spans.into_iter().filter(|(s, _)| *s != map(naga::Span::UNDEFINED));
    // naga gives no span (entry-point interface errors, capabilities): the offending argument
    // or result of the function's signature, else its `fn` line — never the file's first byte.
    let mut chain = vec![e.as_inner().to_string()];
    let mut source = std::error::Error::source(e.as_inner());
    while let Some(s) = source {
        chain.push(s.to_string());
        source = s.source();
    }
    // The argument or result an entry-point error names, else where the shader asks for a
    // missing capability, else the `fn` line.
    let fallback = || {
        let signature = readable::signature_span(e.as_inner(), text);
        let specific = signature
            .clone()
            .filter(|(_, what)| what.starts_with("argument") || what == "the result");
        specific
            .or_else(|| readable::capability_span(&chain, text))
            .or_else(|| readable::type_span(e.as_inner(), module, text))
            .or(signature)
            .map(|(r, what)| (map(naga::Span::new(r.start as u32, r.end as u32)), what))
            .unwrap_or((map(naga::Span::UNDEFINED), String::new()))
    };
    // A missing capability that naga locates at a whole declaration (a struct holding
    // `@builtin(clip_distances)`): the shader's `enable` directive for it first, the
    // declaration beside it. A span on one line (an expression using it) stays first.
    let whole_declaration = (e.spans().next())
        .and_then(|(s, _)| s.to_range())
        .and_then(|r| text.get(r))
        .is_some_and(|t| t.trim_end().contains('\n'));
    let enable = (readable::capability_span(&chain, text))
        .filter(|(_, what)| whole_declaration && what.starts_with("needs "))
        .map(|(r, what)| (map(naga::Span::new(r.start as u32, r.end as u32)), what));
    let (first, first_text) = match enable {
        Some(directive) => directive,
        None => spans.next().unwrap_or_else(fallback),
    };
    let mut d = Diagnostic::error(Code::ShaderValidation, say(&e.as_inner().to_string()), first).with_label_text(first_text);
    for (s, t) in spans {
        d = d.with_secondary(s, t);
    }
    let mut source = std::error::Error::source(e.as_inner());
    while let Some(s) = source {
        d = d.with_note(say(&s.to_string()));
        source = s.source();
    }
    if e.as_inner().to_string().contains("apabilit") || d.notes.iter().any(|n| n.contains("apabilit")) {
        let note = feature_note(&d.notes);
        d = d.with_note(note);
    }
    if let naga::valid::ValidationError::EntryPoint {
        source: naga::valid::EntryPointError::BindingCollision(h),
        ..
    } = e.as_inner()
    {
        d = binding_collision(d, *h, module, map);
    }
    d
}

/// naga names one global of a binding collision (`Bindings for [19] conflict`): the headline
/// names both and where the other one is declared (often in an included lib file).
fn binding_collision(
    mut d: Diagnostic,
    h: naga::Handle<naga::GlobalVariable>,
    module: &naga::Module,
    map: &dyn Fn(naga::Span) -> Span,
) -> Diagnostic {
    let var = &module.global_variables[h];
    let Some(binding) = &var.binding else { return d };
    let other = (module.global_variables.iter())
        .find(|(o, g)| *o != h && g.binding.as_ref() == Some(binding))
        .map(|(o, g)| (o, g.name.clone().unwrap_or_default()));
    let Some((o, other_name)) = other else { return d };
    let name = var.name.clone().unwrap_or_default();
    let at = format!("@group({}) @binding({})", binding.group, binding.binding);
    let headline = std::mem::replace(&mut d.message, format!("`{name}` and `{other_name}` both use {at}"));
    d = d.with_secondary(map(module.global_variables.get_span(o)), format!("`{other_name}` uses {at} too"));
    d.notes.retain(|n| !n.starts_with("Bindings for"));
    d.notes.insert(0, headline);
    d.with_note(
        "give one of them a binding that no other global of the shader or of the files it includes uses \
         (docs/pipelines.md, \"Bindings the lib files take\": group 2 from binding 8 up is free)",
    )
}

/// The wgpu feature a missing naga capability (named in `notes`, `Capabilities(NAME)`) needs,
/// as `requires` would name it; or that no feature lightbench can require provides it.
fn feature_note(notes: &[String]) -> String {
    // naga writes `Capabilities(NAME)` or `naga::valid::Capabilities::NAME` (FLOAT16 for the
    // flag named SHADER_FLOAT16).
    let named = |n: &String| {
        let after = n.split("Capabilities(").nth(1).or_else(|| n.split("Capabilities::").nth(1))?;
        let name: String = after.chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').collect();
        let cap =
            naga::valid::Capabilities::from_name(&name).or_else(|| naga::valid::Capabilities::from_name(&format!("SHADER_{name}")))?;
        Some((name, cap))
    };
    let missing = notes.iter().find_map(named);
    let Some((name, cap)) = missing else {
        return "declare the wgpu feature this needs in the `requires` of the variant option that enables this pass".into();
    };
    match Feature::ALL.iter().find(|f| capabilities(&BTreeSet::from([**f])).contains(cap)) {
        Some(f) => format!(
            "{name} needs the wgpu feature `{}`: add `{}` to the `requires` of the variant option that enables this pass",
            f.wgpu_name(),
            f.name()
        ),
        None => format!("{name}: no feature a pipeline can `requires` provides it yet, so no profile can run this shader"),
    }
}
