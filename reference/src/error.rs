//! The reference's error type: a reference that cannot be rendered as asked, or a store that
//! cannot be read or written (scene and file errors come wrapped).

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A reference whose sums would not fit the memory it may use.
    #[error("{0}")]
    TooLarge(String),
    /// A file of the store (or an image) that cannot be read or written.
    #[error(transparent)]
    Scene(#[from] lightbench_scene::Error),
}

pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// Reading or writing `path` failed.
    pub fn io(path: impl Into<std::path::PathBuf>, e: impl std::fmt::Display) -> Error {
        Error::Scene(lightbench_scene::Error::io(path, e))
    }
}
