//! Diagnostic codes: one documented enum, so that every code the compiler can report is
//! listed in one place (the manual's table in docs/diagnostics.md is checked against it by a test).

use serde::{Serialize, Serializer};

macro_rules! codes {
    ($( $variant:ident = $name:literal : $doc:literal, )*) => {
        /// A stable identifier of a kind of problem; `as_str` is what users see and match on.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Code { $( #[doc = $doc] $variant ),* }

        impl Code {
            pub const ALL: &'static [Code] = &[$(Code::$variant),*];
            pub fn as_str(self) -> &'static str {
                match self { $(Code::$variant => $name),* }
            }
            /// One line saying what the code means.
            pub fn doc(self) -> &'static str {
                match self { $(Code::$variant => $doc),* }
            }
            pub fn from_name(s: &str) -> Option<Code> {
                match s { $($name => Some(Code::$variant),)* _ => None }
            }
        }
    };
}

codes! {
    // Reading files and syntax.
    FileNotFound = "file-not-found": "a pipeline or scene file cannot be read",
    NotAFile = "not-a-file": "a path that names a directory, device or pipe where a file is expected",
    FileTooLarge = "file-too-large": "a pipeline, scene or shader file over 16 MiB",
    InvalidUtf8 = "invalid-utf8": "a file that is not UTF-8 text (the message gives the byte offset, line and column)",
    NestingTooDeep = "nesting-too-deep": "values or conditions nested more than 64 deep, or includes more than 32",
    UnknownFormat = "unknown-format": "a pipeline file whose extension is neither `.ron` nor `.lbp`",
    RonSyntax = "ron-syntax": "RON text that does not parse",
    LbpSyntax = "lbp-syntax": "LBP text that does not parse",
    BadNumber = "bad-number": "a number that cannot be represented where it is used (e.g. not a 32-bit whole number)",
    // Structure of the syntax tree.
    UnknownKey = "unknown-key": "a key the item does not have (with a suggestion)",
    MissingKey = "missing-key": "a required key is absent",
    DuplicateKey = "duplicate-key": "the same key given twice in one item",
    Misplaced = "misplaced": "a key that belongs to another kind of item (e.g. `cull` on a compute pass)",
    ConflictingKeys = "conflicting-keys": "two keys that exclude each other (`clear` and `load`)",
    TypeMismatch = "type-mismatch": "a value of the wrong shape (a list where a string is expected...)",
    UnknownKind = "unknown-kind": "an unknown item kind, e.g. `Rastr(...)` or an unknown condition",
    UnknownValue = "unknown-value": "an unknown enum value, e.g. a texture format (with a suggestion)",
    UnknownEffect = "unknown-effect": "an effect name that does not exist",
    ParamType = "param-type": "a parameter value that does not fit the parameter's type",
    ModelLoad = "model-load": "a scene's glTF model that cannot be loaded",
    SweepSpec = "sweep-spec": "a sweep spec (`Sweep(...)`) that `sweep` would refuse (the message locates it)",
    SkippedPrimitive = "skipped-primitive": "warning: a glTF primitive of points or lines, which is not drawn",
    // Declarations.
    DuplicateName = "duplicate-name": "two declarations (or map keys) with the same name",
    AmbiguousName = "ambiguous-name": "two names that map to one shader identifier",
    EmptyRange = "empty-range": "a parameter whose min is greater than its max",
    DefaultOutOfRange = "default-out-of-range": "a parameter default outside its min..max",
    NonFinite = "non-finite": "NaN or infinity where a finite number is needed",
    EmptyEnum = "empty-enum": "an Enum parameter without options",
    EmptyLightKinds = "empty-light-kinds": "a `per_light` list without light kinds",
    ValueOutOfRange = "value-out-of-range": "a number outside what the item allows (sizes, scales, counts)",
    CubeLayers = "cube-layers": "a cube texture without exactly 6 layers",
    ViewLayers = "view-layers": "a D2 texture with more than one layer",
    MipCount = "mip-count": "more mip levels than the size allows, or none",
    TooManyLayers = "too-many-layers": "more array layers than the profile allows",
    TextureTooLarge = "texture-too-large": "a fixed size over the profile's texture dimension limit",
    HistoryExternal = "history-external": "a resource that is both `history` and `external`",
    UnknownResource = "unknown-resource": "a name that refers to no declared resource",
    UnknownParam = "unknown-param": "a name that refers to no declared parameter",
    UnknownPass = "unknown-pass": "a name that refers to no declared pass",
    UnknownLimit = "unknown-limit": "a limit name wgpu does not have",
    UnknownVariant = "unknown-variant": "a variant name that does not exist",
    UnknownVariantOption = "unknown-variant-option": "a variant option that does not exist",
    UnknownLet = "unknown-let": "a condition name no `let` declares",
    LetCycle = "let-cycle": "named conditions (`let`) that name each other",
    UnusedLet = "unused-let": "warning: a `let` no condition uses",
    EmptyGroup = "empty-group": "warning: a group of passes without passes",
    UnknownTemplate = "unknown-template": "a pass or group `like` a template no `template` declares",
    TemplateArguments = "template-arguments": "a template given more or fewer arguments than it has parameters",
    TemplateCycle = "template-cycle": "templates that are `like` each other",
    TemplateParam = "template-param": "a `$NAME` that is not a parameter of the template it is in, or in a pass outside any template",
    UnusedTemplate = "unused-template": "warning: a template no pass or group is like",
    ChoiceIncomplete = "choice-incomplete": "a choice (`Match`) with no arm for some option of its variant (or, warned, a default arm that serves none)",
    ChoiceOverlap = "choice-overlap": "one option served by two arms of a choice",
    LightChoice = "light-choice": "a `match light` in a pass that does not run per light, or naming a light kind the pass does not run for",
    ToggleNotBool = "toggle-not-bool": "a `Toggle` condition on a parameter that is not a Bool",
    FallbackCycle = "fallback-cycle": "variant fallbacks that lead back to themselves",
    PresetOverlap = "preset-overlap": "one parameter set by the presets of two variants",
    GeometryShader = "geometry-shader": "a geometry stage was asked for; WGSL, naga and wgpu have none",
    OutputNotTexture = "output-not-texture": "the pipeline output is a buffer",
    NotHistory = "not-history": "`Prev(..)` of a resource that keeps no previous frame",
    PerLightMismatch = "per-light-mismatch": "per-light resources used by passes that do not iterate those lights",
    CastersWithoutLights = "casters-without-lights": "`shadow_casters` on a pass that does not run per light",
    VolumeWithoutLights = "volume-without-lights": "`draw: LightVolume` on a pass that does not run per light",
    NotATexture = "not-a-texture": "a buffer used as an attachment",
    DepthAsColor = "depth-as-color": "a depth format used as a color target",
    ColorAsDepth = "color-as-depth": "a color format used as a depth target",
    FormatNotRenderable = "format-not-renderable": "a color target format the profile cannot render to",
    BlendNotBlendable = "blend-not-blendable": "blending on a format that cannot blend",
    AttachmentSize = "attachment-size": "attachments of one pass with different sizes",
    LayerSelect = "layer-select": "a `layer` choice the target or pass cannot honour",
    MipSelect = "mip-select": "a mip level that does not exist, `Rep` without `per_mip`, or a pass reading the mip it writes",
    NoTargets = "no-targets": "a raster or fullscreen pass that renders into nothing",
    MultiviewPerFace = "multiview-per-face": "a multiview pass that also repeats per face",
    RepeatedClear = "repeated-clear": "warning: a repeated pass clears a shared target each time",
    // Shaders.
    ShaderLanguage = "shader-language": "a shader file extension that names no supported language",
    ShaderNotFound = "shader-not-found": "a shader file that cannot be read",
    IncludeSyntax = "include-syntax": "a malformed `#include` line",
    IncludeNotFound = "include-not-found": "an included file that cannot be read",
    IncludeCycle = "include-cycle": "files that include each other",
    OutsideRoot = "outside-root": "a shader, include or data path that is absolute, leaves its root, or links out of it",
    WgslParse = "wgsl-parse": "WGSL that naga cannot parse",
    GlslParse = "glsl-parse": "GLSL that naga cannot parse",
    ShaderValidation = "shader-validation": "a module naga's validator rejects",
    MissingEntryPoint = "missing-entry-point": "an entry point name the module does not have",
    WrongStage = "wrong-stage": "an entry point of another stage than the pass needs",
    ConstantUnknown = "constant-unknown": "a pass constant naming no `override` of the pass's shaders",
    ConstantMissing = "constant-missing": "an `override` without a default that the pass gives no value",
    ConstantType = "constant-type": "a constant whose value does not fit its `override`'s type (or a parameter that is not an Int, Float or Bool)",
    ConstantInvalid = "constant-invalid": "constant values that make a shader invalid in some configuration (an array or workgroup size...)",
    // Bindings and parameter blocks.
    BindingUnsatisfied = "binding-unsatisfied": "a shader global that nothing declared binds to",
    BindingConflict = "binding-conflict": "one @group/@binding slot declared differently by two stages",
    BindingType = "binding-type": "a shader global whose type does not fit what it binds to",
    BindingAccess = "binding-access": "a shader writes a resource the pass only reads",
    TextureType = "texture-type": "a texture binding whose sample type, dimension or format does not fit",
    SamplerType = "sampler-type": "a comparison sampler where a plain one is declared, or the reverse",
    NotFilterable = "not-filterable": "a filtering sampler on a format that cannot be filtered",
    BufferTooSmall = "buffer-too-small": "a buffer smaller than the shader's binding",
    ParamBlock = "param-block": "a parameter block that is not a struct",
    ParamMissing = "param-missing": "a block field without a parameter, or a parameter without a field",
    ParamTypeMismatch = "param-type-mismatch": "a parameter whose type does not fit its block field",
    DataMismatch = "data-mismatch": "resource data whose size, layers or format does not fit its declaration",
    ValueField = "value-field": "a per-pass value naming no field of the pass's parameter block",
    ValueType = "value-type": "a per-pass value that does not fit its block field",
    ParamSign = "param-sign": "warning: an Int parameter that may be negative goes to a `u32` field",
    UnusedRead = "unused-read": "warning: a declared read no entry point uses",
    UnusedParams = "unused-params": "warning: parameters declared for a pass whose shaders have no block",
    // Stage interfaces and limits.
    FragmentOutputs = "fragment-outputs": "fragment outputs that do not match the color targets",
    FragmentOutputKind = "fragment-output-kind": "a fragment output type that does not fit its target format",
    VertexInput = "vertex-input": "a vertex input the scene's vertex layout does not provide",
    StageIo = "stage-io": "a fragment input the vertex stage does not write",
    LimitExceeded = "limit-exceeded": "more of something than the capability profile allows",
    // Configurations and the graph.
    VariantUnsupported = "variant-unsupported": "a variant option the profile cannot run, with no fallback",
    ReadBeforeWrite = "read-before-write": "a resource read before any pass writes it",
    Cycle = "cycle": "passes that depend on each other within a frame",
    DoubleWriter = "double-writer": "two passes that overwrite one resource in no defined order",
    OutputUnreachable = "output-unreachable": "no kept pass writes the output",
}

impl std::fmt::Display for Code {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl PartialEq<&str> for Code {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}

impl PartialEq<str> for Code {
    fn eq(&self, other: &str) -> bool {
        self.as_str() == other
    }
}

impl Serialize for Code {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_round_trip() {
        for c in Code::ALL {
            assert_eq!(Code::from_name(c.as_str()), Some(*c));
            assert!(!c.doc().is_empty());
        }
        let mut names: Vec<&str> = Code::ALL.iter().map(|c| c.as_str()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), Code::ALL.len());
    }
}
