//! The runtime's error type: what went wrong and what it concerns. Every fallible runtime
//! call returns it; the CLI prints it and exits non-zero, nothing panics.

use lightbench_compiler::plan::ParamError;
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The pipeline did not compile: the diagnostics, rendered as `lightbench check` shows them.
    #[error("{0}")]
    Compile(String),
    /// No adapter, or none that could open a device.
    #[error("{0}")]
    Adapter(String),
    /// wgpu reported an error (validation, out of memory, internal) while doing `what`.
    #[error("{what}: {message}")]
    Gpu { what: String, message: String },
    /// The Plan asks for something this executor cannot provide (a compiler/runtime mismatch).
    #[error("plan: {0}")]
    Plan(String),
    /// A built-in scene name, scene file or glTF model that cannot be loaded.
    #[error("{0}")]
    Scene(String),
    /// A resource asked for by name that the Plan lacks, or of another kind.
    #[error("{0}")]
    Resource(String),
    /// Reading or writing a file.
    #[error("{}: {message}", path.display())]
    Io { path: PathBuf, message: String },
    /// A command-line argument that cannot be understood (exit code 2).
    #[error("{0}")]
    Usage(String),
    /// An input file whose content cannot be used as written (a sweep spec's value), the
    /// message located in it: bad input, exit code 1.
    #[error("{0}")]
    Input(String),
    /// A parameter value that does not apply to the running Plan.
    #[error(transparent)]
    Param(#[from] ParamError),
}

pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    pub fn io(path: impl Into<PathBuf>, e: impl std::fmt::Display) -> Error {
        Error::Io {
            path: path.into(),
            message: e.to_string(),
        }
    }
    /// The same error said at `place` (`FILE:LINE`), keeping its kind (and so its exit code).
    pub fn at(self, place: &str) -> Error {
        let at = |m: String| format!("{place}: {m}");
        match self {
            Error::Compile(m) => Error::Compile(at(m)),
            Error::Adapter(m) => Error::Adapter(at(m)),
            Error::Gpu { what, message } => Error::Gpu { what: at(what), message },
            Error::Plan(m) => Error::Plan(at(m)),
            Error::Scene(m) => Error::Scene(at(m)),
            Error::Resource(m) => Error::Resource(at(m)),
            Error::Io { path, message } => Error::Io {
                message: at(message),
                path,
            },
            Error::Usage(m) => Error::Usage(at(m)),
            Error::Input(m) => Error::Input(at(m)),
            Error::Param(e) => Error::Usage(at(e.to_string())),
        }
    }
    pub fn gpu(what: impl Into<String>, e: impl std::fmt::Display) -> Error {
        Error::Gpu {
            what: what.into(),
            message: e.to_string(),
        }
    }
}
