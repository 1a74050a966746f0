//! Check `data`: each resource's initial content (`data:`) read and decoded against its
//! declaration (format, size, layers, bytes), so a wrong file fails `check`, not a render.
//! Files are resolved next to the pipeline file and may not leave its directory.

use crate::data::{self, TextureShape};
use crate::diag::{Code, Diagnostic, Diagnostics};
use crate::ir::{DataSource, Pipeline, Resource, ResourceKind, SizeSpec};
use crate::span::Spanned;
use crate::vfs::Vfs;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Decoded data by resource name (only resources that declare `data`).
pub type ResourceData = BTreeMap<String, Arc<Vec<u8>>>;

pub struct DataCtx<'a> {
    pub vfs: &'a dyn Vfs,
    /// The pipeline file's directory.
    pub dir: PathBuf,
    /// Files read (a watcher reloads when they change).
    pub read: &'a mut BTreeSet<PathBuf>,
    /// Buffers the other compilations of a run decoded from the same snapshot of the files.
    pub decoded: Option<&'a Decoded>,
}

/// Buffers decoded from data files, by path, for the compilations of one run: they read the
/// same snapshot, so one decode serves all (`deferred`'s LTC table is 8,192 numbers of JSON).
pub type Decoded = crate::memo::Memo<PathBuf, Arc<Vec<u8>>>;

pub fn check(p: &Pipeline, ctx: &mut DataCtx, diags: &mut Diagnostics) -> ResourceData {
    let mut out = ResourceData::new();
    for r in &p.resources {
        let Some(d) = r.data() else { continue };
        match bytes(r, d, ctx) {
            Ok(b) => {
                out.insert(r.name.value.clone(), b);
            }
            Err((code, msg)) => diags.push(Diagnostic::error(code, format!("data of `{}`: {msg}", r.name.value), d.span)),
        }
    }
    out
}

type Failure = (Code, String);

fn bytes(r: &Resource, d: &Spanned<DataSource>, ctx: &mut DataCtx) -> Result<Arc<Vec<u8>>, Failure> {
    let mismatch = |m: String| (Code::DataMismatch, m);
    if r.external() {
        return Err((
            Code::ConflictingKeys,
            "an `external` resource is supplied by the caller; drop `data` or `external`".into(),
        ));
    }
    match &r.kind {
        ResourceKind::AccelerationStructure => Err((
            Code::ConflictingKeys,
            "an acceleration structure is built from the scene; it takes no `data`".into(),
        )),
        ResourceKind::Buffer(b) => {
            let raw = match &d.value {
                DataSource::File(f) => buffer_file(ctx, f)?,
                inline => Arc::new(data::inline_bytes(inline).unwrap_or_default()),
            };
            data::check_buffer_size(raw.len(), b.size.value).map_err(|e| mismatch(format!("the data {e}")))?;
            Ok(raw)
        }
        ResourceKind::Texture(t) => {
            let SizeSpec::Fixed { width, height } = t.size.value else {
                return Err(mismatch("a texture with data needs a `Fixed(width, height)` size".into()));
            };
            let DataSource::File(f) = &d.value else {
                return Err(mismatch(
                    "inline numbers fill buffers; a texture takes a file (PNG, EXR or raw bytes)".into(),
                ));
            };
            let path = resolve(ctx, f)?;
            let raw = read(ctx, &path, f)?;
            let shape = TextureShape {
                format: t.format.value,
                extent: (width, height),
                layers: t.layers.value,
            };
            data::texture_from_file(&path, raw, shape)
                .map(Arc::new)
                .map_err(|e| mismatch(format!("`{f}` {e}")))
        }
    }
}

/// A buffer's bytes from a data file, decoded once per run (read, and its link checked, by
/// every compilation all the same: each reports its own failures and watches the file).
fn buffer_file(ctx: &mut DataCtx, f: &str) -> Result<Arc<Vec<u8>>, Failure> {
    let path = resolve(ctx, f)?;
    let raw = read(ctx, &path, f)?;
    let decode = || {
        let bytes = data::buffer_from_file(&path, raw).map_err(|e| (Code::DataMismatch, format!("`{f}`: {e}")))?;
        Ok(Arc::new(bytes))
    };
    match ctx.decoded {
        Some(d) => d.kept(path.clone(), decode),
        None => decode(),
    }
}

/// A data path relative to the pipeline's directory, which it may not leave.
fn resolve(ctx: &DataCtx, f: &str) -> Result<PathBuf, Failure> {
    crate::shader::include::confined(f).map_err(|_| {
        (
            Code::OutsideRoot,
            format!("`{f}` must be a path inside the pipeline's directory (relative, without leaving it)"),
        )
    })?;
    Ok(crate::vfs::normalize(&ctx.dir.join(f)))
}

fn read(ctx: &mut DataCtx, path: &Path, f: &str) -> Result<Vec<u8>, Failure> {
    ctx.read.insert(path.to_path_buf());
    ctx.vfs
        .within(&ctx.dir, path)
        .and_then(|()| ctx.vfs.read_bytes(path))
        .map_err(|e| (crate::vfs::read_error_code(&e), format!("cannot read `{f}`: {e}")))
}
