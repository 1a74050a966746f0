//! lightbench's error type: every command's failure, in the category its exit code comes from
//! — a usage error (exit 2), or bad input and everything else (exit 1) — with the library
//! crates' errors wrapped. The libraries know nothing of exit codes; the mapping is here.

use lightbench_compiler::plan::ParamError;
use lightbench_executor as executor;
use lightbench_reference as reference;
use lightbench_scene as scene;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A command-line argument that cannot be understood, or a request the pipeline or scene
    /// cannot take (exit code 2).
    #[error("{0}")]
    Usage(String),
    /// An input file whose content cannot be used as written, located in it (exit code 1).
    #[error("{0}")]
    Input(String),
    /// Compiling for the device or running the Plan.
    #[error(transparent)]
    Executor(executor::Error),
    /// The reference path tracer or its store.
    #[error(transparent)]
    Reference(reference::Error),
    /// A scene, or a file read or written.
    #[error(transparent)]
    Scene(#[from] scene::Error),
    /// A parameter (`--param`, a spec's or a script's setting) the Plan lacks, or a value of
    /// the wrong type or outside the range (exit code 2).
    #[error("{}", param_message(.0))]
    Param(#[from] ParamError),
}

pub type Result<T> = std::result::Result<T, Error>;

/// A command's exit code when it failed: bad input and everything else.
pub const EXIT_ERRORS: i32 = 1;
/// A command's exit code for a usage error.
pub const EXIT_USAGE: i32 = 2;

/// A request the running Plan cannot take is the user's (a `--param` or `--variant`): a usage
/// error; content that cannot be used is bad input.
impl From<executor::Error> for Error {
    fn from(e: executor::Error) -> Error {
        match e {
            executor::Error::Request(m) => Error::Usage(m),
            executor::Error::Variant(lines) => Error::Usage(lines.iter().map(|l| format!("--variant: {l}")).collect::<Vec<_>>().join("\n")),
            executor::Error::Input(m) => Error::Input(m),
            // The command line supplies external resources with `--input NAME=FILE`.
            executor::Error::Supply { name, error, .. } => match Error::from(*error) {
                Error::Input(m) => Error::Input(format!("--input `{name}`: {m}")),
                Error::Usage(m) => Error::Usage(format!("--input `{name}`: {m}")),
                e => e,
            },
            executor::Error::Unsupplied(n) => {
                Error::Usage(format!("resource `{n}` is external: supply its contents (render --input {n}=FILE)"))
            }
            executor::Error::Param(p) => Error::Param(p),
            executor::Error::Scene(s) => Error::Scene(s),
            e => Error::Executor(e),
        }
    }
}

/// A reference too large for memory is asked for by the user's size and terms: a usage error.
impl From<reference::Error> for Error {
    fn from(e: reference::Error) -> Error {
        match e {
            reference::Error::TooLarge(m) => Error::Usage(m),
            reference::Error::Scene(s) => Error::Scene(s),
        }
    }
}

impl Error {
    /// The process exit code this error ends a command with: 2 for usage errors, else 1.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Usage(_) | Error::Param(_) => EXIT_USAGE,
            _ => EXIT_ERRORS,
        }
    }

    pub fn io(path: impl Into<std::path::PathBuf>, e: impl std::fmt::Display) -> Error {
        Error::Scene(scene::Error::io(path, e))
    }

    /// A scene that cannot be loaded or used.
    pub fn scene(message: impl Into<String>) -> Error {
        Error::Scene(scene::Error::Scene(message.into()))
    }

    /// A pipeline that did not compile: its diagnostics, rendered.
    pub fn compile(message: impl Into<String>) -> Error {
        Error::Executor(executor::Error::Compile(message.into()))
    }

    /// A resource the Plan lacks, or of another kind.
    pub fn resource(message: impl Into<String>) -> Error {
        Error::Executor(executor::Error::Resource(message.into()))
    }

    /// No adapter, or no device.
    pub fn adapter(message: impl Into<String>) -> Error {
        Error::Executor(executor::Error::Adapter(message.into()))
    }

    /// The same error said at `place` (`FILE:LINE`), keeping its category (and so its exit
    /// code).
    pub fn at(self, place: &str) -> Error {
        let at = |m: String| format!("{place}: {m}");
        match self {
            Error::Usage(m) => Error::Usage(at(m)),
            Error::Input(m) => Error::Input(at(m)),
            Error::Scene(scene::Error::Scene(m)) => Error::scene(at(m)),
            Error::Scene(scene::Error::Io { path, message }) => Error::io(path, at(message)),
            Error::Param(e) => Error::Usage(at(e.to_string())),
            // The libraries' other errors, said at the place (exit code 1 still).
            e => Error::Input(at(e.to_string())),
        }
    }
}

/// A parameter error in the words of `--param`.
fn param_message(e: &ParamError) -> String {
    match e {
        ParamError::Unknown { name, suggestion } => {
            let hint = suggestion.as_ref().map(|m| format!(" (did you mean `{m}`?)")).unwrap_or_default();
            format!("--param `{name}`: the pipeline has no such parameter{hint}")
        }
        e => format!("--param: {e}"),
    }
}
