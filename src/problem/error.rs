use std::path::PathBuf;

/// Why a problem file was refused. Each variant names the file; `Invalid` names the key.
#[derive(Debug, thiserror::Error)]
pub enum ProblemError {
    // `error`, not `source`: the message already says it, and a source would be printed twice
    // by the binary's error chain.
    #[error("{}: cannot read the problem file: {error}", file.display())]
    Io {
        file: PathBuf,
        error: std::io::Error,
    },
    #[error("{}:{line}:{column}: not valid TOML: {message}", file.display())]
    Syntax {
        file: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    #[error("{}: key `{key}`: {message}", file.display())]
    Invalid {
        file: PathBuf,
        key: String,
        message: String,
    },
}

impl ProblemError {
    /// The dotted key the error is about, if it is about one.
    pub fn key(&self) -> Option<&str> {
        match self {
            ProblemError::Invalid { key, .. } => Some(key),
            _ => None,
        }
    }
}
