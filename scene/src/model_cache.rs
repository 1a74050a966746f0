//! Scene loading, its models kept between loads: a watcher loading a scene again after a file
//! changed parses only the models one of whose files changed (the model, its external buffers
//! and images, as `gltf_load::files` lists them); the others are taken as the last load left
//! them.

use crate::error::Result;
use crate::gltf_load::{self, Loaded};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

/// A file as it was when its model was loaded: its path, length and modification time.
type Stamp = (PathBuf, Option<(u64, SystemTime)>);

/// The models of the last load, each with its files' stamps. `default()` keeps nothing (a
/// load that is not repeated: each model is moved into its scene, never copied);
/// `keeping()` keeps them for the next load.
#[derive(Default)]
pub struct ModelCache {
    keep: bool,
    kept: HashMap<PathBuf, (Vec<Stamp>, Arc<Loaded>)>,
    /// The models the load under way asked for, and how many of them were kept.
    asked: Vec<PathBuf>,
    kept_now: usize,
    /// Of the last load's models, how many were taken as they were, of all.
    last: (usize, usize),
}

impl ModelCache {
    pub fn keeping() -> ModelCache {
        ModelCache {
            keep: true,
            ..ModelCache::default()
        }
    }

    /// Start a load: its counts begin at zero.
    pub(crate) fn begin(&mut self) {
        self.asked.clear();
        self.kept_now = 0;
    }

    /// The model at `file`: as loaded before if none of its files changed since, else loaded
    /// now (and kept).
    pub(crate) fn model(&mut self, file: &Path) -> Result<Arc<Loaded>> {
        if !self.keep {
            self.asked.push(file.to_path_buf());
            return Ok(Arc::new(gltf_load::load(file)?));
        }
        // One model however its path is written (a scene file given relative or absolute).
        let key = std::fs::canonicalize(file).unwrap_or_else(|_| file.to_path_buf());
        self.asked.push(key.clone());
        let now = stamps(file);
        if let Some((_, loaded)) = self.kept.get(&key).filter(|(then, _)| *then == now) {
            self.kept_now += 1;
            return Ok(loaded.clone());
        }
        // Stamped before loading: a file written while it was read counts as changed next time.
        let loaded = Arc::new(gltf_load::load(file)?);
        self.kept.insert(key, (now, loaded.clone()));
        Ok(loaded)
    }

    /// End a load: the models it did not ask for are dropped.
    pub(crate) fn end(&mut self) {
        let asked = &self.asked;
        self.kept.retain(|f, _| asked.contains(f));
        self.last = (self.kept_now, self.asked.len());
    }

    /// Of the last load's models: how many were taken as the load before left them (none of
    /// their files changed), of all.
    pub fn last(&self) -> (usize, usize) {
        self.last
    }
}

fn stamps(file: &Path) -> Vec<Stamp> {
    gltf_load::files(file)
        .into_iter()
        .map(|p| {
            let meta = std::fs::metadata(&p).ok();
            let stamp = meta.and_then(|m| Some((m.len(), m.modified().ok()?)));
            // Compared by where the file is, however the scene named it.
            (std::fs::canonicalize(&p).unwrap_or(p), stamp)
        })
        .collect()
}
