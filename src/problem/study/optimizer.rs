//! The validated `[optimizer]` section: [`OptimizerSettings`], one variant per method holding
//! only the settings that method reads, each with `Default` (the problem file's defaults) and a
//! builder that checks every field against its range (as Clarabel's `DefaultSettingsBuilder`).
//! Lengths are fractions of the bounds box: the optimizers work on its unit box. The file layer
//! (`validate_study.rs`) reads the keys, refuses a key the method does not read
//! ([`Method::keys`]), and builds the variant.

/// Optimisation method, the `method` key of `[optimizer]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    TrustRegion,
    NelderMead,
    ParticleSwarm,
    Grid,
    Ego,
    EgoTrustRegion,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::TrustRegion => "trust_region",
            Method::NelderMead => "nelder_mead",
            Method::ParticleSwarm => "particle_swarm",
            Method::Grid => "grid",
            Method::Ego => "ego",
            Method::EgoTrustRegion => "ego+trust_region",
        }
    }

    /// The `[optimizer]` keys the method reads besides `method`; any other key is refused.
    /// `grid` is accepted by every method: it is also `drillopt map`'s default grid.
    pub fn keys(self) -> &'static [&'static str] {
        match self {
            Method::TrustRegion | Method::NelderMead => &[
                "max_evaluations",
                "start",
                "initial_radius",
                "min_radius",
                "grid",
            ],
            Method::ParticleSwarm => &["max_evaluations", "min_radius", "seed", "grid"],
            Method::Grid => &["grid"],
            Method::Ego => &["max_evaluations", "initial_design", "seed", "grid"],
            Method::EgoTrustRegion => &[
                "max_evaluations",
                "initial_design",
                "seed",
                "ego_share",
                "initial_radius",
                "min_radius",
                "grid",
            ],
        }
    }
}

/// Legal range of `max_evaluations` (design points).
pub const MAX_EVALUATIONS: std::ops::RangeInclusive<usize> = 3..=100_000;
/// Legal range of `initial_design` (points of EGO's initial design).
pub const INITIAL_DESIGN: std::ops::RangeInclusive<usize> = 3..=1000;
/// Legal range of the points per axis of `grid`.
pub const GRID_POINTS: std::ops::RangeInclusive<usize> = 2..=200;

/// An optimizer setting outside its range: the `[optimizer]` key and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("optimizer.{key}: {message}")]
pub struct SettingsError {
    pub key: &'static str,
    pub message: String,
}

fn check_budget(n: usize) -> Result<(), SettingsError> {
    if MAX_EVALUATIONS.contains(&n) {
        return Ok(());
    }
    Err(SettingsError {
        key: "max_evaluations",
        message: format!("must be an integer in [3, 100000], got {n}"),
    })
}

fn check_grid(g: [usize; 2]) -> Result<(), SettingsError> {
    if g.iter().all(|n| GRID_POINTS.contains(n)) {
        return Ok(());
    }
    Err(SettingsError {
        key: "grid",
        message: format!("must be [n_omega, n_v0] with each in [2, 200], got {g:?}"),
    })
}

fn check_start(s: Option<[f64; 2]>) -> Result<(), SettingsError> {
    match s {
        Some(s) if !s.iter().all(|v| v.is_finite() && *v > 0.0) => Err(SettingsError {
            key: "start",
            message: format!("must be a positive finite (omega rad/s, v0 m/s), got {s:?}"),
        }),
        _ => Ok(()),
    }
}

fn check_fraction(key: &'static str, x: f64) -> Result<(), SettingsError> {
    if x > 0.0 && x <= 1.0 {
        return Ok(());
    }
    Err(SettingsError {
        key,
        message: format!("must be a fraction of the bounds box in (0, 1], got {x}"),
    })
}

/// `min_radius < initial_radius`, both fractions of the bounds box.
fn check_radii(initial_radius: f64, min_radius: f64) -> Result<(), SettingsError> {
    check_fraction("initial_radius", initial_radius)?;
    check_fraction("min_radius", min_radius)?;
    if min_radius < initial_radius {
        return Ok(());
    }
    Err(SettingsError {
        key: "min_radius",
        message: format!(
            "must be smaller than optimizer.initial_radius ({initial_radius}), got {min_radius}"
        ),
    })
}

/// The local methods' settings: `method = "trust_region"` (`optimize::minimize_trust_region`;
/// `initial_radius` is the initial trust radius and the step of the initial design, `min_radius`
/// the radius below which it has converged) and `method = "nelder_mead"`
/// (`optimize::minimize_nelder_mead`; `initial_radius` is the edge of the initial and every restart
/// simplex, `min_radius` the simplex diameter that ends a run). Lengths are fractions of the bounds
/// box (the optimizer works on its unit box).
#[derive(Debug, Clone, PartialEq)]
pub struct LocalSearchSettings {
    /// Budget of design points (each one is `samples` simulations; over all restarts for
    /// Nelder–Mead). Default 30; [3, 100000].
    pub max_evaluations: usize,
    /// Starting point (Ω rad/s, V0 m/s); the operating point unless set.
    pub start: Option<[f64; 2]>,
    /// Initial radius (see above). Default 0.25; (0, 1].
    pub initial_radius: f64,
    /// Converged below this (see above). Default 0.02; (0, initial_radius).
    pub min_radius: f64,
    /// `drillopt map`'s default grid (n_Ω, n_V0). Default [9, 9]; each in [2, 200].
    pub grid: [usize; 2],
}

/// Settings of `method = "trust_region"`.
pub type TrustRegionSettings = LocalSearchSettings;
/// Settings of `method = "nelder_mead"`.
pub type NelderMeadSettings = LocalSearchSettings;

impl Default for LocalSearchSettings {
    fn default() -> Self {
        LocalSearchSettings {
            max_evaluations: 30,
            start: None,
            initial_radius: 0.25,
            min_radius: 0.02,
            grid: [9, 9],
        }
    }
}

impl LocalSearchSettings {
    fn validate(&self) -> Result<(), SettingsError> {
        check_budget(self.max_evaluations)?;
        check_grid(self.grid)?;
        check_start(self.start)?;
        check_radii(self.initial_radius, self.min_radius)
    }
}

/// `method = "particle_swarm"` (`optimize::minimize_particle_swarm`): particles start uniformly
/// over the bounds box, so there is no start point.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleSwarmSettings {
    /// Budget of design points. Default 30; [3, 100000].
    pub max_evaluations: usize,
    /// Converged when every particle is within this fraction of the bounds box of the best.
    /// Default 0.02; (0, 1].
    pub min_radius: f64,
    /// Seed of the swarm's random generator. Default 0.
    pub seed: u64,
    /// `drillopt map`'s default grid (n_Ω, n_V0). Default [9, 9]; each in [2, 200].
    pub grid: [usize; 2],
}

impl Default for ParticleSwarmSettings {
    fn default() -> Self {
        ParticleSwarmSettings {
            max_evaluations: 30,
            min_radius: 0.02,
            seed: 0,
            grid: [9, 9],
        }
    }
}

impl ParticleSwarmSettings {
    fn validate(&self) -> Result<(), SettingsError> {
        check_budget(self.max_evaluations)?;
        check_grid(self.grid)?;
        check_fraction("min_radius", self.min_radius)
    }
}

/// `method = "grid"` (`optimize::grid_search`): every node of the grid inside the linear
/// constraints, all evaluated; no budget, no start.
#[derive(Debug, Clone, PartialEq)]
pub struct GridSettings {
    /// Points per axis (n_Ω, n_V0); the search uses max(n_Ω, n_V0) on both axes, and
    /// `drillopt map` uses the grid as given. Default [9, 9]; each in [2, 200].
    pub grid: [usize; 2],
}

impl Default for GridSettings {
    fn default() -> Self {
        GridSettings { grid: [9, 9] }
    }
}

impl GridSettings {
    fn validate(&self) -> Result<(), SettingsError> {
        check_grid(self.grid)
    }
}

fn check_initial_design(initial_design: usize, ego_budget: usize) -> Result<(), SettingsError> {
    if !INITIAL_DESIGN.contains(&initial_design) {
        return Err(SettingsError {
            key: "initial_design",
            message: format!("must be an integer in [3, 1000], got {initial_design}"),
        });
    }
    if initial_design >= ego_budget {
        return Err(SettingsError {
            key: "initial_design",
            message: format!(
                "must be below EGO's evaluations ({ego_budget}), so that EGO adds at least one point, got {initial_design}"
            ),
        });
    }
    Ok(())
}

/// `method = "ego"` (`optimize::minimize_ego`): efficient global optimisation (Gaussian-process
/// surrogates of the score and of each chance constraint, expected improvement) on egobox. The
/// initial design is a maximin Latin hypercube inside the linear constraints; no start point.
#[derive(Debug, Clone, PartialEq)]
pub struct EgoSettings {
    /// Budget of design points, the initial design included. Default 40; [3, 100000], above
    /// `initial_design`.
    pub max_evaluations: usize,
    /// Points of the initial Latin-hypercube design. Default 10; [3, 1000], below
    /// `max_evaluations`.
    pub initial_design: usize,
    /// Seed of the initial design and of egobox's generator: the run is reproducible from it.
    /// Default 0.
    pub seed: u64,
    /// `drillopt map`'s default grid (n_Ω, n_V0). Default [9, 9]; each in [2, 200].
    pub grid: [usize; 2],
}

impl Default for EgoSettings {
    fn default() -> Self {
        EgoSettings {
            max_evaluations: 40,
            initial_design: 10,
            seed: 0,
            grid: [9, 9],
        }
    }
}

impl EgoSettings {
    fn validate(&self) -> Result<(), SettingsError> {
        check_budget(self.max_evaluations)?;
        check_grid(self.grid)?;
        check_initial_design(self.initial_design, self.max_evaluations)
    }
}

/// `method = "ego+trust_region"` (`optimize::minimize_ego_trust_region`): EGO on
/// `⌊ego_share · max_evaluations⌋` points, then the trust region from EGO's best point on what is
/// left of the budget, with EGO's evaluations in its models (never evaluated twice).
#[derive(Debug, Clone, PartialEq)]
pub struct EgoTrustRegionSettings {
    /// Budget of design points of both phases. Default 40; [3, 100000].
    pub max_evaluations: usize,
    /// Points of EGO's initial design. Default 10; [3, 1000], below EGO's share.
    pub initial_design: usize,
    /// Seed of EGO (see [`EgoSettings::seed`]). Default 0.
    pub seed: u64,
    /// Fraction of `max_evaluations` given to EGO. Default 0.7; (0, 1).
    pub ego_share: f64,
    /// Initial trust radius of the refinement. Default 0.1; (0, 1].
    pub initial_radius: f64,
    /// The refinement has converged below this radius. Default 0.02; (0, initial_radius).
    pub min_radius: f64,
    /// `drillopt map`'s default grid (n_Ω, n_V0). Default [9, 9]; each in [2, 200].
    pub grid: [usize; 2],
}

impl Default for EgoTrustRegionSettings {
    fn default() -> Self {
        EgoTrustRegionSettings {
            max_evaluations: 40,
            initial_design: 10,
            seed: 0,
            ego_share: 0.7,
            initial_radius: 0.1,
            min_radius: 0.02,
            grid: [9, 9],
        }
    }
}

impl EgoTrustRegionSettings {
    /// EGO's share of the budget, `⌊ego_share · max_evaluations⌋` design points.
    pub fn ego_evaluations(&self) -> usize {
        (self.ego_share * self.max_evaluations as f64).floor() as usize
    }

    fn validate(&self) -> Result<(), SettingsError> {
        check_budget(self.max_evaluations)?;
        check_grid(self.grid)?;
        if !(self.ego_share > 0.0 && self.ego_share < 1.0) {
            return Err(SettingsError {
                key: "ego_share",
                message: format!(
                    "must be a fraction of max_evaluations in (0, 1), got {}",
                    self.ego_share
                ),
            });
        }
        check_initial_design(self.initial_design, self.ego_evaluations())?;
        check_radii(self.initial_radius, self.min_radius)
    }
}

/// A builder per settings struct, as Clarabel's `DefaultSettingsBuilder`: it starts from the
/// defaults, each setter sets one field, and `build` checks every field against its range.
macro_rules! settings_builder {
    ($settings:ident, $builder:ident { $($field:ident: $ty:ty),* $(,)? }) => {
        #[doc = concat!("Builder of [`", stringify!($settings), "`], from its defaults.")]
        #[derive(Debug, Clone, Default)]
        pub struct $builder {
            settings: $settings,
        }

        impl $builder {
            $(
                #[doc = concat!("Sets `", stringify!($field), "` (see [`", stringify!($settings), "`]).")]
                pub fn $field(mut self, value: $ty) -> Self {
                    self.settings.$field = value;
                    self
                }
            )*

            /// The settings, or the first one outside its range.
            pub fn build(self) -> Result<$settings, SettingsError> {
                self.settings.validate()?;
                Ok(self.settings)
            }
        }

        impl $settings {
            /// A builder starting from the defaults.
            pub fn builder() -> $builder {
                $builder::default()
            }
        }
    };
}

settings_builder!(LocalSearchSettings, LocalSearchSettingsBuilder {
    max_evaluations: usize,
    start: Option<[f64; 2]>,
    initial_radius: f64,
    min_radius: f64,
    grid: [usize; 2],
});
settings_builder!(
    ParticleSwarmSettings,
    ParticleSwarmSettingsBuilder {
        max_evaluations: usize,
        min_radius: f64,
        seed: u64,
        grid: [usize; 2],
    }
);
settings_builder!(GridSettings, GridSettingsBuilder { grid: [usize; 2] });
settings_builder!(
    EgoSettings,
    EgoSettingsBuilder {
        max_evaluations: usize,
        initial_design: usize,
        seed: u64,
        grid: [usize; 2],
    }
);
settings_builder!(
    EgoTrustRegionSettings,
    EgoTrustRegionSettingsBuilder {
        max_evaluations: usize,
        initial_design: usize,
        seed: u64,
        ego_share: f64,
        initial_radius: f64,
        min_radius: f64,
        grid: [usize; 2],
    }
);

/// The `[optimizer]` section, validated: the method and the settings it uses, nothing else.
#[derive(Debug, Clone, PartialEq)]
pub enum OptimizerSettings {
    TrustRegion(TrustRegionSettings),
    NelderMead(NelderMeadSettings),
    ParticleSwarm(ParticleSwarmSettings),
    Grid(GridSettings),
    Ego(EgoSettings),
    EgoTrustRegion(EgoTrustRegionSettings),
}

impl Default for OptimizerSettings {
    fn default() -> Self {
        OptimizerSettings::TrustRegion(TrustRegionSettings::default())
    }
}

impl OptimizerSettings {
    pub fn method(&self) -> Method {
        match self {
            OptimizerSettings::TrustRegion(_) => Method::TrustRegion,
            OptimizerSettings::NelderMead(_) => Method::NelderMead,
            OptimizerSettings::ParticleSwarm(_) => Method::ParticleSwarm,
            OptimizerSettings::Grid(_) => Method::Grid,
            OptimizerSettings::Ego(_) => Method::Ego,
            OptimizerSettings::EgoTrustRegion(_) => Method::EgoTrustRegion,
        }
    }

    /// Points per axis (n_Ω, n_V0): the grid method's, and `drillopt map`'s default.
    pub fn grid(&self) -> [usize; 2] {
        match self {
            OptimizerSettings::TrustRegion(s) => s.grid,
            OptimizerSettings::NelderMead(s) => s.grid,
            OptimizerSettings::ParticleSwarm(s) => s.grid,
            OptimizerSettings::Grid(s) => s.grid,
            OptimizerSettings::Ego(s) => s.grid,
            OptimizerSettings::EgoTrustRegion(s) => s.grid,
        }
    }

    /// `(initial_radius, min_radius)` of the methods with a trust region (`trust_region`,
    /// `ego+trust_region`): fractions of the bounds box.
    pub fn trust_radii(&self) -> Option<(f64, f64)> {
        match self {
            OptimizerSettings::TrustRegion(s) => Some((s.initial_radius, s.min_radius)),
            OptimizerSettings::EgoTrustRegion(s) => Some((s.initial_radius, s.min_radius)),
            _ => None,
        }
    }

    /// Starting point (Ω rad/s, V0 m/s), for the methods that start from one.
    pub fn start(&self) -> Option<[f64; 2]> {
        match self {
            OptimizerSettings::TrustRegion(s) => s.start,
            OptimizerSettings::NelderMead(s) => s.start,
            OptimizerSettings::ParticleSwarm(_)
            | OptimizerSettings::Grid(_)
            | OptimizerSettings::Ego(_)
            | OptimizerSettings::EgoTrustRegion(_) => None,
        }
    }

    /// The same settings with `max_evaluations = n`, checked as the file's key is (in [3,
    /// 100000]; for EGO above `initial_design`). The grid method has no budget: refused, saying
    /// what sets its number of points.
    pub fn with_max_evaluations(&self, n: usize) -> Result<Self, SettingsError> {
        let mut s = self.clone();
        match &mut s {
            OptimizerSettings::TrustRegion(x) | OptimizerSettings::NelderMead(x) => {
                x.max_evaluations = n;
                x.validate()?;
            }
            OptimizerSettings::ParticleSwarm(x) => {
                x.max_evaluations = n;
                x.validate()?;
            }
            OptimizerSettings::Ego(x) => {
                x.max_evaluations = n;
                x.validate()?;
            }
            OptimizerSettings::EgoTrustRegion(x) => {
                x.max_evaluations = n;
                x.validate()?;
            }
            OptimizerSettings::Grid(_) => {
                return Err(SettingsError {
                    key: "max_evaluations",
                    message: "method = \"grid\" evaluates every node of optimizer.grid and has no budget; change optimizer.grid, or choose a method with max_evaluations".into(),
                });
            }
        }
        Ok(s)
    }

    /// Most design points the method evaluates: `max_evaluations`, or the grid's n² nodes
    /// (n = max(n_Ω, n_V0); nodes outside the linear constraints are skipped).
    pub fn budget(&self) -> usize {
        match self {
            OptimizerSettings::TrustRegion(s) => s.max_evaluations,
            OptimizerSettings::NelderMead(s) => s.max_evaluations,
            OptimizerSettings::ParticleSwarm(s) => s.max_evaluations,
            OptimizerSettings::Grid(s) => s.grid[0].max(s.grid[1]).pow(2),
            OptimizerSettings::Ego(s) => s.max_evaluations,
            OptimizerSettings::EgoTrustRegion(s) => s.max_evaluations,
        }
    }
}

#[cfg(test)]
mod budget_tests {
    use super::*;

    #[test]
    fn a_budget_override_is_checked_as_the_key_is() {
        let tr = OptimizerSettings::default();
        let s = tr.with_max_evaluations(12).unwrap();
        assert_eq!(s.budget(), 12);
        assert_eq!(s.method(), Method::TrustRegion);
        let e = tr.with_max_evaluations(2).unwrap_err();
        assert_eq!(e.key, "max_evaluations");
        assert!(e.message.contains("[3, 100000]"), "{e}");
        // EGO: the budget must stay above the initial design (10 by default).
        let ego = OptimizerSettings::Ego(EgoSettings::default());
        assert_eq!(ego.with_max_evaluations(11).unwrap().budget(), 11);
        let e = ego.with_max_evaluations(10).unwrap_err();
        assert_eq!(e.key, "initial_design");
        // EGO + trust region: EGO's share ⌊0.7 × 12⌋ = 8 is below the initial design, 10.
        let etr = OptimizerSettings::EgoTrustRegion(EgoTrustRegionSettings::default());
        assert!(etr.with_max_evaluations(12).is_err());
        let grid = OptimizerSettings::Grid(GridSettings::default());
        let e = grid.with_max_evaluations(20).unwrap_err();
        assert!(e.message.contains("optimizer.grid"), "{e}");
    }
}
