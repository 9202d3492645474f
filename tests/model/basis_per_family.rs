//! The reduced basis chosen per family (MODEL.md §7): static corrections against the closed-form
//! static flexibility of the fixed–free rod, orthogonality of the extended basis, the refusal of a
//! basis that leaves a family empty, and the pre-loaded start.

use crate::common;

use common::{SEED, Table1};
use drillopt::fem::Dof;
use drillopt::integrate::ImplicitSystem;
use drillopt::model::{BasisSpec, FamilySize, OperatingPoint};
use drillopt::rom::{BasisError, Family, ModalBasis, ModeKind, ReducedModel};
use drillopt::sim::{Dynamics, Effects, preloaded_equilibrium};
use nalgebra::DVector;

const ELEMENTS: usize = 30;

fn per_family(torsional: usize, axial: usize, static_corrections: bool) -> BasisSpec {
    BasisSpec::PerFamily {
        bending: FamilySize::Count(6),
        torsional: FamilySize::Count(torsional),
        axial: FamilySize::Count(axial),
        static_corrections,
        steady_shapes: false,
    }
}

/// Static tip flexibility of the reduced model for a unit load on `dof` at the bit:
/// Σᵢ φᵢ(L)² / ωᵢ² (Φ is M-orthonormal and K-diagonal).
fn tip_flexibility(basis: &ModalBasis, dof: Dof) -> f64 {
    let row = dof.at(ELEMENTS);
    basis
        .modes
        .iter()
        .enumerate()
        .map(|(c, m)| basis.shapes[(row, c)].powi(2) / (m.omega * m.omega))
        .sum()
}

/// A fixed–free rod under a tip load has the static tip flexibility L/(EA) axially and
/// L/(κ_t G J) in torsion, which linear elements reproduce exactly. The two lowest modes alone give
/// Σ_{n≤2} 8/((2n−1)²π²) = 90.06 % of it; with the static correction the basis spans the exact
/// static response.
#[test]
fn static_corrections_give_the_exact_static_tip_flexibility() {
    let p = common::seed();
    let j = 2.0 * Table1::inertia();
    let exact_torsion = Table1::L / (Table1::cowper() * Table1::shear_modulus() * j);
    let exact_axial = Table1::L / (Table1::E * Table1::area());
    let truncated = 8.0 / std::f64::consts::PI.powi(2) * (1.0 + 1.0 / 9.0);
    for (sc, expected) in [(false, truncated), (true, 1.0)] {
        let basis = ModalBasis::compute(&p.model, ELEMENTS, &per_family(2, 2, sc)).unwrap();
        let torsion = tip_flexibility(&basis, Dof::ThetaX) / exact_torsion;
        let axial = tip_flexibility(&basis, Dof::U) / exact_axial;
        println!("static corrections {sc}: torsion {torsion:.6}, axial {axial:.6} of exact");
        // Without corrections the FE modes differ from the rod's by O(h²) (< 1e-3 here).
        let tol = if sc { 1e-9 } else { 2e-3 };
        assert!((torsion - expected).abs() < tol, "torsion {torsion}");
        assert!((axial - expected).abs() < tol, "axial {axial}");
        let corrections: Vec<_> = basis
            .modes
            .iter()
            .filter(|m| m.kind == ModeKind::StaticCorrection)
            .map(|m| m.family)
            .collect();
        if sc {
            assert_eq!(corrections, vec![Family::Torsional, Family::Axial]);
        } else {
            assert!(corrections.is_empty());
        }
    }
}

/// The extended basis keeps the reduced operators of the modal one: Φᵀ M Φ = I and
/// Φᵀ K Φ = diag(ω²), so everything downstream (damping, step weights, Newmark) is unchanged.
#[test]
fn the_extended_basis_is_mass_orthonormal_and_stiffness_diagonal() {
    let p = common::seed();
    let model = ReducedModel::new(&p.model, ELEMENTS, &BasisSpec::DEFAULT).unwrap();
    let phi = &model.phi;
    let global = drillopt::fem::assemble(&p.model, ELEMENTS);
    let m = nalgebra::DMatrix::from_fn(phi.nrows(), phi.nrows(), |i, j| global.mass[(i, j)]);
    let k = nalgebra::DMatrix::from_fn(phi.nrows(), phi.nrows(), |i, j| global.stiffness[(i, j)]);
    let (mm, kk) = (phi.transpose() * &m * phi, phi.transpose() * &k * phi);
    let n = model.size();
    let scale = model.omega2.max();
    for i in 0..n {
        for j in 0..n {
            let (mi, ki) = if i == j {
                (1.0, model.omega2[i])
            } else {
                (0.0, 0.0)
            };
            assert!(
                (mm[(i, j)] - mi).abs() < 1e-10,
                "M[{i},{j}] = {}",
                mm[(i, j)]
            );
            assert!(
                (kk[(i, j)] - ki).abs() < 1e-9 * scale,
                "K[{i},{j}] = {}",
                kk[(i, j)]
            );
        }
    }
    let counts = model.basis.counts();
    assert_eq!(
        (
            counts.bending,
            counts.torsional,
            counts.axial,
            counts.static_corrections,
            counts.resting_shapes
        ),
        (32, 8, 4, 2, 4)
    );
    // Both bending planes hold the same modes: one block of Φ serves both (one twin pair).
    assert_eq!(model.blocks.twins(), 1);
}

/// The lowest 10 modes of the 8 m tiny string are 9 bending and 1 torsional: no axial mode, so no
/// bit-bounce and ROP = V0 by construction. Refused.
#[test]
fn a_basis_without_axial_modes_is_refused() {
    let p = common::seed();
    let mut string = p.model.clone();
    string.length = 8.0;
    let err = ModalBasis::compute(&string, 12, &BasisSpec::Lowest(10)).unwrap_err();
    match err {
        BasisError::EmptyFamily { family, counts, .. } => {
            assert_eq!(family, "axial");
            assert_eq!((counts.bending, counts.torsional, counts.axial), (9, 1, 0));
        }
        other => panic!("expected an empty-family refusal, got {other}"),
    }
}

/// The pre-loaded start is the steady drilling state: the bit moves at V0 and spins at Ω, so the
/// weight on bit is Γ(1 − exp(−α V0)) and the torque on bit μ WOB ξ(Ω) (MODEL.md §6), and the
/// state is an equilibrium (zero acceleration).
#[test]
fn the_preloaded_start_carries_the_steady_bit_loads() {
    let p = drillopt::problem::Problem::load(SEED).unwrap();
    let model = ReducedModel::new(&p.model, ELEMENTS, &BasisSpec::DEFAULT).unwrap();
    let op = OperatingPoint {
        omega: 2.0 * std::f64::consts::PI,
        v0: 10.0 / 3600.0,
        wob: 0.0,
    };
    let (q, _) = preloaded_equilibrium(&model, op, Effects::ALL).unwrap();
    let n = model.size();
    let zero = DVector::zeros(n);
    let mut sys = Dynamics::new(&model, op, Effects::ALL);
    let obs = sys.observe(&q, &zero, &zero);
    let bit = &p.model.bit;
    let wob = bit.get("limit_force").unwrap() * (1.0 - (-bit.get("rate").unwrap() * op.v0).exp());
    assert!(
        (-obs.bit.force / wob - 1.0).abs() < 1e-12,
        "WOB {}",
        -obs.bit.force
    );
    assert!((obs.bit_velocity - op.v0).abs() < 1e-15);
    assert!((obs.bit_spin - op.omega).abs() < 1e-12);
    // ξ(ω) = tanh ω + 2ω/(1 + ω²), MODEL.md §6, written out as the independent reference.
    let w = op.omega;
    let tob = bit.get("friction").unwrap() * wob * (w.tanh() + 2.0 * w / (1.0 + w * w));
    assert!(
        (-obs.bit.torque / tob - 1.0).abs() < 1e-12,
        "TOB {}",
        -obs.bit.torque
    );
    // The string carries the load: compressed and twisted at the bit (elastic u < 0, θx < 0).
    assert!(obs.bit_u_elastic < 0.0 && obs.bit_theta_elastic < 0.0);
    let twist_static = -tob * p.model.length
        / (Table1::cowper() * Table1::shear_modulus() * 2.0 * Table1::inertia());
    // Wall friction and damping add torque along the string: the twist exceeds the bit's share.
    assert!(obs.bit_theta_elastic <= twist_static * (1.0 - 1e-9));
    let mut r = DVector::zeros(n);
    sys.residual(0.0, &q, &zero, &zero, &mut r);
    assert!(
        r.norm() < 1e-6 * model.gravity.norm(),
        "residual {} against the gravity load {}",
        r.norm(),
        model.gravity.norm()
    );
}
