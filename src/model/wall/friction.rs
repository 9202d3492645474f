//! How the wall's friction acts on a node in contact (`[model.wall] friction_law`).
//!
//! - [`WallFriction::Coulomb`] (MODEL.md §11.2, the default): Coulomb friction on the slip of the
//!   contact point. The pipe touches the wall at R_ext n (n = (v, w)/r the outward normal); that
//!   material point slips over the fixed wall with an axial speed u̇ and a circumferential speed
//!   v_t = t·(v̇, ẇ) + R_ext θ̇x (t = e_x × n). The friction force −μ N s/|s| (N ≥ 0 the normal
//!   force, s = (u̇, v_t)) acts on u (axial drag), on (v, w) along t (it makes a rotating pipe
//!   climb the low side of the hole and drives backward whirl) and on θx with the lever arm R_ext.
//!   This is the friction of soft-string torque and drag (Johancsik, Friesen & Dawson, JPT 36(6),
//!   1984): rotating a string turns most of its axial drag into torque, in the ratio V : Ω R_ext.
//! - [`WallFriction::Paper`] (MODEL.md §5, Cunha Jr, Soize & Sampaio 2014, Eq. (3)): a torque
//!   −μ |F| R_bh tanh(θ̇x/ε) on θx only, the friction of the files that reproduce the paper.
//!
//! **Regularisation.** Coulomb's law is set-valued at s = 0. Here |s| is replaced by
//! S = √(|s|² + ε²) (ε = `slip_smoothing`, a slip speed), a smooth law with no switch:
//! f = −μ N s / S. It is the friction law at slip speeds well above ε (its magnitude is
//! μN (1 − ε²/(2|s|²)) there: 4·10⁻⁴ % low at the seed's Ω R_ext = 0.38 m/s and 0.3 % at its
//! feed V0 = 1.4 mm/s for the default ε = 10⁻⁴ m/s) and a viscous creep of coefficient μN/ε
//! below it. Why not Karnopp's stick–slip switch (Leine, van Campen & Keultjes, Nonlinear Dyn.
//! 16, 1998): a switch between sticking and slipping states per node, inside an implicit Newton
//! step, needs event location or a complementarity solve at every touching node; the smooth law
//! keeps one residual with an exact tangent, and the implicit integrator with its local error
//! control resolves the creep's stiffness μN/ε (the tangent is part of the Newton matrix, so a
//! stiff creep costs iterations, not stability). In a drilling string the contact points slip
//! almost always: the string turns (|s| ≥ Ω R_ext) or slides (|s| ≥ V0); only at the stuck bit's
//! end of a stick phase does |s| fall to the feed, and the default ε is 14 times below the
//! seed's feed. `drillopt verify` shows whether ε matters for a problem's metrics.

use crate::units::{Dimension, Range};

/// The friction of the wall on a node in contact (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case", tag = "friction_law")]
pub enum WallFriction {
    /// Coulomb friction on the slip (u̇, t·(v̇, ẇ) + R_ext θ̇x) of the contact point, with the
    /// smooth magnitude √(|s|² + ε²), ε = `slip_smoothing` in m/s.
    Coulomb { slip_smoothing: f64 },
    /// The paper's torque-only friction −μ |F| R_bh tanh(θ̇x/ε) (the law's `sign_smoothing` ε).
    Paper,
}

impl WallFriction {
    /// Default regularisation ε of the Coulomb law, m/s (see the module doc).
    pub const DEFAULT_SLIP_SMOOTHING: f64 = 1e-4;

    /// The Coulomb law with the default regularisation.
    pub const COULOMB: WallFriction = WallFriction::Coulomb {
        slip_smoothing: Self::DEFAULT_SLIP_SMOOTHING,
    };

    /// Admissible ε: above 1e-7 m/s (below, the creep coefficient μN/ε of a kilonewton contact
    /// exceeds 1e9 N·s/m and the Newton matrix loses its digits), below 0.01 m/s (above, the law
    /// misses a quarter of the friction at the seed's Ω R_ext).
    pub const SLIP_SMOOTHING_RANGE: Range = Range::closed(
        1e-7,
        1e-2,
        "a slip speed small against the feed and the rotation's surface speed",
    );

    /// The dimension of `slip_smoothing`.
    pub const SLIP_SMOOTHING_DIMENSION: Dimension = Dimension::Velocity;

    /// The name used in problem files (`model.wall.friction_law`).
    pub fn name(&self) -> &'static str {
        match self {
            WallFriction::Coulomb { .. } => "coulomb",
            WallFriction::Paper => "paper",
        }
    }

    /// The names a problem file may give.
    pub const NAMES: [&'static str; 2] = ["coulomb", "paper"];
}

impl Default for WallFriction {
    fn default() -> Self {
        Self::COULOMB
    }
}
