//! Scenes' error type: a scene that cannot be loaded or used, or a file that cannot be read or
//! written. The other crates have their own, which wrap this one.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A built-in scene name, scene file, glTF model or a host's geometry that cannot be
    /// loaded or used (empty when its diagnostics were shown already).
    #[error("{0}")]
    Scene(String),
    /// Reading or writing a file.
    #[error("{}: {message}", path.display())]
    Io { path: PathBuf, message: String },
}

pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    pub fn io(path: impl Into<PathBuf>, e: impl std::fmt::Display) -> Error {
        Error::Io {
            path: path.into(),
            message: e.to_string(),
        }
    }
}
