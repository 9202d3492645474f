//! Problem files: the TOML schema of a study, its validation, and the validated [`Problem`].
//!
//! Two layers: [`schema`] mirrors the file (serde, unknown keys rejected), [`validate`] checks every
//! value and builds the SI runtime structs of [`crate::model`]. Every error names the file and the
//! dotted key (`model.pipe.outer_radius`) and says what is allowed; every refusal of a file is
//! reported in one pass (unknown keys, units, ranges), one line each.

mod check;
mod error;
pub mod file;
pub mod keys;
pub mod pipe_tables;
pub mod reference;
pub mod schema;
pub mod study;
mod validate;
mod validate_expect;
mod validate_explore;
mod validate_fatigue;
mod validate_range;
mod validate_sections;
mod validate_study;
mod validate_threshold;
mod validate_top;

pub use crate::units::{self, Dimension, UnitError};
pub use error::{KeyError, ProblemError};

use crate::model::{CampbellSettings, Drillstring, Mesh, OperatingPoint, Simulation};
use std::path::{Path, PathBuf};

/// The largest problem file read, bytes (the shipped ones are 2-12 kB).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// A validated study: the model, its discretisation, the operating point and the simulation window.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Name of the study (file stem unless the file sets `name`).
    pub name: String,
    /// Free-text description from the file.
    pub description: String,
    /// Where it was read from (empty for problems built in code).
    pub source: PathBuf,
    /// The problem file's text as read, recorded in every report with its hash.
    pub text: String,
    pub model: Drillstring,
    pub mesh: Mesh,
    pub operating_point: OperatingPoint,
    pub simulation: Simulation,
    /// Uncertain parameters, objective, constraints, optimizer and expected optimum (issue 4).
    pub study: study::Study,
    /// `[campbell]`: the excitation multiple of the critical speeds (default 3×).
    pub campbell: CampbellSettings,
}

impl Problem {
    /// Read and validate a problem file (at most [`MAX_FILE_BYTES`]: `drillopt modes /dev/zero`
    /// read 1.2 GB before it failed).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, ProblemError> {
        use std::io::Read;
        let path = path.as_ref();
        let io = |error| ProblemError::Io {
            file: path.to_path_buf(),
            error,
        };
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .map_err(io)?
            .take(MAX_FILE_BYTES + 1)
            .read_to_end(&mut bytes)
            .map_err(io)?;
        if bytes.len() as u64 > MAX_FILE_BYTES {
            return Err(io(std::io::Error::new(
                std::io::ErrorKind::FileTooLarge,
                format!(
                    "larger than {} MiB: a problem file is a few kB of TOML (is this the right file?)",
                    MAX_FILE_BYTES >> 20
                ),
            )));
        }
        let text = String::from_utf8(bytes).map_err(|e| {
            io(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("not UTF-8 text ({e}); a problem file is TOML"),
            ))
        })?;
        Self::from_toml(&text, path)
    }

    /// Parse and validate TOML text; `path` is used for messages and the default name.
    pub fn from_toml(text: &str, path: &Path) -> Result<Self, ProblemError> {
        let (raw, shape, masked) = validate::parse(text, path)?;
        let Some(raw) = raw else {
            return Err(ProblemError::Invalid {
                file: path.to_path_buf(),
                errors: shape,
            });
        };
        let mut problem = validate::problem(raw, path, shape, masked)?;
        problem.text = text.to_string();
        Ok(problem)
    }
}
