//! The modes of long meshes without dense matrices (issue 13 item 6): sparse assembly and
//! shift-invert Lanczos against the dense solver where both run, and against the fixed–free rod's
//! closed form on a mesh where only the sparse path is affordable.

use crate::common;

use drillopt::fem::{BoundaryConditions, assemble, assemble_sparse};
use drillopt::model::{BasisSpec, Section};
use drillopt::rom::{
    Family, ModalBasis, generalized_symmetric_eigen, lanczos_applies, sparse_generalized_eigen,
};
use faer::{Mat, Par};

/// The free DOFs of one family at `elements` elements, ascending.
fn family_dofs(bc: &BoundaryConditions, family: Family) -> Vec<usize> {
    bc.free_dofs()
        .into_iter()
        .filter(|&i| Family::of(drillopt::fem::Dof::of_index(i)) == family)
        .collect()
}

/// Lanczos and a dense solver on the same family block of a mid-size mesh (150 elements, the
/// bending block of 300 DOFs): the same frequencies to 1e-8 relative and the same subspace (the
/// cosines of the principal angles between the M-orthonormal sets, the singular values of
/// Φ_dᵀ M Φ_s, all within 1e-8 of 1).
///
/// The dense solver works on the inverted pencil M φ = μ K φ (μ = 1/λ, the largest μ), whose
/// absolute error is about ε μ₁; the standard form's, ε times the element-scale λ_max ≈ 1e7 λ₁
/// here, lost 3e-7 on λ₁ at 150 elements and 6e-6 at 1000 (revision 12 and before).
#[test]
fn lanczos_and_dense_agree_on_a_mid_size_mesh() {
    let p = common::seed();
    let elements = 150;
    let count = 16;
    let sparse = assemble_sparse(&p.model, elements);
    let bc = BoundaryConditions::drillstring(elements);
    for family in Family::ALL {
        let dofs = family_dofs(&bc, family);
        let (k, m) = (
            sparse.stiffness.submatrix(&dofs),
            sparse.mass.submatrix(&dofs),
        );
        assert!(
            lanczos_applies(dofs.len(), count),
            "{family}: {}",
            dofs.len()
        );
        let (ls, xs) = sparse_generalized_eigen(&k, &m, count, Par::Seq).unwrap();
        let (kd, md) = (k.to_dense(), m.to_dense());
        let (ld, xd) =
            generalized_symmetric_eigen(kd.as_ref(), md.as_ref(), count, Par::Seq).unwrap();
        for (i, (s, d)) in ls.iter().zip(&ld).enumerate() {
            assert!((s - d).abs() <= 1e-8 * d, "{family} mode {i}: {s} vs {d}");
        }
        let c: Mat<f64> = xd.transpose() * &md * &xs;
        let cosines = c.singular_values().unwrap();
        for s in cosines {
            assert!((s - 1.0).abs() < 1e-8, "{family}: principal cosine {s}");
        }
    }
}

/// The sparse assembly with the dense per-block solve (blocks below LANCZOS_MIN_BLOCK) is the
/// dense path bit for bit: the same frequencies and shapes for the seed's default basis.
#[test]
fn sparse_assembly_gives_the_seed_basis_bitwise() {
    let p = common::seed();
    let n = p.mesh.elements;
    let bc = BoundaryConditions::drillstring(n);
    assert!(!ModalBasis::sparse_mesh(n));
    let dense = ModalBasis::of(&assemble(&p.model, n), &bc, &p.mesh.basis, Par::Seq).unwrap();
    let sparse =
        ModalBasis::of_sparse(&assemble_sparse(&p.model, n), &bc, &p.mesh.basis, Par::Seq).unwrap();
    assert_eq!(dense.len(), sparse.len());
    for (d, s) in dense.modes.iter().zip(&sparse.modes) {
        assert_eq!((d.freq_hz, d.family, d.kind), (s.freq_hz, s.family, s.kind));
    }
    assert_eq!(dense.shapes, sparse.shapes);
}

/// A 1000-element mesh (6006 DOF, bending blocks of 1999 DOFs: Lanczos): the axial modes of the
/// fixed–free rod (no lumped mass on u) are f_k = (2k − 1) c / (4L), c = √(EA/ρA), to the
/// discretisation error of linear elements ((k π h / 2L)² / 24 < 1e-6 here); the basis is
/// M-orthonormal; the bending planes are twins in y, z order.
#[test]
fn a_long_mesh_by_lanczos_matches_the_rod_closed_form() {
    let p = common::seed();
    let elements = 1000;
    assert!(ModalBasis::sparse_mesh(elements));
    let basis = ModalBasis::compute(&p.model, elements, &BasisSpec::Lowest(60)).unwrap();
    let s = Section::of(&p.model);
    let c = (s.ea / s.pipe_mass).sqrt();
    let axial: Vec<f64> = basis.family(Family::Axial).map(|m| m.freq_hz).collect();
    assert!(axial.len() >= 2);
    for (k, f) in axial.iter().enumerate() {
        let exact = (2 * k + 1) as f64 * c / (4.0 * p.model.length);
        assert!(
            (f - exact).abs() < 1e-6 * exact,
            "axial {k}: {f} vs {exact}"
        );
    }
    let global = assemble_sparse(&p.model, elements);
    let phi = &basis.shapes;
    let mut mphi = Mat::<f64>::zeros(phi.nrows(), phi.ncols());
    let mut y = vec![0.0; phi.nrows()];
    for j in 0..phi.ncols() {
        global
            .mass
            .mul_vec(phi.col(j).try_as_col_major().unwrap().as_slice(), &mut y);
        for i in 0..y.len() {
            mphi[(i, j)] = y[i];
        }
    }
    let gram = phi.transpose() * &mphi;
    for i in 0..gram.nrows() {
        for j in 0..gram.ncols() {
            let e = if i == j { 1.0 } else { 0.0 };
            assert!((gram[(i, j)] - e).abs() < 1e-10, "gram[{i},{j}]");
        }
    }
    let modes = &basis.modes;
    assert_eq!(
        (modes[0].family, modes[1].family),
        (Family::BendingY, Family::BendingZ)
    );
    assert!((modes[0].freq_hz - modes[1].freq_hz).abs() < 1e-9 * modes[0].freq_hz);
}

/// The 466 m collar string of `problems/long_collars.toml` as a 5 in drill pipe (127 mm OD,
/// 109.2 mm bore) of `length` m on `elements` elements, written to `dir`.
fn drill_pipe(dir: &std::path::Path, length: f64, elements: usize) -> std::path::PathBuf {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/problems/long_collars.toml"
    ))
    .unwrap();
    let mut out = String::new();
    for line in text.lines() {
        let line = match line.split_whitespace().next() {
            Some("length") => format!("length = \"{length} m\""),
            Some("elements") => format!("elements = {elements}"),
            Some("inner_radius") => "inner_radius = \"54.6 mm\"".into(),
            Some("outer_radius") => "outer_radius = \"63.5 mm\"".into(),
            Some("probes") => "probes = []".into(),
            _ => line.to_string(),
        };
        out.push_str(&line);
        out.push('\n');
    }
    let path = dir.join(format!("dp_{length}_{elements}.toml"));
    std::fs::write(&path, out).unwrap();
    path
}

fn modes_json(path: &std::path::Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["modes", path.to_str().unwrap(), "--json"];
    args.extend(extra);
    let out = common::drillopt(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Field lengths on field meshes: every default basis holds the four resting shapes (two per
/// plane). At 5–6 km they used to be dropped without a word (the shape's Newton solve from the
/// unloaded string stopped short; it now starts again from the string lying on the wall, and a
/// shape that still does not converge is refused naming the keys that set it).
#[test]
fn resting_shapes_are_in_the_basis_of_one_to_six_kilometre_strings() {
    let dir = tempfile::tempdir().unwrap();
    for (length, elements) in [(1000.0, 150), (3000.0, 300), (5000.0, 520), (6000.0, 600)] {
        let json = modes_json(&drill_pipe(dir.path(), length, elements), &[]);
        assert_eq!(
            json["basis"]["resting_shapes"], 4,
            "{length} m, {elements} elements: {}",
            json["basis"]
        );
    }
}

/// 300 modes of a 5 km string on 520 elements: Lanczos with faer's default space converges 214
/// of them to the basis' accuracy, and the family then goes to a wider space or the dense solver
/// (its blocks are of at most 1040 DOFs); the bending planes stay twins and the frequencies
/// ascend. (The count is a lowest-count basis of the whole string, every family.)
#[test]
fn three_hundred_modes_of_a_five_kilometre_string() {
    let dir = tempfile::tempdir().unwrap();
    let json = modes_json(&drill_pipe(dir.path(), 5000.0, 520), &["--count", "300"]);
    let modes = json["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 300);
    let hz: Vec<f64> = modes
        .iter()
        .map(|m| m["freq_hz"].as_f64().unwrap())
        .collect();
    assert!(
        hz.windows(2).all(|w| w[0] <= w[1] * (1.0 + 1e-9)),
        "ascending"
    );
    assert!(hz[0] > 0.0 && hz[299].is_finite());
    let planes = |family: &str| {
        modes
            .iter()
            .filter(|m| m["family"] == family)
            .map(|m| m["freq_hz"].as_f64().unwrap())
            .collect::<Vec<f64>>()
    };
    let (y, z) = (planes("bending_y"), planes("bending_z"));
    // The 300th may split a twin pair.
    assert!(
        y.len().abs_diff(z.len()) <= 1 && y.len() > 100,
        "{} {}",
        y.len(),
        z.len()
    );
    for (a, b) in y.iter().zip(&z) {
        assert!((a - b).abs() <= 1e-8 * a, "{a} vs {b}");
    }
}
