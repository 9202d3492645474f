//! Which fidelity produced an evaluation: the cheap one of a multi-fidelity solve's exploration
//! (`[optimizer.explore]`) or the problem's own (every evaluation of a problem without it).

use serde::Serialize;

/// The fidelity of an evaluation, serialised `"explore"` / `"full"` in every report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Fidelity {
    /// `[optimizer.explore]`'s overrides: a shorter window, fewer samples or a smaller basis.
    Explore,
    /// The problem's own window, samples and basis.
    #[default]
    Full,
}

impl Fidelity {
    /// The name in reports and tables: `explore`, `full`.
    pub fn name(self) -> &'static str {
        match self {
            Fidelity::Explore => "explore",
            Fidelity::Full => "full",
        }
    }
}

impl std::fmt::Display for Fidelity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
