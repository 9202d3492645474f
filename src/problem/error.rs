use std::fmt;
use std::path::{Path, PathBuf};

/// Why a problem file was refused. Each variant names the file; `Invalid` names every refused key.
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
    /// Every refused key of the file found in one pass (unknown keys, wrong units, values out of
    /// range), in the order validation met them; at least one. Displayed one line per key.
    #[error("{}", Lines(file, errors))]
    Invalid {
        file: PathBuf,
        errors: Vec<KeyError>,
    },
}

/// One refused key: the dotted key (`model.pipe.outer_radius`) and what is wrong, in words.
#[derive(Debug, Clone, PartialEq)]
pub struct KeyError {
    pub key: String,
    pub message: String,
}

/// `file: key `k`: message`, one line per refused key.
struct Lines<'a>(&'a Path, &'a [KeyError]);

impl fmt::Display for Lines<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, e) in self.1.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{}: key `{}`: {}", self.0.display(), e.key, e.message)?;
        }
        Ok(())
    }
}

impl ProblemError {
    /// One refused key.
    pub fn invalid(file: &Path, key: &str, message: String) -> Self {
        ProblemError::Invalid {
            file: file.to_path_buf(),
            errors: vec![KeyError {
                key: key.to_string(),
                message,
            }],
        }
    }

    /// The dotted key the (first) error is about, if it is about one.
    pub fn key(&self) -> Option<&str> {
        self.key_errors().first().map(|e| e.key.as_str())
    }

    /// Every refused key, in the order validation met them (empty for I/O and syntax errors).
    pub fn key_errors(&self) -> &[KeyError] {
        match self {
            ProblemError::Invalid { errors, .. } => errors,
            _ => &[],
        }
    }
}
