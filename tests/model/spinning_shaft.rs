//! A spinning shaft against its closed form (MODEL.md §3 [settled, turn 3], issue 28 item 5): with
//! the gyroscopic sign of the spin rate θ̇x − θy θ̇z, forward whirl stiffens with Ω, and `campbell`
//! labels the stiffening branch forward.
//!
//! Circular whirl of an isotropic shaft spinning at Ω about +x: r = v + i w = φ(x) e^{iωt}, ω > 0
//! an orbit turning +y → +z with the spin (forward), ω < 0 against it (backward). With the
//! section rotation ψ = θz − i θy (= r′ without shear: θz = v′, θy = −w′) the shaft's equations,
//! from the kinetic energy of MODEL.md §3 linearised about θ̇x = Ω (f_y = 2ρIΩ θ̇z,
//! f_z = −2ρIΩ θ̇y), are
//!
//!   m r̈ = κGA (r″ − ψ′),     ρI ψ̈ − 2iρIΩ ψ̇ = EI ψ″ + κGA (r′ − ψ),
//!
//! m = ρA + ρ_f A_f the lateral mass per length (the fluid adds no rotatory inertia). For
//! r, ψ ∝ e^{sx} e^{iωt} and J = ρI (ω² − 2Ωω):
//!
//!   EI S² + (J + m ω² EI/κGA) S − m ω² (1 − J/κGA) = 0,   S = s²,
//!
//! one root S = α² > 0, one S = −β² < 0, and ψ/r = s + m ω²/(κGA s). In the Rayleigh limit
//! (κGA → ∞) it is EI φ'''' + J φ'' − m ω² φ = 0, and a pinned–pinned shaft (φ = sin kx,
//! k = nπ/L) has the classical frequency equation (Lalanne & Ferraris 1998, §2; Genta 2005, §5)
//!
//!   (m + ρI k²) ω² − 2ρI Ω k² ω − EI k⁴ = 0,
//!
//! whose positive root (forward) rises with Ω and whose negative root (backward) falls.
//!
//! The string's own supports (MODEL.md §4) are clamped–pinned for bending: v = w = θy = θz = 0 at
//! x = 0, v = w = 0 at the bit. There r = ψ = 0 at x = 0 and r = EI ψ′ = 0 at x = L, and with
//! r = A cosh αx + B sinh αx + C cos βx + D sin βx (ψ = p(A sinh + B cosh) + q(−C sin + D cos),
//! p = α + mω²/(κGA α), q = β − mω²/(κGA β)) the frequency equation is
//!
//!   (cosh αL − cos βL)(pα sinh αL + pβ sin βL) − (sinh αL − (p/q) sin βL)(pα cosh αL + qβ cos βL) = 0,
//!
//! exact for the Timoshenko shaft with rotatory and gyroscopic inertia. It is solved here by a
//! scan and bisection, independently of the finite elements.
//!
//! The shaft: the seed's section (R 40/60 mm, steel, inner mud 1200 kg/m³), 2 m long, so that
//! rotatory inertia and shear matter (1–8 % on the lowest three pairs). The relative split of a pair is
//! about 2Ω r_g / c (r_g = √(I/A), c = √(EA/m)), 1.5e-3 at 1000 rpm, whatever the length: the
//! library tests spin at 300–3000 rad/s, where the split is 45–450 times the tolerance.

use crate::common;

use drillopt::campbell::*;
use drillopt::model::{BasisSpec, Drillstring};
use drillopt::rom::{Family, ReducedModel};
use nalgebra::DMatrix;
use std::f64::consts::{PI, TAU};

/// Length of the short shaft, m, and its elements (5 cm each).
const LENGTH: f64 = 2.0;
const ELEMENTS: usize = 40;

/// Relative tolerance on each whirl frequency against the closed form.
const TOLERANCE: f64 = 1e-4;

/// κ_s of a shaft without shear flexibility (the Rayleigh limit): the shear correction of the
/// frequencies, about ½ (E/κ_s G) r_g² k², is then below 5e-6 on the lowest three pairs. Stiffer
/// shear only spoils the round-off: it puts the element's shear modes at κ_s G A/ρI and the
/// eigensolvers' absolute error grows with them.
const RIGID_SHEAR: f64 = 1e4;

const NO_WALL: Linearisation = Linearisation {
    contact: false,
    damping: false,
};

/// The seed's string, cut to the short shaft, with the shear factor `shear_factor`.
fn shaft(shear_factor: f64) -> Drillstring {
    let mut s = common::seed().model;
    s.length = LENGTH;
    s.pipe.shear_factor = shear_factor;
    s
}

/// The closed forms of the module documentation, from Table 1's raw numbers.
struct Shaft {
    ei: f64,
    kga: f64,
    m: f64,
    rho_i: f64,
    length: f64,
}

impl Shaft {
    fn new(shear_factor: f64, length: f64) -> Self {
        use common::Table1 as T;
        Shaft {
            ei: T::E * T::inertia(),
            kga: shear_factor * T::shear_modulus() * T::area(),
            m: T::lateral_mass(),
            rho_i: T::RHO * T::inertia(),
            length,
        }
    }

    /// The pinned–pinned Rayleigh shaft's whirl frequencies of wavenumber k = nπ/L at spin Ω
    /// (rad/s): (forward, backward) magnitudes, rad/s.
    fn pinned_pinned_rayleigh(&self, n: usize, spin: f64) -> (f64, f64) {
        let k2 = (n as f64 * PI / self.length).powi(2);
        let (a, b, c) = (
            self.m + self.rho_i * k2,
            self.rho_i * spin * k2,
            self.ei * k2 * k2,
        );
        let root = (b * b + a * c).sqrt();
        ((b + root) / a, (root - b) / a)
    }

    /// The clamped–pinned frequency determinant at the signed whirl frequency w (rad/s; > 0
    /// forward), times q / cosh² αL (finite for every w below the shear cut-off).
    fn clamped_pinned_determinant(&self, spin: f64, w: f64) -> f64 {
        let j = self.rho_i * (w * w - 2.0 * spin * w);
        let mw2 = self.m * w * w;
        let b = j + mw2 * self.ei / self.kga;
        let c = mw2 * (1.0 - j / self.kga);
        let disc = (b * b + 4.0 * self.ei * c).sqrt();
        let alpha = ((disc - b) / (2.0 * self.ei)).sqrt();
        let beta = ((disc + b) / (2.0 * self.ei)).sqrt();
        let p = alpha + mw2 / (self.kga * alpha);
        let q = beta - mw2 / (self.kga * beta);
        let l = self.length;
        let (t, e) = ((alpha * l).tanh(), 1.0 / (alpha * l).cosh());
        let (sn, cs) = ((beta * l).sin(), (beta * l).cos());
        (1.0 - cs * e) * (p * alpha * t + p * beta * sn * e) * q
            - (q * t - p * sn * e) * (p * alpha + q * beta * cs * e)
    }

    /// The n-th clamped–pinned whirl frequency (rad/s, magnitude) of sense `forward` at spin Ω:
    /// the n-th sign change of the determinant scanning |ω| up from 1 rad/s by 0.1 %, bisected
    /// to round-off.
    fn clamped_pinned(&self, n: usize, spin: f64, forward: bool) -> f64 {
        let sign = if forward { 1.0 } else { -1.0 };
        let d = |s: f64| self.clamped_pinned_determinant(spin, sign * s);
        let (mut s, mut found) = (1.0, 0);
        let mut ds = d(s);
        loop {
            let next = s * 1.001;
            let dn = d(next);
            assert!(
                next < 1e6 && dn.is_finite(),
                "no root {n} below {next} rad/s"
            );
            if (ds > 0.0) != (dn > 0.0) {
                found += 1;
                if found == n {
                    let (mut a, mut b, mut da) = (s, next, ds);
                    for _ in 0..100 {
                        let mid = 0.5 * (a + b);
                        let dm = d(mid);
                        if (dm > 0.0) == (da > 0.0) {
                            (a, da) = (mid, dm);
                        } else {
                            b = mid;
                        }
                    }
                    return 0.5 * (a + b);
                }
            }
            (s, ds) = (next, dn);
        }
    }
}

/// The determinant's solver reproduces the Euler–Bernoulli clamped–pinned beam (tan βL = tanh βL)
/// without spin, rotatory inertia or shear, and in the Rayleigh limit its spin splits a pair the
/// way the pinned–pinned closed form does to first order in Ω (a check of the helper itself).
#[test]
fn the_clamped_pinned_frequency_equation_has_its_limits() {
    let mut s = Shaft::new(RIGID_SHEAR * 1e6, LENGTH);
    s.rho_i *= 1e-12;
    for n in 1..=3 {
        let bl = common::clamped_pinned_root(n);
        let expected = bl * bl / (LENGTH * LENGTH) * (s.ei / s.m).sqrt();
        for forward in [true, false] {
            let w = s.clamped_pinned(n, 0.0, forward);
            assert!(
                (w - expected).abs() < 1e-9 * expected,
                "mode {n}: {w} vs {expected}"
            );
        }
    }
}

/// The bending pairs of a spectrum, lowest first: (forward, backward) frequencies in Hz, each
/// pair checked to hold one orbit of each sense, circular (|κ| = 1 to 1e-3: the eigenvectors of
/// a pair split by a few per mille are accurate to round-off over the split).
fn whirl_pairs(s: &Spectrum, count: usize) -> Vec<(f64, f64)> {
    let bending: Vec<&EigenMode> = s
        .modes
        .iter()
        .filter(|m| m.family == ModeFamily::Bending)
        .collect();
    bending[..2 * count]
        .chunks(2)
        .map(|p| {
            for m in p {
                assert!(
                    (m.circularity.abs() - 1.0).abs() < 1e-2,
                    "κ = {} at {} Hz",
                    m.circularity,
                    m.freq_hz
                );
            }
            let of = |w: Whirl| p.iter().find(|m| m.whirl == w).map(|m| m.freq_hz);
            match (of(Whirl::Forward), of(Whirl::Backward)) {
                (Some(f), Some(b)) => (f, b),
                _ => panic!("a pair without one whirl of each sense: {:?}", p),
            }
        })
        .collect()
}

/// The largest relative error of the pairs against (forward, backward) closed forms in rad/s,
/// with the checks that the forward member is the higher and the split is resolved.
fn compare(pairs: &[(f64, f64)], expected: &[(f64, f64)], what: &str) -> f64 {
    let mut worst: f64 = 0.0;
    for (n, ((f, b), (ef, eb))) in pairs.iter().zip(expected).enumerate() {
        let (f, b) = (TAU * f, TAU * b);
        let (ef_err, eb_err) = ((f - ef).abs() / ef, (b - eb).abs() / eb);
        assert!(
            ef_err < TOLERANCE && eb_err < TOLERANCE,
            "{what}, pair {}: forward {f} vs {ef}, backward {b} vs {eb} rad/s",
            n + 1
        );
        assert!(f > b, "{what}, pair {}: forward whirl stiffens", n + 1);
        assert!(
            (ef - eb) / ef > 20.0 * TOLERANCE,
            "{what}: the split must be resolved"
        );
        worst = worst.max(ef_err).max(eb_err);
    }
    worst
}

/// The lowest `count` modes of the restricted (M, K) of a finite-element model, as a
/// [`LinearSystem`] in modal coordinates (M = I, K = Λ, G and the lateral rows projected, each
/// mode's family the one holding most of its mass), as `ReducedModel` builds its basis: the stiff
/// directions of the mesh (shear, axial) stay out of the first-order eigenproblem.
fn modal_system(
    mass: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    gyroscopic: DMatrix<f64>,
    families: &[Family],
    lateral: [DMatrix<f64>; 2],
    count: usize,
) -> LinearSystem {
    let l = mass.cholesky().expect("M positive definite").l();
    let l_inv = l.try_inverse().unwrap();
    let a = &l_inv * stiffness * l_inv.transpose();
    let eigen = nalgebra::SymmetricEigen::new(0.5 * (&a + a.transpose()));
    let mut order: Vec<usize> = (0..a.nrows()).collect();
    order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    let modes = l_inv.transpose() * eigen.eigenvectors.select_columns(&order[..count]);
    let family = |j: usize| {
        let x = modes.column(j);
        let share = |f: Family| -> f64 {
            (0..x.len())
                .filter(|&i| families[i] == f)
                .map(|i| x[i] * x[i])
                .sum()
        };
        [
            Family::Axial,
            Family::Torsional,
            Family::BendingY,
            Family::BendingZ,
        ]
        .into_iter()
        .max_by(|&a, &b| share(a).total_cmp(&share(b)))
        .unwrap()
    };
    LinearSystem::from_parts(
        DMatrix::identity(count, count),
        DMatrix::from_diagonal(
            &order[..count]
                .iter()
                .map(|&i| eigen.eigenvalues[i])
                .collect::<Vec<_>>()
                .into(),
        ),
        modes.transpose() * gyroscopic * &modes,
        None,
        (0..count).map(family).collect(),
        lateral.map(|rows| rows * &modes),
    )
    .unwrap()
}

/// The model's Campbell spectrum of the short shaft simply supported (θ free at both ends, which
/// the string's supports cannot express: the model's finite-element matrices restricted by hand
/// and reduced to their lowest 30 modes), in the Rayleigh limit, against
/// (m + ρI k²) ω² − 2ρI Ω k² ω − EI k⁴ = 0: both branches of the lowest three pairs within 1e-4
/// at Ω = 300, 1000 and 3000 rad/s, the forward one the higher.
#[test]
fn a_simply_supported_rayleigh_shaft_whirls_as_its_closed_form() {
    let string = shaft(RIGID_SHEAR);
    let m = common::simply_supported(&string, ELEMENTS);
    let sys = modal_system(
        m.mass,
        m.stiffness,
        m.gyroscopic,
        &m.families,
        m.lateral,
        30,
    );
    let closed = Shaft::new(RIGID_SHEAR, LENGTH);
    let mut worst: f64 = 0.0;
    for spin in [300.0, 1000.0, 3000.0] {
        let pairs = whirl_pairs(&spectrum(&sys, spin).unwrap(), 3);
        let expected: Vec<(f64, f64)> = (1..=3)
            .map(|k| closed.pinned_pinned_rayleigh(k, spin))
            .collect();
        worst = worst.max(compare(&pairs, &expected, &format!("Ω = {spin} rad/s")));
    }
    eprintln!("simply supported Rayleigh shaft: largest relative error {worst:.2e}");
}

/// The same through the production path (`ReducedModel` with the default basis and
/// `LinearSystem::about_rest` without the wall, as `drillopt campbell --no-contact` does) on the
/// string's own clamped–pinned supports, against the clamped–pinned closed form: in the Rayleigh
/// limit (three pairs) and with the pipe's own (Cowper) shear factor (the lowest pair only: with
/// shear flexibility the mesh error falls as h², and on 40 elements it is 9e-6, 9e-5 and 3.5e-4
/// on the first three pairs; 2.3e-6, 2.6e-5 and 9e-5 on 80).
#[test]
fn the_string_spinning_on_its_own_supports_whirls_as_its_closed_form() {
    for (shear, count) in [(RIGID_SHEAR, 3), (common::Table1::cowper(), 1)] {
        let model = ReducedModel::new(&shaft(shear), ELEMENTS, &BasisSpec::DEFAULT).unwrap();
        let sys = LinearSystem::about_rest(&model, NO_WALL).unwrap();
        let closed = Shaft::new(shear, LENGTH);
        let mut worst: f64 = 0.0;
        for spin in [300.0, 1000.0, 3000.0] {
            let pairs = whirl_pairs(&spectrum(&sys, spin).unwrap(), count);
            let expected: Vec<(f64, f64)> = (1..=count)
                .map(|k| {
                    (
                        closed.clamped_pinned(k, spin, true),
                        closed.clamped_pinned(k, spin, false),
                    )
                })
                .collect();
            worst = worst.max(compare(
                &pairs,
                &expected,
                &format!("κ_s = {shear}, Ω = {spin} rad/s"),
            ));
        }
        eprintln!("clamped–pinned shaft, κ_s = {shear}: largest relative error {worst:.2e}");
    }
}

/// `drillopt campbell SHAFT --no-contact` on the short shaft (the seed's file cut to 2 m and 40
/// elements, its default basis, Cowper's shear): the lowest bending pair at 100–1000 rpm is one
/// curve labelled forward that rises with Ω and one labelled backward that falls, each within 1e-4
/// of the clamped–pinned closed form at every speed (at 1000 rpm the split is 1.5e-3, 15 times
/// the tolerance).
#[test]
fn campbell_labels_the_stiffening_branch_of_a_spinning_shaft_forward() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = std::fs::read_to_string(common::SEED).unwrap();
    for (from, to) in [
        ("name = \"seed_mc2014\"", "name = \"spinning_shaft\""),
        ("length = \"35 m\"", "length = \"2 m\""),
        ("elements = 105 ", "elements = 40 "),
        ("probes = [\"20 m\"]", "probes = [\"1 m\"]"),
    ] {
        assert!(text.contains(from), "the seed file has `{from}`");
        text = text.replacen(from, to, 1);
    }
    let problem = dir.path().join("spinning_shaft.toml");
    std::fs::write(&problem, text).unwrap();
    let out = dir.path().join("campbell");
    let run = common::drillopt(&[
        "campbell",
        problem.to_str().unwrap(),
        "--no-contact",
        "--omega-range",
        "100rpm..1000rpm",
        "--points",
        "4",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let c: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("campbell.json")).unwrap()).unwrap();
    assert_eq!(c["linearisation"]["contact"], false);
    let rpm: Vec<f64> = c["omega_rpm"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let mut bending: Vec<&serde_json::Value> = c["modes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["family"] == "bending")
        .collect();
    bending.sort_by_key(|m| m["mode"].as_u64().unwrap());
    let closed = Shaft::new(common::Table1::cowper(), LENGTH);
    let mut worst: f64 = 0.0;
    for m in &bending[..2] {
        let forward = match m["whirl"].as_str().unwrap() {
            "forward" => true,
            "backward" => false,
            other => panic!("the lowest pair whirls, not {other}: {m}"),
        };
        let f: Vec<f64> = m["freq_hz"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        // Stiffening forward, softening backward, at every step of Ω.
        for w in f.windows(2) {
            assert_eq!(w[1] > w[0], forward, "{} whirl: {f:?} Hz", m["whirl"]);
        }
        for (hz, r) in f.iter().zip(&rpm) {
            let spin = r * TAU / 60.0;
            let expected = closed.clamped_pinned(1, spin, forward);
            let err = (TAU * hz - expected).abs() / expected;
            assert!(
                err < TOLERANCE,
                "{} at {r} rpm: {} vs {expected} rad/s",
                m["whirl"],
                TAU * hz
            );
            worst = worst.max(err);
        }
    }
    assert_ne!(bending[0]["whirl"], bending[1]["whirl"]);
    eprintln!("campbell --no-contact, lowest pair: largest relative error {worst:.2e}");
}
