//! Validated physical parameters. Constructed by [`crate::problem`] from a problem file, or directly
//! in code (tests, benches); every field is in SI units.

/// Pipe material and cross-section (MODEL.md §1).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Pipe {
    /// Steel density ρ, kg/m³.
    pub density: f64,
    /// Young's modulus E, Pa.
    pub youngs_modulus: f64,
    /// Poisson's ratio ν, in (−1, 0.5).
    pub poisson_ratio: f64,
    /// Inner radius R_int, m (0 for a solid bar).
    pub inner_radius: f64,
    /// Outer radius R_ext, m.
    pub outer_radius: f64,
    /// Transverse shear correction κ_s (Cowper's hollow circle unless the problem sets it).
    pub shear_factor: f64,
    /// Torsional correction κ_t (1 is exact St-Venant torsion, stiffness G J).
    pub torsion_factor: f64,
    /// Minimum yield strength, Pa (the von Mises safety factor's reference); None: not given.
    pub yield_strength: Option<f64>,
    /// S-N curve, endurance limit and stress concentration of the fatigue damage
    /// (`[model.pipe.fatigue]`; default DNV-RP-C203 (2016) B1 in air, see [`crate::fatigue`]).
    pub fatigue: crate::fatigue::SnCurve,
}

/// The API drill-pipe grades (API Spec 5DP, Table C.3: minimum yield strength in ksi, here in Pa
/// with 1 ksi = 6.894757293168 MPa): E-75, X-95, G-105, S-135.
pub const API_GRADES: [(&str, f64); 4] = [
    ("E-75", 75.0 * 6.894_757_293_168e6),
    ("X-95", 95.0 * 6.894_757_293_168e6),
    ("G-105", 105.0 * 6.894_757_293_168e6),
    ("S-135", 135.0 * 6.894_757_293_168e6),
];

/// One section of a string of sections (`[[model.section]]`, MODEL.md §11.5): drill pipe,
/// heavy-weight pipe, collars or a stabiliser, listed from the top drive down to the bit.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StringSection {
    /// The section's name, as the file gives it (reports and errors name it).
    pub name: String,
    /// Its length along the string, m.
    pub length: f64,
    /// Its pipe: sizes, material, yield strength and S-N curve (the keys the section does not
    /// give are those of `[model.pipe]`).
    pub pipe: Pipe,
    /// Its share of the mesh's elements (`elements`; a graded mesh), or `None`: the elements
    /// are shared out by length ([`crate::fem::ElementLayout::of`]). Either every section of a
    /// string gives one or none does. Left out of the serialised model when `None`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub elements: Option<usize>,
}

/// The drillstring, borehole and environment.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Drillstring {
    /// Length L from the top drive (x = 0) to the bit (x = L), m.
    pub length: f64,
    /// The pipe of a string of one section, and the material defaults of the sections.
    pub pipe: Pipe,
    /// The sections from the top drive down to the bit (`[[model.section]]`); empty: the string
    /// is one section of `pipe` over `length`. Their lengths add up to `length`. Left out of the
    /// serialised model when empty, so that the model hash of a file without sections is
    /// unchanged.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sections: Vec<StringSection>,
    /// Density ρ_f of the drilling fluid inside the pipe, kg/m³: it adds lateral mass ρ_f A_f and
    /// its weight ρ_f A_f g to the string (MODEL.md §3).
    pub fluid_density: f64,
    /// Density ρ_a of the fluid in the annulus, outside the pipe, kg/m³; 0 (the default, the
    /// seed paper's model) for none. It buoys the string: the gravity load becomes the buoyed
    /// weight (ρA + ρ_f A_f − ρ_a π R_ext²) g, see [`super::Section::weight_mass`], and adds the
    /// confined added mass of the annulus to the lateral inertia, see
    /// [`super::Section::confined_added_mass`]. Left out of the canonical form (cache keys) when
    /// 0, so a problem without it keeps its key.
    #[serde(skip_serializing_if = "crate::units::is_zero")]
    pub annulus_density: f64,
    /// Borehole radius R_bh, m.
    pub borehole_radius: f64,
    /// Mass-proportional damping c, 1/s (C = c · M_pipe + β K).
    pub damping: f64,
    /// Stiffness-proportional damping β, s (`[model.pipe] stiffness_damping`; 0, the paper's
    /// model, when absent): C = c M_pipe + β K, Rayleigh damping (Clough & Penzien, *Dynamics of
    /// Structures*, 2nd ed., 1993, §12.4), a damping ratio ζ = c/(2ω) + βω/2 for a mode of
    /// circular frequency ω. Not in the paper, whose C = c M_pipe damps every mode at the same rate
    /// c/2: the velocity-weakening bit feeds torsional waves of every length (docs/model.md, "Converged
    /// model"), and β, which damps a wave at a rate growing as ω², is the dissipation that grows
    /// with frequency (material hysteresis, the mud's viscous torque) that bounds them. The rigid
    /// motion carries no strain (K Q̇_rigid = 0), so β adds no load of the imposed motion. Left out
    /// of the serialised model when 0, so that the model hash of a problem without it is unchanged.
    #[serde(skip_serializing_if = "crate::units::is_zero")]
    pub stiffness_damping: f64,
    /// Gravitational acceleration g, m/s², acting along −z.
    pub gravity: f64,
    /// The wall contact law and its parameters (MODEL.md §5).
    pub wall: super::WallContact,
    /// How the wall's friction acts on a node in contact (`[model.wall] friction_law`): Coulomb
    /// on the slip of the contact point (MODEL.md §11.2, the default) or the paper's torque.
    pub wall_friction: super::WallFriction,
    /// How the wall law's stiffness and damping are read (`[model.wall] stiffness_per`, MODEL.md
    /// §11.3): per metre of string (the default) or per node (the paper's). Left out of the
    /// serialised model per node, so that the model hash of a file that states the paper's
    /// reading is unchanged.
    #[serde(skip_serializing_if = "super::WallStiffnessPer::is_node")]
    pub wall_stiffness_per: super::WallStiffnessPer,
    /// The bit–rock interaction law and its parameters (MODEL.md §6).
    pub bit: super::BitRock,
    /// Polar moment of inertia of the bit (and of whatever turns with it below the last node),
    /// lumped on θx of the bit node, kg·m² (`[model.bit] inertia`; 0, the paper's model, when
    /// absent). Not in the paper: with none, the bit node of the unreduced finite-element model
    /// chatters at the element scale under the velocity-weakening bit torque (docs/model.md,
    /// "Converged model"). Left out of the serialised model when 0, so that the model hash of a
    /// problem without it is unchanged.
    #[serde(skip_serializing_if = "crate::units::is_zero")]
    pub bit_inertia: f64,
    /// How the top drive moves the string along its axis (`[operating_point] top`, MODEL.md
    /// §11.8): the paper's imposed feed, a hook-load set-point or an autodriller. Left out of the
    /// serialised model for the imposed feed, so that the model hash of a problem without it is
    /// unchanged.
    #[serde(skip_serializing_if = "super::TopDrive::is_feed")]
    pub top: super::TopDrive,
}

impl Drillstring {
    /// Radial gap between the pipe and the borehole wall, R_bh − R_ext, m; for a string of
    /// sections the smallest, of the section with the largest outer radius.
    pub fn gap(&self) -> f64 {
        self.borehole_radius - self.max_outer_radius()
    }

    /// The largest outer radius of the string's pipes, m.
    pub fn max_outer_radius(&self) -> f64 {
        if self.sections.is_empty() {
            return self.pipe.outer_radius;
        }
        (self.sections.iter())
            .map(|s| s.pipe.outer_radius)
            .fold(0.0, f64::max)
    }

    /// The string's sections, top drive to bit, each as a string of its own: its pipe and
    /// length, with this string's hole, fluids, damping, laws and top (and no sections). A
    /// string without `[[model.section]]` is its own only section. What is a property of one
    /// section (its [`super::Section`] constants, buckling loads, stresses, impedance) is read
    /// off these.
    pub fn section_strings(&self) -> Vec<Drillstring> {
        if self.sections.is_empty() {
            return vec![self.clone()];
        }
        self.sections
            .iter()
            .map(|s| Drillstring {
                length: s.length,
                pipe: s.pipe.clone(),
                sections: Vec::new(),
                ..self.clone()
            })
            .collect()
    }

    /// The section at the bit, as a string of its own ([`Self::section_strings`]'s last).
    pub fn bit_section(&self) -> Drillstring {
        match self.sections.last() {
            None => self.clone(),
            Some(s) => Drillstring {
                length: s.length,
                pipe: s.pipe.clone(),
                sections: Vec::new(),
                ..self.clone()
            },
        }
    }

    /// The string with the regularisation widths of its contact and friction laws that act
    /// divided by `divisor`, and their keys (empty: nothing to refine). The widths are
    /// numerics, not physics: each smooths a set-valued law (a sign, a contact that switches on,
    /// Coulomb's |s| at zero slip), and a metric that depends on them is not converged
    /// (`drillopt verify`'s "smoothing" refinement). They are the bit law's `…_smoothing`
    /// parameters, and, when the wall has friction, the Coulomb law's `slip_smoothing` or, for
    /// the paper's torque-only friction, the wall law's `sign_smoothing`.
    pub fn with_smoothing_refined(&self, divisor: f64) -> (Drillstring, Vec<&'static str>) {
        let mut string = self.clone();
        let mut keys = string.bit.refine_smoothing(divisor);
        if string.wall.law().friction() > 0.0 {
            match &mut string.wall_friction {
                super::WallFriction::Coulomb { slip_smoothing } => {
                    *slip_smoothing /= divisor;
                    keys.push("model.wall.slip_smoothing");
                }
                super::WallFriction::Paper => keys.extend(string.wall.refine_smoothing(divisor)),
            }
        }
        (string, keys)
    }
}

/// Finite-element discretisation and reduction (MODEL.md §7).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Mesh {
    /// Number of 2-node beam elements N (6(N+1) DOF).
    pub elements: usize,
    /// The modes (and static corrections) kept in the reduced-order model.
    pub basis: super::BasisSpec,
}

impl Mesh {
    /// Total DOF count of the unconstrained mesh, 6(N+1).
    pub fn dof(&self) -> usize {
        6 * (self.elements + 1)
    }
}

/// What the driller sets at the top drive (MODEL.md §4, §11.8): the rotation speed and the
/// set-point of the top's law, the feed V0 (tops `feed` and `autodriller`) or the hook load's
/// WOB (top `hook_load`). Each top reads its own set-point; the other is 0.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct OperatingPoint {
    /// Rotation speed Ω, rad/s.
    pub omega: f64,
    /// Imposed axial velocity V0 (the feed, or the autodriller's set-point), m/s; 0 under a
    /// hook load.
    pub v0: f64,
    /// The hook load's surface WOB set-point W, N (> 0 pushes towards the bit); 0 under the
    /// other tops.
    #[serde(skip_serializing_if = "crate::units::is_zero")]
    pub wob: f64,
}

impl OperatingPoint {
    /// Ω (rad/s) with a feed or autodriller set-point V0 (m/s).
    pub const fn feed(omega: f64, v0: f64) -> Self {
        OperatingPoint {
            omega,
            v0,
            wob: 0.0,
        }
    }

    /// Ω (rad/s) with a hook load's WOB set-point W (N).
    pub const fn hook_load(omega: f64, wob: f64) -> Self {
        OperatingPoint {
            omega,
            v0: 0.0,
            wob,
        }
    }

    /// The point snapped to its canonical bits (Ω in rpm, V0 in m/h and the WOB in kN rounded to
    /// [`crate::units::POINT_DIGITS`] significant digits, [`crate::units::canonical_point`]): the
    /// same point reached by different arithmetic is the same evaluation-cache entry.
    pub fn canonical(&self) -> Self {
        let (omega, v0) = crate::units::canonical_point(self.omega, self.v0);
        OperatingPoint {
            omega,
            v0,
            wob: 1e3 * crate::units::round_point(self.wob / 1e3),
        }
    }

    /// Which set-point the point carries: the WOB when it has one (a hook load's is > 0), else
    /// the feed.
    pub fn kind(&self) -> SetPoint {
        if self.wob != 0.0 {
            SetPoint::Wob
        } else {
            SetPoint::Feed
        }
    }

    /// Its own set-point ([`Self::kind`]) in the unit it is shown in: V0 in m/h, or the WOB in kN.
    pub fn shown_set_point(&self) -> f64 {
        let kind = self.kind();
        kind.to_unit(self.set_point(kind))
    }

    /// The set-point of `kind`: V0 (m/s) or W (N).
    pub fn set_point(&self, kind: SetPoint) -> f64 {
        match kind {
            SetPoint::Feed => self.v0,
            SetPoint::Wob => self.wob,
        }
    }

    /// The point at Ω (rad/s) with the set-point `value` of `kind` (m/s or N).
    pub fn of(kind: SetPoint, omega: f64, value: f64) -> Self {
        match kind {
            SetPoint::Feed => Self::feed(omega, value),
            SetPoint::Wob => Self::hook_load(omega, value),
        }
    }
}

/// The set-point of an operating point as the JSON reports write it (flattened beside Ω): the
/// feed's `v0_m_s` and `v0_m_per_h`, or a hook load's `wob_n` and `wob_kn` (and then no V0,
/// which would read as off-bottom rotation).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum SetPointValue {
    Feed { v0_m_s: f64, v0_m_per_h: f64 },
    Wob { wob_n: f64, wob_kn: f64 },
}

impl SetPointValue {
    /// The set-point of `op` (its own kind, [`OperatingPoint::kind`]).
    pub fn of(op: &OperatingPoint) -> Self {
        match op.kind() {
            SetPoint::Feed => SetPointValue::Feed {
                v0_m_s: op.v0,
                v0_m_per_h: crate::units::to_m_per_h(op.v0),
            },
            SetPoint::Wob => SetPointValue::Wob {
                wob_n: op.wob,
                wob_kn: op.wob / 1e3,
            },
        }
    }

    /// The operating point at Ω (rad/s) with this set-point.
    pub fn at(&self, omega: f64) -> OperatingPoint {
        match *self {
            SetPointValue::Feed { v0_m_s, .. } => OperatingPoint::feed(omega, v0_m_s),
            SetPointValue::Wob { wob_n, .. } => OperatingPoint::hook_load(omega, wob_n),
        }
    }
}

/// The driller's second design variable besides Ω, which the top decides
/// ([`crate::model::TopDrive::set_point`]): the feed V0 or the hook load's WOB.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SetPoint {
    /// V0, m/s (shown in m/h; key `v0`).
    Feed,
    /// The surface WOB W, N (shown in kN; key `wob`).
    Wob,
}

impl SetPoint {
    /// The problem file's key of the set-point (`[operating_point]`, `[constraints]`, `[expect]`).
    pub fn key(self) -> &'static str {
        match self {
            SetPoint::Feed => "v0",
            SetPoint::Wob => "wob",
        }
    }

    /// Its symbol in tables and plots.
    pub fn symbol(self) -> &'static str {
        match self {
            SetPoint::Feed => "V0",
            SetPoint::Wob => "WOB",
        }
    }

    /// The unit it is shown in.
    pub fn unit(self) -> &'static str {
        match self {
            SetPoint::Feed => "m/h",
            SetPoint::Wob => "kN",
        }
    }

    /// SI (m/s or N) to the shown unit.
    pub fn to_unit(self, si: f64) -> f64 {
        match self {
            SetPoint::Feed => crate::units::to_m_per_h(si),
            SetPoint::Wob => si / 1e3,
        }
    }

    /// The shown unit to SI.
    pub fn from_unit(self, x: f64) -> f64 {
        match self {
            SetPoint::Feed => crate::units::from_m_per_h(x),
            SetPoint::Wob => x * 1e3,
        }
    }

    /// The dimension of its value.
    pub fn dimension(self) -> crate::units::Dimension {
        match self {
            SetPoint::Feed => crate::units::Dimension::Velocity,
            SetPoint::Wob => crate::units::Dimension::Force,
        }
    }
}

/// Time window and outputs of one simulation.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Simulation {
    /// Simulated time window, s.
    pub duration: f64,
    /// Nominal time step, s (refined automatically around impacts).
    pub time_step: f64,
    /// Time discarded before metrics are computed, s.
    pub settling_time: f64,
    /// Positions x where the radial displacement is recorded, m.
    pub probes: Vec<f64>,
    /// The state a run starts from.
    pub start: Start,
    /// The interval of the written time history (`simulate`'s `timeseries.csv` and plots); the
    /// metrics read every accepted step whatever it is. Not part of the canonical form (cache
    /// keys): no simulated number depends on it.
    #[serde(skip)]
    pub sample_interval: SampleInterval,
}

impl Simulation {
    /// The settling time of a run of `duration` seconds, s: `settling_time`, but at most half the
    /// run, so that the analysis window is never shorter than what it discards (a file's own
    /// duration always keeps its settling time: validation refuses more than half; a shorter
    /// `--duration` on the command line cuts it, and `simulate` and `verify` say so).
    pub fn settling_for(&self, duration: f64) -> f64 {
        self.settling_time.min(0.5 * duration)
    }
}

/// What a run writes out: every accepted step, or the states at a fixed interval.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SampleInterval {
    /// One row per accepted adaptive step (about 7 800 per simulated second on the seed).
    EveryStep,
    /// One row every Δ seconds (Δ > 0), from t = 0.
    Fixed(f64),
}

impl SampleInterval {
    /// The default: every 0.5 ms (2 kHz). It resolves the 10 ms averaging window of the stick-slip
    /// statistics with 20 samples, the highest axial mode of the seed's default basis (253 Hz)
    /// with 8 samples per period, and its Nyquist frequency (1 kHz) lies above the bit's static
    /// correction (468 Hz), the highest frequency of the reduced model.
    pub const DEFAULT: SampleInterval = SampleInterval::Fixed(5e-4);

    /// Rows a run of `duration` s writes at a fixed interval: ⌊duration/Δ⌋ + 1 (t = 0 included);
    /// `None` for every step (not known in advance).
    pub fn rows(self, duration: f64) -> Option<usize> {
        match self {
            SampleInterval::EveryStep => None,
            SampleInterval::Fixed(dt) => {
                // A whole number of intervals up to round-off (0.3 / 0.1 = 2.9999999999999996)
                // counts whole; a tolerance relative to the count added rows to long runs (a day
                // at 1 µs: 86 400 000 087 rows).
                let n = duration / dt;
                let whole = n.round();
                let n = if (n - whole).abs() <= 1e-9 * whole.max(1.0) {
                    whole
                } else {
                    n.floor()
                };
                Some(n as usize + 1)
            }
        }
    }
}

/// `[campbell]` of a problem file: what the critical speeds of `drillopt campbell` and of the
/// metric `critical_speed_margin` are sought against.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CampbellSettings {
    /// The multiple k of the rotation frequency that the bit excites besides 1× (mass unbalance,
    /// bent pipe), dimensionless, in [1, 50]; default [`CampbellSettings::DEFAULT_MULTIPLE`] = 3,
    /// the tri-cone bit, whose three cones leave a three-lobed bottom-hole pattern that excites
    /// the string at three times the rotation frequency (Dareing, J. Pet. Tech. 36, 1984; Spanos,
    /// Chevallier, Politis & Payne, *Oil and gas well drilling: a vibrations perspective*, Shock
    /// Vib. Digest 35, 2003). A PDC bit with n blades excites n×: a depth-of-cut bit law with a
    /// blade count (`model.bit.blades`) gives the default n instead.
    pub excitation_multiple: f64,
    /// Where `excitation_multiple` comes from (not part of the problem's canonical form: the
    /// value is).
    #[serde(skip)]
    pub source: MultipleSource,
}

/// Where a problem's excitation multiple K comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MultipleSource {
    /// `[campbell] excitation_multiple` of the file.
    File,
    /// The bit law's blade count (`model.bit.blades`).
    Blades,
    /// Neither: the tri-cone's 3.
    #[default]
    Default,
}

impl CampbellSettings {
    /// The tri-cone bit's 3×.
    pub const DEFAULT_MULTIPLE: f64 = 3.0;

    /// What a driller should know of K besides its value, or `None`: the tri-cone's default 3
    /// under a bit law `bit_law` (its registry name) that models a PDC bit without knowing its
    /// blades (`detournay`), whose blade count is the multiple it excites.
    pub fn note(&self, bit_law: &str) -> Option<String> {
        match (self.source, bit_law) {
            (MultipleSource::Default, "detournay") => Some(format!(
                "K = {} is the default, a tri-cone bit's; this file's bit law (detournay) is a PDC bit's, which excites its blade count: give it as [campbell] excitation_multiple",
                Self::DEFAULT_MULTIPLE
            )),
            _ => None,
        }
    }
}

impl Default for CampbellSettings {
    fn default() -> Self {
        CampbellSettings {
            excitation_multiple: Self::DEFAULT_MULTIPLE,
            source: MultipleSource::Default,
        }
    }
}

/// The state a run starts from (MODEL.md §4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Start {
    /// The steady drilling state of the operating point (bit, wall and damping loads on).
    #[default]
    Preloaded,
    /// The paper's start: static equilibrium under gravity without bit load.
    Unloaded,
}

impl Start {
    /// The name used in problem files (`simulation.start`).
    pub fn name(self) -> &'static str {
        match self {
            Start::Preloaded => "preloaded",
            Start::Unloaded => "unloaded",
        }
    }
}
