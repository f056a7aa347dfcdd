//! One error type for the whole program, split by what the user must do about it.
//!
//! Exit codes (documented in docs/guide.md): 2 = bad input (fix the scenario or the
//! flags), 3 = the run became unstable and was stopped (see the diagnosis),
//! 1 = anything else (I/O failure while writing results), 130 = interrupted by
//! SIGINT (a checkpoint was written).

pub use crate::stop::Diagnosis;
use std::path::PathBuf;

/// `:line:column` of a scenario-file error, or nothing.
fn at(line: &Option<(usize, usize)>) -> String {
    line.map_or(String::new(), |(l, c)| format!(":{l}:{c}"))
}

#[derive(Debug, thiserror::Error)]
/// Every error of fibresim, by what the user must do about it.
pub enum Error {
    /// The scenario file or the command line is wrong. `file`, `line` (1-based
    /// line and column of the key in the file, when it has one) and `key`
    /// locate it; `message` says what is wrong and how to fix it.
    #[error("{file}{}: {key}: {message}", at(.line))]
    BadInput {
        /// The scenario file, `checkpoint` or `command line`.
        file: String,
        /// Line and column of the key in the file.
        line: Option<(usize, usize)>,
        /// The key or flag.
        key: String,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// The run was stopped because it stopped being trustworthy.
    #[error("run stopped: {0}")]
    Unstable(Diagnosis),
    /// Stopped by SIGINT after writing a checkpoint.
    #[error("{} at step {} (t = {} s)", .0.kind, .0.step, crate::fmt::short(.0.t))]
    Interrupted(Diagnosis),
    #[error("cannot write {path}: {source}")]
    /// An output could not be written (exit 1).
    Io {
        /// The file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
}

impl Error {
    /// Bad input at `key` of `file`, with a message that gives the fix.
    pub fn bad(
        file: impl Into<String>,
        key: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Error::BadInput {
            file: file.into(),
            line: None,
            key: key.into(),
            message: message.into(),
        }
    }

    /// Attach the line and column of a bad-input key of the scenario file
    /// `source`, found in its `text` (see `scenario::locate`); errors about
    /// other files (a body file), errors already located and other errors
    /// pass unchanged.
    pub fn located(self, source: &str, text: &str) -> Self {
        match self {
            Error::BadInput {
                file,
                line: None,
                key,
                message,
            } if file == source => Error::BadInput {
                line: crate::scenario::locate(text, &key),
                file,
                key,
                message,
            },
            e => e,
        }
    }

    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// The process exit code for this error (docs/guide.md, "Exit codes").
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::BadInput { .. } => 2,
            Error::Unstable(_) => 3,
            Error::Interrupted(_) => 130,
            Error::Io { .. } => 1,
        }
    }
}

/// fibresim's result type.
pub type Result<T> = std::result::Result<T, Error>;
