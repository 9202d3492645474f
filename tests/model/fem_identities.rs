//! Exact identities of the assembled linear model: symmetry, total mass, rigid-body null space,
//! gravity resultant; and mesh refinement converging monotonically to closed-form frequencies.

use crate::common;

use common::*;
use drillopt::fem::{BoundaryConditions, Dof, assemble};
use drillopt::model::{Drillstring, Section};
use drillopt::rom::{Family, ModalBasis};
use faer::{Col, Mat, Par};

fn string() -> Drillstring {
    seed().model
}

fn max_abs(m: &Mat<f64>) -> f64 {
    let mut x: f64 = 0.0;
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            x = x.max(m[(i, j)].abs());
        }
    }
    x
}

/// A global vector with `value(x)` on every DOF of kind `dof`.
fn field(n_nodes: usize, h: f64, parts: &[(Dof, &dyn Fn(f64) -> f64)]) -> Col<f64> {
    let mut v = Col::zeros(6 * n_nodes);
    for node in 0..n_nodes {
        for (dof, f) in parts {
            v[dof.at(node)] = f(node as f64 * h);
        }
    }
    v
}

#[test]
fn global_matrices_are_symmetric() {
    let g = assemble(&string(), 105);
    for (name, m) in [
        ("M", &g.mass),
        ("M_pipe", &g.pipe_mass),
        ("K", &g.stiffness),
    ] {
        let scale = max_abs(m);
        let asym = max_abs(&(m - m.transpose()));
        assert!(
            asym <= 1e-14 * scale,
            "{name} asymmetry {asym:e} vs scale {scale:e}"
        );
    }
}

#[test]
fn total_translational_mass_is_exact() {
    let s = string();
    let g = assemble(&s, 105);
    let (nodes, h) = (106, g.layout.element(0).length);
    let one = |_: f64| 1.0;
    let mass_along = |m: &Mat<f64>, dof: Dof| {
        let e = field(nodes, h, &[(dof, &one)]);
        (e.transpose() * m * &e).abs()
    };
    let l = Table1::L;
    let axial = Table1::RHO * Table1::area() * l;
    let lateral = Table1::lateral_mass() * l;
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    assert!(
        rel(mass_along(&g.mass, Dof::U), axial) < 1e-13,
        "axial mass ρAL"
    );
    assert!(
        rel(mass_along(&g.mass, Dof::V), lateral) < 1e-13,
        "lateral mass (ρA + ρ_f A_f)L in y"
    );
    assert!(
        rel(mass_along(&g.mass, Dof::W), lateral) < 1e-13,
        "lateral mass (ρA + ρ_f A_f)L in z"
    );
    assert!(
        rel(mass_along(&g.pipe_mass, Dof::V), axial) < 1e-13,
        "M_pipe carries no fluid"
    );
    let polar = 2.0 * Table1::RHO * Table1::inertia() * l;
    assert!(
        rel(mass_along(&g.mass, Dof::ThetaX), polar) < 1e-13,
        "polar inertia 2ρI L"
    );
}

#[test]
fn rigid_body_motions_are_in_the_null_space_of_the_unconstrained_stiffness() {
    let g = assemble(&string(), 40);
    let (nodes, h) = (41, g.layout.element(0).length);
    let k_scale = max_abs(&g.stiffness);
    let one = |_: f64| 1.0;
    let x = |x: f64| x;
    let minus_x = |x: f64| -x;
    let motions: Vec<(&str, Col<f64>)> = vec![
        ("translation x", field(nodes, h, &[(Dof::U, &one)])),
        ("translation y", field(nodes, h, &[(Dof::V, &one)])),
        ("translation z", field(nodes, h, &[(Dof::W, &one)])),
        ("rigid spin", field(nodes, h, &[(Dof::ThetaX, &one)])),
        // Rotation about z: v = x, θz = 1 (γ_xy = v′ − θz = 0); about y: w = −x, θy = 1.
        (
            "rotation about z",
            field(nodes, h, &[(Dof::V, &x), (Dof::ThetaZ, &one)]),
        ),
        (
            "rotation about y",
            field(nodes, h, &[(Dof::W, &minus_x), (Dof::ThetaY, &one)]),
        ),
    ];
    for (name, r) in &motions {
        let f = &g.stiffness * r;
        let r_norm = r.norm_max();
        let residual = f.norm_max() / (k_scale * r_norm);
        assert!(residual < 1e-12, "{name}: |K r| / (|K| |r|) = {residual:e}");
    }
    // And nothing else: the unconstrained K has exactly six zero eigenvalues.
    let ev = g
        .stiffness
        .self_adjoint_eigenvalues(faer::Side::Lower)
        .unwrap();
    let top = ev.last().copied().unwrap();
    let zeros = ev.iter().filter(|l| l.abs() < 1e-10 * top).count();
    assert_eq!(zeros, 6, "null space dimension");
}

#[test]
fn gravity_resultant_is_the_weight() {
    let g = assemble(&string(), 105);
    let weight = -Table1::lateral_mass() * 9.81 * Table1::L;
    let fz: f64 = (0..106).map(|n| g.gravity[Dof::W.at(n)]).sum();
    assert!(
        (fz - weight).abs() < 1e-12 * weight.abs(),
        "{fz} vs {weight}"
    );
    // The end moments of the uniform load cancel over the mesh, leaving only the two end nodes'.
    let moment_sum: f64 = (0..106).map(|n| g.gravity[Dof::ThetaY.at(n)]).sum();
    assert!(moment_sum.abs() < 1e-9 * weight.abs());
}

/// Pinned–pinned stocky beam (shear and rotatory inertia matter): u, θx held at x = 0 only.
fn stocky() -> Drillstring {
    let mut s = string();
    s.length = 1.5; // L / r ≈ 42
    s
}

fn pinned_pinned(elements: usize) -> BoundaryConditions {
    BoundaryConditions::free(elements)
        .fix(0, &[Dof::U, Dof::V, Dof::W, Dof::ThetaX])
        .fix(elements, &[Dof::V, Dof::W])
}

fn first(basis: &ModalBasis, family: Family, n: usize) -> f64 {
    basis
        .family(family)
        .nth(n - 1)
        .expect("mode present")
        .freq_hz
}

#[test]
fn stocky_pinned_beam_matches_exact_timoshenko_and_refinement_converges_monotonically() {
    let s = stocky();
    let sec = Section::of(&s);
    let exact: Vec<f64> = (1..=3)
        .map(|n| {
            pinned_pinned_timoshenko_hz(
                n,
                sec.ei,
                sec.shear_rigidity,
                sec.lateral_mass(),
                sec.rotary_inertia,
                s.length,
            )
        })
        .collect();
    // Shear and rotatory inertia lower the frequency well below Euler–Bernoulli here.
    let eb3 = 9.0 * std::f64::consts::PI / (2.0 * s.length.powi(2))
        * (sec.ei / sec.lateral_mass()).sqrt();
    assert!(
        exact[2] < 0.97 * eb3,
        "the test must exercise shear: {} vs EB {}",
        exact[2],
        eb3
    );
    let mut previous_err = [f64::INFINITY; 3];
    let mut ratio = [0.0; 3];
    for elements in [2, 4, 8, 16, 32] {
        let basis = ModalBasis::lowest(
            &assemble(&s, elements),
            &pinned_pinned(elements),
            12,
            Par::Seq,
        )
        .unwrap();
        for n in 1..=3 {
            let fe = first(&basis, Family::BendingZ, n);
            let err = (fe - exact[n - 1]) / exact[n - 1];
            eprintln!("N = {elements:>2}, bending mode {n}: rel. error {err:+.3e}");
            assert!(
                err > -1e-9,
                "consistent-mass FE frequencies bound from above: {err}"
            );
            assert!(err < previous_err[n - 1], "error must fall with refinement");
            ratio[n - 1] = previous_err[n - 1] / err;
            previous_err[n - 1] = err;
        }
    }
    // Converged to the exact Timoshenko values, at second order (error ÷ 4 per halving) or better.
    assert!(
        previous_err[0] < 2e-5 && previous_err.iter().all(|&e| e < 1e-3),
        "{previous_err:?}"
    );
    assert!(
        ratio.iter().all(|&r| r > 3.5),
        "convergence ratios {ratio:?}"
    );
}

#[test]
fn seed_refinement_converges_monotonically_to_the_rod_and_beam_closed_forms() {
    let s = string();
    let axial = fixed_free_rod_hz(1, (Table1::E / Table1::RHO).sqrt(), Table1::L);
    let torsion = fixed_free_rod_hz(
        1,
        (Table1::cowper() * Table1::shear_modulus() / Table1::RHO).sqrt(),
        Table1::L,
    );
    let bending = clamped_pinned_hz(
        1,
        Table1::E * Table1::inertia(),
        Table1::lateral_mass(),
        Table1::L,
    );
    let mut prev = [f64::INFINITY; 3];
    for elements in [3, 6, 12, 24, 48, 96] {
        let free = BoundaryConditions::drillstring(elements).free_count();
        let basis = ModalBasis::compute(
            &s,
            elements,
            &drillopt::model::BasisSpec::Lowest(free.min(40)),
        )
        .unwrap();
        let fe = [
            first(&basis, Family::Axial, 1),
            first(&basis, Family::Torsional, 1),
            first(&basis, Family::BendingY, 1),
        ];
        for (i, (f, exact)) in fe.iter().zip([axial, torsion, bending]).enumerate() {
            let err = (f - exact) / exact;
            eprintln!("N = {elements:>2}, family {i}: rel. error {err:+.3e}");
            assert!(*f < prev[i], "frequency must decrease with refinement");
            prev[i] = *f;
        }
    }
    // At 96 elements the rods are within 1e-4 of exact; bending within the Timoshenko–EB gap.
    assert!((prev[0] - axial).abs() / axial < 1e-4);
    assert!((prev[1] - torsion).abs() / torsion < 1e-4);
    assert!((prev[2] - bending).abs() / bending < 1e-3);
}

#[test]
fn modes_are_mass_orthonormal_and_satisfy_the_eigen_equation() {
    let s = string();
    let g = assemble(&s, 105);
    let bc = BoundaryConditions::drillstring(105);
    let basis = ModalBasis::lowest(&g, &bc, 51, Par::Seq).unwrap();
    let phi = &basis.shapes;
    let gram = phi.transpose() * &g.mass * phi;
    for i in 0..51 {
        for j in 0..51 {
            let expected = if i == j { 1.0 } else { 0.0 };
            assert!(
                (gram[(i, j)] - expected).abs() < 1e-10,
                "ΦᵀMΦ[{i},{j}] = {}",
                gram[(i, j)]
            );
        }
    }
    let kphi = &g.stiffness * phi;
    let k_scale = max_abs(&g.stiffness);
    let mphi = &g.mass * phi;
    for (c, mode) in basis.modes.iter().enumerate() {
        // Residual on the free DOFs only (constrained rows carry reactions).
        let lambda = mode.omega * mode.omega;
        let mut res: f64 = 0.0;
        let scale = k_scale * phi.col(c).norm_max();
        for i in bc.free_dofs() {
            res = res.max((kphi[(i, c)] - lambda * mphi[(i, c)]).abs());
        }
        assert!(res < 1e-10 * scale, "mode {}: residual {res:e}", mode.index);
        assert!(
            mode.energy_share.iter().cloned().fold(0.0, f64::max) > 0.999,
            "pure family"
        );
    }
}
