//! The executor's error type: what went wrong compiling for a device or running a Plan, and
//! what it concerns. Scene errors come wrapped; how a program reports them is the program's.

use lightbench_compiler::plan::ParamError;

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
    /// The Plan asks for something this executor cannot provide, or contradicts itself.
    #[error("plan: {0}")]
    Plan(String),
    /// A resource asked for by name that the Plan lacks, or of another kind.
    #[error("{0}")]
    Resource(String),
    /// A request the running Plan cannot take: a parameter it fixes, frame lights that do
    /// not fit it, an input that is not one of its external resources.
    #[error("{0}")]
    Request(String),
    /// Variants or options asked for that the pipeline does not have: one message each (with
    /// the nearest name, where there is one).
    #[error("{}", .0.join("\n"))]
    Variant(Vec<String>),
    /// Content that cannot be used as given: an input's bytes or file of the wrong size or
    /// format.
    #[error("{0}")]
    Input(String),
    /// External resource `name` cannot be supplied through `call` (`load_input`,
    /// `supply_input`, `mark_supplied`): `error` says why (a `Request` — no such resource, not
    /// external — or an `Input` — contents of the wrong size or format).
    #[error("{call} `{name}`: {error}")]
    Supply {
        call: &'static str,
        name: String,
        error: Box<Error>,
    },
    /// A frame reads external resource `0`, whose contents nothing has supplied yet.
    #[error("resource `{0}` is external: supply its contents (Executor::load_input, supply_input or mark_supplied)")]
    Unsupplied(String),
    /// A scene that cannot be loaded or used, or a file that cannot be read or written.
    #[error(transparent)]
    Scene(#[from] lightbench_scene::Error),
    /// A parameter value that does not apply to the running Plan.
    #[error(transparent)]
    Param(#[from] ParamError),
}

pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    pub fn gpu(what: impl Into<String>, e: impl std::fmt::Display) -> Error {
        Error::Gpu {
            what: what.into(),
            message: e.to_string(),
        }
    }

    /// A scene this device or Plan cannot take (over a limit, inconsistent geometry).
    pub fn scene(message: impl Into<String>) -> Error {
        Error::Scene(lightbench_scene::Error::Scene(message.into()))
    }

    /// Reading or writing `path` failed.
    pub fn io(path: impl Into<std::path::PathBuf>, e: impl std::fmt::Display) -> Error {
        Error::Scene(lightbench_scene::Error::io(path, e))
    }
}
