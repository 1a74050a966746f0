//! Reading a scene: a built-in name, or a scene file read through the workspace's file
//! system, parsed (RON front end), lowered, checked and merged with its `builtin:` base.

use super::{builtin, SceneDesc, SceneFile};
use crate::diag::{suggestion_note, Code, Diagnostic, Diagnostics, Severity};
use crate::span::SourceMap;
use crate::vfs::Vfs;
use std::path::Path;

/// A built-in scene by name, or the scene file at `spec`. Problems go to `diags`.
pub fn load(vfs: &dyn Vfs, spec: &str, sources: &mut SourceMap, diags: &mut Diagnostics) -> Option<SceneDesc> {
    if let Some(s) = builtin::by_name(spec) {
        return Some(s);
    }
    let path = Path::new(spec);
    if is_model(path) {
        return Some(model_scene(spec, sources));
    }
    let text = match vfs.read(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound && path.extension().is_none() => {
            let msg = format!(
                "`{spec}` is neither a scene file nor a built-in scene ({})",
                builtin::NAMES.join(", ")
            );
            diags.push(Diagnostic::unlocated(Severity::Error, Code::FileNotFound, msg).with_note(suggestion_note(spec, &builtin::NAMES)));
            return None;
        }
        Err(e) => {
            let code = crate::vfs::read_error_code(&e);
            diags.push(Diagnostic::unlocated(
                Severity::Error,
                code,
                format!("cannot read scene `{spec}`: {e}"),
            ));
            return None;
        }
    };
    load_text(path, text, sources, diags)
}

/// A glTF model given where a scene is expected.
pub fn is_model(path: &Path) -> bool {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    matches!(ext.as_deref(), Some("gltf" | "glb"))
}

/// A scene of one model, framed and lit once it is loaded (see `SceneDesc::framed_model`),
/// with shadows. Diagnostics about the model point at the name as given.
fn model_scene(spec: &str, sources: &mut SourceMap) -> SceneDesc {
    let file = sources.add("<--scene>", spec.to_string());
    let span = crate::span::Span::new(file, 0, spec.len());
    let path = Path::new(spec);
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("model");
    let mut desc = SceneDesc::empty(stem);
    desc.models.push(super::ModelDesc {
        path: crate::span::Spanned::new(spec.to_string(), span),
        file: path.to_path_buf(),
        translation: [0.0; 3],
        rotation: [0.0; 3],
        scale: 1.0,
        triangles: 1.0,
        reflective: false,
        double_sided: None,
        at: super::KeySpans {
            span,
            keys: Default::default(),
        },
    });
    desc.effects.insert(crate::ir::Effect::Shadows);
    desc.framed_model = true;
    desc
}

/// Whether RON text is a scene file (`Scene(...)` after any comments), so that `check DIR`
/// checks scene files as scenes and pipeline files as pipelines.
pub fn is_scene_text(text: &str) -> bool {
    opens_with(text, "Scene")
}

/// What a file among pipelines holds, as `check` and editors tell them apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    Pipeline,
    Scene,
    Sweep,
    /// Neither `.ron` nor `.lbp`.
    Other,
}

/// A `.ron` file is a scene file or a sweep spec when its first item says so (`text`, when it
/// could be read), else a pipeline; a `.lbp` file is a pipeline.
pub fn file_kind(path: &std::path::Path, text: Option<&str>) -> FileKind {
    match path.extension().and_then(|e| e.to_str()) {
        Some("lbp") => FileKind::Pipeline,
        Some("ron") => match text {
            Some(t) if opens_with(t, "Scene") => FileKind::Scene,
            Some(t) if opens_with(t, "Sweep") => FileKind::Sweep,
            _ => FileKind::Pipeline,
        },
        _ => FileKind::Other,
    }
}

/// Whether RON `text` is an item of `kind` (`Scene(`, `Sweep(`): its first token after
/// comments.
pub fn opens_with(text: &str, kind: &str) -> bool {
    let mut rest = text.trim_start_matches('\u{feff}');
    loop {
        rest = rest.trim_start();
        if let Some(r) = rest.strip_prefix("//") {
            rest = r.split_once('\n').map_or("", |(_, after)| after);
        } else if let Some(r) = rest.strip_prefix("/*") {
            rest = r.split_once("*/").map_or("", |(_, after)| after);
        } else {
            break;
        }
    }
    rest.strip_prefix(kind).is_some_and(|r| r.trim_start().starts_with('('))
}

/// A scene file's text (`path` names it in diagnostics and anchors its model paths).
pub fn load_text(path: &Path, text: String, sources: &mut SourceMap, diags: &mut Diagnostics) -> Option<SceneDesc> {
    let file = sources.add(path.display().to_string(), text.clone());
    let root = match crate::front::ron::parse::parse(file, &text) {
        Ok(n) => n,
        Err(d) => {
            diags.push(d);
            return None;
        }
    };
    let dir = path.parent().unwrap_or(Path::new(""));
    let lowered = crate::syntax::lower::scene(&root, dir, diags)?;
    let before = diags.error_count();
    crate::check::scene::scene(&lowered, diags);
    if diags.error_count() > before {
        return None;
    }
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("scene");
    let mut desc = merge(lowered, stem);
    desc.file = Some(path.to_path_buf());
    Some(desc)
}

/// The file's scene over its `builtin:` base: name, size and camera replace the base's;
/// models, lights and effects are added to it (lights replace its own with
/// `builtin_lights: false`).
fn merge(f: SceneFile, stem: &str) -> SceneDesc {
    let base = f.builtin.as_ref().and_then(|b| builtin::by_name(&b.value));
    let mut desc = base.unwrap_or_else(|| SceneDesc::empty(stem));
    desc.name = f.name.unwrap_or_else(|| stem.to_string());
    if let Some(s) = f.size {
        desc.size = s.value;
    }
    if let Some(c) = f.camera {
        desc.camera = c;
    }
    desc.models.extend(f.models);
    if !f.builtin_lights {
        desc.lights.clear();
    }
    desc.lights.extend(f.lights);
    desc.effects.extend(f.effects);
    desc
}

#[cfg(test)]
mod tests {
    #[test]
    fn scene_files_are_told_from_pipelines_by_their_root() {
        assert!(super::is_scene_text("// a scene\n/* x */ Scene (lights: [])"));
        assert!(!super::is_scene_text("// Scene(\nPipeline(name: \"p\")"));
        assert!(!super::is_scene_text("Scenes()"));
    }
}
