//! The whole problem file as written: the model's tables ([`super::schema`]) and the study's
//! ([`super::study`]), which know nothing of each other.

use super::schema::{
    CampbellSection, MeshSection, ModelSection, OperatingPointSection, SimulationSection,
};
use super::study::{
    ConstraintsSection, ExpectSection, ObjectiveSection, OptimizerSection, UncertainSection,
};
use serde::Deserialize;

/// The whole problem file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProblemFile {
    /// Name used for the results folder; defaults to the file stem.
    pub name: Option<String>,
    /// Free text: where the configuration comes from.
    pub description: Option<String>,
    pub model: ModelSection,
    pub mesh: MeshSection,
    pub operating_point: OperatingPointSection,
    pub simulation: SimulationSection,
    pub uncertain: Option<UncertainSection>,
    pub objective: Option<ObjectiveSection>,
    pub constraints: Option<ConstraintsSection>,
    pub optimizer: Option<OptimizerSection>,
    pub expect: Option<ExpectSection>,
    pub campbell: Option<CampbellSection>,
}
