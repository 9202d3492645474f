//! The eigenvalues of the linearised system at one spin rate Ω, each labelled by family and,
//! for bending, by whirl.
//!
//! The quadratic eigenproblem (λ² M + λ (Ω G + D) + K) x = 0 is solved in first-order form,
//! z = (x, λx) of size 2n, with the state matrix
//!
//!   A = [ 0, I ; −M⁻¹K, −M⁻¹(Ω G + D) ],   A z = λ z,
//!
//! by faer's general real eigendecomposition (Hessenberg–Schur–eigenvectors; sequential without
//! faer's rayon feature). The eigenvalues come in complex-conjugate pairs; an undamped gyroscopic
//! system with K positive definite has them on the imaginary axis, λ = ±iω (Genta, *Dynamics of
//! Rotating Systems*, 2005, §4.4). Each pair gives one [`EigenMode`] with ω = Im λ > 0.
//!
//! **Family**: the family holding most of the kinetic energy of x, Re Σ_{j ∈ family} x̄ⱼ (M x)ⱼ
//! (every coordinate lives on one family; bending counts both planes).
//!
//! **Whirl**: the lateral displacements of the eigenvector at the nodes, V = Φ_v x and
//! W = Φ_w x, describe the orbit v(t) = Re(V e^{iωt}), w(t) = Re(W e^{iωt}) of every node, whose
//! angular momentum about +x averages to v ẇ − w v̇ = −ω Im(V̄ W). The circularity
//!
//!   κ = Σ_nodes −2 Im(V̄ W) / Σ_nodes (|V|² + |W|²)   ∈ [−1, 1]
//!
//! is +1 for circular orbits turning from +y to +z (the sense of a positive spin θ̇x, MODEL.md §2),
//! −1 for circular orbits turning the other way, 0 for planar motion. A bending mode whirls
//! **forward** when κ has the sign of Ω, **backward** when it has the other (Lalanne & Ferraris,
//! *Rotordynamics Prediction in Engineering*, 1998, §2.3: the sense of the orbit against the
//! spin). At Ω = 0 there is no spin to compare with: the whirl is `none`.

use super::{CampbellError, LinearSystem};
use crate::rom::Family;
use faer::Mat;
use nalgebra::{Complex, DMatrix, DVector};
use serde::Serialize;

/// The family of a mode of the linearised string.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModeFamily {
    Axial,
    Torsional,
    /// Lateral, in either plane or both.
    Bending,
}

impl ModeFamily {
    pub fn name(self) -> &'static str {
        match self {
            ModeFamily::Axial => "axial",
            ModeFamily::Torsional => "torsional",
            ModeFamily::Bending => "bending",
        }
    }

    fn of(family: Family) -> Self {
        match family {
            Family::Axial => ModeFamily::Axial,
            Family::Torsional => ModeFamily::Torsional,
            Family::BendingY | Family::BendingZ => ModeFamily::Bending,
        }
    }
}

/// The sense of a bending mode's orbit against the spin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Whirl {
    /// The orbit turns with the spin (κ Ω > 0).
    Forward,
    /// The orbit turns against the spin (κ Ω < 0).
    Backward,
    /// A bending mode under spin whose orbit is nearly a line (|κ| ≤ [`PLANAR`]): it turns
    /// neither way to speak of (an anisotropic support, a mode of one plane).
    Planar,
    /// Not a bending mode, or no spin (Ω = 0): no whirl sense to give.
    None,
}

impl Whirl {
    pub fn name(self) -> &'static str {
        match self {
            Whirl::Forward => "forward",
            Whirl::Backward => "backward",
            Whirl::Planar => "planar",
            Whirl::None => "none",
        }
    }
}

/// |κ| at or below which a bending mode's orbit is called [`Whirl::Planar`]: 1e-3, an ellipse
/// whose minor axis is at most 1/2000 of its major one (κ = 2ab/(a² + b²) ≈ 2b/a for b ≪ a).
/// Below it the sense of the orbit is round-off or a negligible gyroscopic coupling (orbits with
/// |κ| of order 1e-5 were called "forward", issue 13), not a whirl a driller should read.
pub const PLANAR: f64 = 1e-3;

/// The whirl of a mode of `family` with circularity κ at spin rate Ω (rad/s): none for a mode
/// that is not bending or without spin, planar for |κ| ≤ [`PLANAR`], else forward when κ has the
/// sign of Ω and backward when it has the other.
pub fn classify(family: ModeFamily, omega: f64, circularity: f64) -> Whirl {
    if family != ModeFamily::Bending || omega == 0.0 {
        Whirl::None
    } else if circularity.abs() <= PLANAR {
        Whirl::Planar
    } else if circularity * omega > 0.0 {
        Whirl::Forward
    } else {
        Whirl::Backward
    }
}

/// One eigenpair of the linearised system at a spin rate.
#[derive(Debug, Clone)]
pub struct EigenMode {
    /// λ, 1/s (Im λ > 0).
    pub eigenvalue: Complex<f64>,
    /// Im λ / 2π, Hz: the (damped) natural frequency.
    pub freq_hz: f64,
    /// −Re λ / |λ|, dimensionless (0 undamped, to round-off).
    pub damping_ratio: f64,
    pub family: ModeFamily,
    /// Kinetic-energy share of [axial, torsional, bending], summing to 1.
    pub shares: [f64; 3],
    pub whirl: Whirl,
    /// κ of the module documentation, in [−1, 1].
    pub circularity: f64,
    /// Share of the lateral motion in the vertical plane, Σ|W|² / Σ(|V|² + |W|²) (NaN without
    /// lateral motion).
    pub vertical_share: f64,
    /// x, normalised to xᴴ M x = 1.
    pub vector: DVector<Complex<f64>>,
}

/// The eigenpairs at one spin rate, by increasing frequency.
#[derive(Debug, Clone)]
pub struct Spectrum {
    /// Ω, rad/s.
    pub omega: f64,
    pub modes: Vec<EigenMode>,
    /// Eigenvalues with no oscillating part (real: overdamped or unstable directions).
    pub non_oscillatory: usize,
}

/// The 2n eigenvalues λ of the first-order form and its eigenvectors z = (x, λx) as columns.
pub type StateEigen = (Vec<Complex<f64>>, DMatrix<Complex<f64>>);

/// All 2n eigenvalues and eigenvectors z = (x, λx) of the first-order form at `omega`.
pub fn state_eigen(sys: &LinearSystem, omega: f64) -> Result<StateEigen, CampbellError> {
    let n = sys.size();
    let [k, g, d] = &sys.inv_mass;
    // The state (x, ẋ/w) with w a typical frequency, sqrt(max |(M⁻¹K)_ii|): the similarity
    // diag(I, I/w) balances the blocks (M⁻¹K reaches 1e10 1/s² beside the identity), and without
    // it faer's Schur reordering looped without end on a stiff wall (3.2e12 N/m; issue 34).
    let w = (0..n)
        .map(|i| k[(i, i)].abs())
        .fold(0.0, f64::max)
        .sqrt()
        .max(1.0);
    let a = Mat::<f64>::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => 0.0,
        (true, false) => w * f64::from(u8::from(j - n == i)),
        (false, true) => -k[(i - n, j)] / w,
        (false, false) => -(omega * g[(i - n, j - n)] + d[(i - n, j - n)]),
    });
    let evd = a.eigen().map_err(|_| CampbellError::Eigen {
        omega_rpm: crate::units::to_rpm(omega),
    })?;
    let s = evd.S().column_vector();
    let u = evd.U();
    let values = (0..2 * n).map(|j| s[j]).collect();
    // Back to z = (x, λx): the lower half times w.
    let vectors = DMatrix::from_fn(
        2 * n,
        2 * n,
        |i, j| {
            if i < n { u[(i, j)] } else { u[(i, j)] * w }
        },
    );
    Ok((values, vectors))
}

/// The spectrum of `sys` at spin rate `omega` (rad/s, ≥ 0), modes by increasing frequency.
pub fn spectrum(sys: &LinearSystem, omega: f64) -> Result<Spectrum, CampbellError> {
    let n = sys.size();
    let (values, vectors) = state_eigen(sys, omega)?;
    let scale = values.iter().map(|l| l.norm()).fold(0.0, f64::max);
    let mut modes = Vec::with_capacity(n);
    let mut non_oscillatory = 0;
    for (j, &lambda) in values.iter().enumerate() {
        if lambda.im.abs() <= 1e-12 * scale {
            // Real to round-off: counted once (a pair of tiny conjugates by its lower member).
            if lambda.im <= 0.0 {
                non_oscillatory += 1;
            }
            continue;
        }
        if lambda.im < 0.0 {
            // The conjugate of a kept eigenvalue.
            continue;
        }
        let x = vectors.view((0, j), (n, 1)).column(0).into_owned();
        modes.push(label(sys, omega, lambda, x));
    }
    modes.sort_by(|a, b| a.freq_hz.total_cmp(&b.freq_hz));
    Ok(Spectrum {
        omega,
        modes,
        non_oscillatory,
    })
}

/// M x.
pub(super) fn times_mass(sys: &LinearSystem, x: &DVector<Complex<f64>>) -> DVector<Complex<f64>> {
    if sys.mass_is_identity {
        return x.clone();
    }
    DVector::from_fn(x.len(), |i, _| {
        (0..x.len()).fold(Complex::new(0.0, 0.0), |acc, j| {
            acc + x[j] * sys.mass[(i, j)]
        })
    })
}

/// The modal assurance criterion |xᴴ M y|² / (xᴴ M x · yᴴ M y) of two eigenvectors normalised
/// to xᴴ M x = 1: 1 for the same shape, 0 for M-orthogonal shapes.
pub(super) fn mac(sys: &LinearSystem, x: &DVector<Complex<f64>>, y: &DVector<Complex<f64>>) -> f64 {
    let my = times_mass(sys, y);
    x.iter()
        .zip(my.iter())
        .map(|(a, b)| a.conj() * b)
        .sum::<Complex<f64>>()
        .norm_sqr()
}

/// The [`EigenMode`] of eigenvalue `lambda` and eigenvector `x`.
fn label(
    sys: &LinearSystem,
    omega: f64,
    lambda: Complex<f64>,
    x: DVector<Complex<f64>>,
) -> EigenMode {
    let mx = times_mass(sys, &x);
    let norm2: f64 = x
        .iter()
        .zip(mx.iter())
        .map(|(a, b)| (a.conj() * b).re)
        .sum();
    let mut shares = [0.0; 3];
    for (j, f) in sys.families.iter().enumerate() {
        shares[ModeFamily::of(*f) as usize] += (x[j].conj() * mx[j]).re / norm2;
    }
    let x = x.unscale(norm2.max(f64::MIN_POSITIVE).sqrt());
    let family = [
        ModeFamily::Axial,
        ModeFamily::Torsional,
        ModeFamily::Bending,
    ][(0..3)
        .max_by(|&a, &b| shares[a].total_cmp(&shares[b]))
        .unwrap_or(2)];
    let project = |rows: &DMatrix<f64>| -> Vec<Complex<f64>> {
        (0..rows.nrows())
            .map(|r| (0..x.len()).fold(Complex::new(0.0, 0.0), |acc, j| acc + x[j] * rows[(r, j)]))
            .collect()
    };
    let (v, w) = (project(&sys.lateral[0]), project(&sys.lateral[1]));
    let circularity = circularity(&v, &w);
    let lateral: f64 = v.iter().chain(&w).map(|c| c.norm_sqr()).sum();
    let vertical_share = w.iter().map(|c| c.norm_sqr()).sum::<f64>() / lateral;
    let whirl = classify(family, omega, circularity);
    EigenMode {
        eigenvalue: lambda,
        freq_hz: lambda.im / std::f64::consts::TAU,
        damping_ratio: -lambda.re / lambda.norm(),
        family,
        shares,
        whirl,
        circularity,
        vertical_share,
        vector: x,
    }
}

/// κ = Σ −2 Im(V̄ W) / Σ (|V|² + |W|²) of complex lateral amplitudes (see the module
/// documentation); 0 without lateral motion.
pub fn circularity(v: &[Complex<f64>], w: &[Complex<f64>]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (a, b) in v.iter().zip(w) {
        num += -2.0 * (a.conj() * b).im;
        den += a.norm_sqr() + b.norm_sqr();
    }
    if den > 0.0 { num / den } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rayleigh damping C = c M_pipe + β K damps a mode of circular frequency ω with the ratio
    /// ζ = c/(2ω) + βω/2 (Clough & Penzien, *Dynamics of Structures*, 2nd ed., §12.4) when the
    /// mass is M_pipe: with c = 0 and no fluid (M = M_pipe), ζ = βω/2 for every mode, and the
    /// eigenvalue's modulus |λ| is the undamped ω. Read off the damped eigenvalues of the
    /// linearised string (a different computation: the first-order form of M, D, K).
    #[test]
    fn stiffness_proportional_damping_gives_each_mode_the_ratio_beta_omega_over_two() {
        use crate::campbell::{LinearSystem, Linearisation};
        use crate::model::BasisSpec;
        use crate::rom::ReducedModel;
        let mut string = crate::problem::Problem::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed_mc2014.toml"
        ))
        .unwrap()
        .model;
        string.damping = 0.0;
        string.fluid_density = 0.0;
        string.stiffness_damping = 1e-4;
        let model = ReducedModel::new(&string, 30, &BasisSpec::DEFAULT).unwrap();
        let options = Linearisation {
            contact: false,
            damping: true,
        };
        let sys = LinearSystem::about_rest(&model, options).unwrap();
        let s = spectrum(&sys, 0.0).unwrap();
        assert!(s.modes.len() > 40, "{} modes", s.modes.len());
        let mut families = [0; 3];
        for m in &s.modes {
            let omega = m.eigenvalue.norm();
            let expected = 0.5 * string.stiffness_damping * omega;
            // Round-off of the eigen solve: relative to the largest |λ|, so absolute in ζ.
            assert!(
                (m.damping_ratio - expected).abs() < 1e-8 * expected + 1e-10,
                "{:?} mode at {:.2} Hz: ζ = {} against βω/2 = {expected}",
                m.family,
                m.freq_hz,
                m.damping_ratio
            );
            families[m.family as usize] += 1;
        }
        assert!(families.iter().all(|&n| n > 0), "{families:?}");
        // Without β the same modes are undamped.
        string.stiffness_damping = 0.0;
        let model = ReducedModel::new(&string, 30, &BasisSpec::DEFAULT).unwrap();
        let sys = LinearSystem::about_rest(&model, options).unwrap();
        let s = spectrum(&sys, 0.0).unwrap();
        assert!(s.modes.iter().all(|m| m.damping_ratio.abs() < 1e-9));
    }

    #[test]
    fn circularity_of_circles_and_lines() {
        let one = Complex::new(1.0, 0.0);
        let i = Complex::new(0.0, 1.0);
        // v = cos ωt, w = sin ωt: W = −i, turning from +y to +z.
        assert!((circularity(&[one], &[-i]) - 1.0).abs() < 1e-15);
        assert!((circularity(&[one], &[i]) + 1.0).abs() < 1e-15);
        assert_eq!(circularity(&[one], &[one * 0.3]), 0.0);
        assert_eq!(circularity(&[], &[]), 0.0);
        // An ellipse with semi-axes 1 and 0.5: κ = 2ab/(a² + b²) = 0.8.
        assert!((circularity(&[one], &[-i * 0.5]) - 0.8).abs() < 1e-15);
    }

    #[test]
    fn nearly_planar_orbits_are_planar_not_forward() {
        let one = Complex::new(1.0, 0.0);
        let i = Complex::new(0.0, 1.0);
        // Semi-axes 1 and 2.5e-5: κ = 2ab/(a² + b²) ≈ 5e-5, the orbits issue 13 saw called
        // "forward"; at 1/1000 (κ ≈ 2e-3) the ellipse turns visibly.
        let thin = circularity(&[one], &[-i * 2.5e-5]);
        assert!((thin - 5e-5).abs() < 1e-12, "{thin}");
        assert_eq!(classify(ModeFamily::Bending, 6.0, thin), Whirl::Planar);
        assert_eq!(classify(ModeFamily::Bending, -6.0, thin), Whirl::Planar);
        assert_eq!(classify(ModeFamily::Bending, 6.0, PLANAR), Whirl::Planar);
        let open = circularity(&[one], &[-i * 1e-3]);
        assert_eq!(classify(ModeFamily::Bending, 6.0, open), Whirl::Forward);
        assert_eq!(classify(ModeFamily::Bending, -6.0, open), Whirl::Backward);
        assert_eq!(classify(ModeFamily::Bending, 6.0, -open), Whirl::Backward);
        // No spin, or not bending: no whirl sense at all.
        assert_eq!(classify(ModeFamily::Bending, 0.0, open), Whirl::None);
        assert_eq!(classify(ModeFamily::Torsional, 6.0, open), Whirl::None);
        assert_eq!(classify(ModeFamily::Bending, 0.0, 0.0), Whirl::None);
        // The JSON name.
        assert_eq!(serde_json::to_string(&Whirl::Planar).unwrap(), "\"planar\"");
        assert_eq!(Whirl::Planar.name(), "planar");
    }
}
