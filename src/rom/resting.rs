//! The resting shape of a bending plane: the static deflection of the string under its own
//! weight with the wall's contact, the basis vector that lets a reduced model hold a string lying
//! along the low side of the hole (issue 11).
//!
//! A horizontal string rests on the wall over most of its length and leaves it only near its
//! supported ends. A basis of free-string modes cannot represent that shape: the seed's default
//! basis (16 modes per plane) touches the wall at 14 of the 106 nodes at rest where the
//! unreduced model touches at 71, and the spans between those 14 supports are free to vibrate:
//! after about 5 s of stick-slip the reduced string lifts off and bounces on the wall at ~1400
//! impacts/s where the unreduced one lies still. The static solution is the standard remedy
//! (Ritz vectors of the load, Wilson, Yuan & Dickens 1982, "Dynamic analysis by direct
//! superposition of Ritz vectors", Earthq. Eng. Struct. Dyn. 10:813–821): with the resting
//! shape in the span of the basis, the reduced static equilibrium is the finite-element one up to
//! the coupling of the planes with the other families.
//!
//! The weight on bit compresses the string (55 kN on the seed), and a compressed beam on the wall
//! rests in another shape: with the resting shape alone the seed's pre-loaded state touched at 26
//! nodes (32 modes per plane: 53) where the finite-element model touches at 71, and the doubled
//! basis lifted off after 6 s (21 impacts/s over 40 s). The derivative of the resting shape with
//! respect to a uniform compression ([`BlockRest::compression_sensitivity`], through the geometric
//! stiffness [`crate::fem::geometric_stiffness`]) is the second Ritz vector of each plane; with
//! both, the pre-loaded contact set is the finite-element one (`tests/model/resting_shape.rs`).
//! Both vectors are combined by a Rayleigh–Ritz step so that the basis stays M- and K-orthogonal.
//!
//! Per bending block, x solves the plane's static problem
//!   K x − b − Σᵢ F(|xᵢ| − gap) sign(xᵢ) eᵢ = 0,
//! K the block's linear stiffness, b the weight load along −y or −z ([`crate::fem::weight_load`];
//! along −y it is the twin of the real one, so both planes keep twin bases), F ≤ 0 the wall law's
//! elastic normal force at each node's lateral translation xᵢ (the radius when the other plane
//! is at rest). It is the minimum of the convex energy ½xᵀKx − bᵀx + Σᵢ φ(|xᵢ| − gap), found
//! by Newton's method with a backtracking (Armijo) line search on that energy.

use super::lanczos::SparseCholesky;
use crate::fem::SymmetricSparse;
use crate::model::WallContactLaw;
use faer::Mat;

/// The static problem of one bending block.
pub(super) struct BlockRest<'a> {
    /// Weight load on the block's DOFs, N and N·m.
    pub load: Vec<f64>,
    /// Block-local indices of the lateral translations (v or w) of the nodes.
    pub contact: Vec<usize>,
    /// The wall law's factor at each row of `contact` (1 per node, the node's tributary length per
    /// metre of string: [`crate::model::WallStiffnessPer::factor`]).
    pub factors: Vec<f64>,
    /// The radial gap at each row of `contact`, m (the node's: a string of sections has its own
    /// at every section).
    pub gaps: Vec<f64>,
    pub law: &'a dyn WallContactLaw,
    /// The smallest radial gap, m (the scale of the shape's convergence test).
    pub gap: f64,
    /// The block's geometric stiffness K_σ of a unit axial force (for
    /// [`Self::compression_sensitivity`]); `None`: the resting shape alone.
    pub geometric: Option<SymmetricSparse>,
    /// The steady drilling state's shapes on the block's DOFs (its own plane's part of the
    /// finite-element steady state and the other plane's part turned into this plane), Ritz
    /// vectors beside the resting shapes ([`super::SteadyState`]); empty without one.
    pub steady: Vec<Vec<f64>>,
}

/// Newton iterations allowed (the seed converges in about 20).
const ITERATIONS: usize = 200;

impl BlockRest<'_> {
    /// Energy, gradient and the contact stiffness −∂F/∂δ at each contact row, at x.
    fn evaluate(&self, k: &SymmetricSparse, x: &[f64]) -> (f64, Vec<f64>, Vec<f64>) {
        let mut g = vec![0.0; x.len()];
        k.mul_vec(x, &mut g);
        let mut energy = 0.0;
        for (gi, (xi, bi)) in g.iter_mut().zip(x.iter().zip(&self.load)) {
            energy += 0.5 * xi * *gi - bi * xi;
            *gi -= bi;
        }
        let mut stiffness = vec![0.0; self.contact.len()];
        let rows = self.contact.iter().zip(&self.factors).zip(&self.gaps);
        for (s, ((&r, &factor), &gap)) in stiffness.iter_mut().zip(rows) {
            let delta = x[r].abs() - gap;
            if delta > 0.0 {
                let f = self.law.normal(delta, 0.0).scaled(factor);
                energy += f.energy;
                g[r] -= f.elastic * x[r].signum();
                *s = -f.dforce_dindentation;
            }
        }
        (energy, g, stiffness)
    }

    /// For each of the block's `n` rows, its index in `contact` (`usize::MAX`: no contact row).
    fn contact_of(&self, n: usize) -> Vec<usize> {
        let mut contact_of = vec![usize::MAX; n];
        for (c, &r) in self.contact.iter().enumerate() {
            contact_of[r] = c;
        }
        contact_of
    }

    /// The Hessian K + diag(contact stiffness) of the energy.
    fn hessian(k: &SymmetricSparse, contact_of: &[usize], stiffness: &[f64]) -> SymmetricSparse {
        SymmetricSparse::from_column_fn(k.size(), |j| {
            k.column(j)
                .map(|(i, v)| match contact_of[j] {
                    c if i == j && c != usize::MAX => (i, v + stiffness[c]),
                    _ => (i, v),
                })
                .collect()
        })
    }

    /// The derivative dx/dP of the resting shape `x` (from [`Self::shape`]) with respect to a
    /// uniform axial compression P of the string, m/N: the string in compression has the
    /// stiffness K − P K_σ (`geometric`, from [`crate::fem::geometric_stiffness`]), so
    /// differentiating (K − P K_σ) x − b − F(x) = 0 at P = 0 gives H dx/dP = K_σ x with H the
    /// energy's Hessian at x (K plus the wall's contact stiffness). The weight on bit compresses the
    /// string by tens of kN; the shape it adds is what the basis needs to rest on the wall where
    /// the finite-element model does in the pre-loaded state. `None` if H is not positive
    /// definite (then the basis goes without it).
    pub fn compression_sensitivity(
        &self,
        k: &SymmetricSparse,
        geometric: &SymmetricSparse,
        x: &[f64],
    ) -> Option<Vec<f64>> {
        let n = k.size();
        let contact_of = self.contact_of(n);
        let (_, _, stiffness) = self.evaluate(k, x);
        let chol = SparseCholesky::new(&Self::hessian(k, &contact_of, &stiffness)).ok()?;
        let mut rhs = vec![0.0; n];
        geometric.mul_vec(x, &mut rhs);
        let mut y = Mat::<f64>::from_fn(n, 1, |i, _| rhs[i]);
        chol.solve(y.as_mut());
        Some(y.col_as_slice(0).to_vec())
    }

    /// The resting shape on the block whose stiffness is `k`; `None` when the load is zero or
    /// Newton does not converge (the basis then goes without it).
    ///
    /// Newton starts from the unloaded string (x = 0). On a long string that start is far from the
    /// minimum (the first step deflects a 5 km span by about 10⁹ m, and the line search crawls back
    /// to the wall over hundreds of iterations), so when it fails Newton starts again from the
    /// string lying on the wall ([`Self::bed_start`]): the answer is the same minimum of a strictly
    /// convex energy, and the strings that converged from x = 0 keep their bits.
    pub fn shape(&self, k: &SymmetricSparse) -> Option<Vec<f64>> {
        let n = k.size();
        if self.load.iter().all(|&b| b == 0.0) {
            return None;
        }
        self.minimum(k, vec![0.0; n])
            .or_else(|| self.minimum(k, self.bed_start(n)))
    }

    /// The string lying on the wall: each contact row at the indentation δ ≥ 0 at which the wall
    /// carries the row's own load, |F(δ)| = |bᵢ| (bisection), on the side the load pushes it; the
    /// other rows (rotations, unloaded translations) at 0. It is the resting shape of an infinitely
    /// long string on an elastic bed, where no span bends.
    fn bed_start(&self, n: usize) -> Vec<f64> {
        let mut x = vec![0.0; n];
        let rows = self.contact.iter().zip(&self.factors).zip(&self.gaps);
        for ((&r, &factor), &gap) in rows {
            let b = self.load[r];
            if b == 0.0 {
                continue;
            }
            let carried = |delta: f64| -self.law.normal(delta, 0.0).scaled(factor).elastic;
            let mut high = gap.max(1e-6);
            for _ in 0..60 {
                if carried(high) >= b.abs() {
                    break;
                }
                high *= 2.0;
            }
            let mut low = 0.0;
            for _ in 0..100 {
                let mid = 0.5 * (low + high);
                if carried(mid) < b.abs() {
                    low = mid;
                } else {
                    high = mid;
                }
            }
            x[r] = b.signum() * (gap + 0.5 * (low + high));
        }
        x
    }

    /// Newton from `x` on the energy (see the module doc); `None` when it does not converge.
    fn minimum(&self, k: &SymmetricSparse, mut x: Vec<f64>) -> Option<Vec<f64>> {
        let n = k.size();
        let contact_of = self.contact_of(n);
        let mut trial = vec![0.0; n];
        for _ in 0..ITERATIONS {
            let (energy, g, stiffness) = self.evaluate(k, &x);
            let chol = SparseCholesky::new(&Self::hessian(k, &contact_of, &stiffness)).ok()?;
            let mut d = Mat::<f64>::from_fn(n, 1, |i, _| -g[i]);
            chol.solve(d.as_mut());
            let d = d.col_as_slice(0);
            let largest = d.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            // Converged: the Newton update is below a picometre.
            if largest < 1e-12 {
                return Some(x);
            }
            let slope: f64 = g.iter().zip(d).map(|(a, b)| a * b).sum();
            let mut alpha = 1.0;
            loop {
                for ((t, xi), di) in trial.iter_mut().zip(&x).zip(d) {
                    *t = xi + alpha * di;
                }
                let (e, _, _) = self.evaluate(k, &trial);
                if e <= energy + 1e-4 * alpha * slope {
                    break;
                }
                alpha *= 0.5;
                if alpha < 1e-12 {
                    // No decrease along a descent direction: round-off at the minimum.
                    return (largest < 1e-9 * self.gap.max(1e-3)).then_some(x);
                }
            }
            std::mem::swap(&mut x, &mut trial);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::wall::Cubic;

    fn law(stiffness: f64) -> Cubic {
        Cubic {
            stiffness,
            cubic_stiffness: 0.0,
            damping: 0.0,
            friction: 0.0,
            sign_smoothing: 1e-3,
        }
    }

    /// A chain of n unit springs fixed at one end, a load b at every node: without a wall the
    /// end moves by Σ b i = b n(n+1)/2; with a wall at `gap` every node beyond the gap rests
    /// on a spring of stiffness k_w. Both against closed forms.
    fn chain(n: usize) -> SymmetricSparse {
        SymmetricSparse::from_column_fn(n, |j| {
            let mut c = Vec::new();
            if j > 0 {
                c.push((j - 1, -1.0));
            }
            c.push((j, if j + 1 < n { 2.0 } else { 1.0 }));
            if j + 1 < n {
                c.push((j + 1, -1.0));
            }
            c
        })
    }

    #[test]
    fn without_contact_the_shape_is_the_linear_static_response() {
        let n = 10;
        let wall = law(1e6);
        let rest = BlockRest {
            load: vec![-1e-3; n],
            contact: (0..n).collect(),
            factors: vec![1.0; n],
            gaps: vec![1.0; n],
            law: &wall,
            gap: 1.0,
            geometric: None,
            steady: Vec::new(),
        };
        let x = rest.shape(&chain(n)).unwrap();
        // Node i (1-based) of a fixed–free chain under uniform load b: x_i = b Σ_{j≤i} (n − j + 1).
        for (i, xi) in x.iter().enumerate() {
            let expected: f64 = -1e-3 * (1..=i + 1).map(|j| (n - j + 1) as f64).sum::<f64>();
            approx::assert_relative_eq!(*xi, expected, max_relative = 1e-12);
        }
    }

    #[test]
    fn a_single_node_on_a_linear_wall_rests_where_the_forces_balance() {
        // One spring of stiffness 1 to the ground, load −2, wall at 0.5 with stiffness 100:
        // x + 100 (|x| − 0.5) = 2 at x = −(2 + 50)/101.
        let k = SymmetricSparse::from_column_fn(1, |_| vec![(0, 1.0)]);
        let wall = law(100.0);
        let rest = BlockRest {
            load: vec![-2.0],
            contact: vec![0],
            factors: vec![1.0],
            gaps: vec![0.5],
            law: &wall,
            gap: 0.5,
            geometric: None,
            steady: Vec::new(),
        };
        let x = rest.shape(&k).unwrap();
        approx::assert_relative_eq!(x[0], -52.0 / 101.0, max_relative = 1e-12);
        let free = BlockRest {
            load: vec![0.0],
            geometric: None,
            ..rest
        };
        assert!(free.shape(&k).is_none(), "no load, no shape");
    }

    /// dx/dP against a central difference of the resting shapes of K ∓ δP K_σ, on the chain
    /// with its free end beyond the gap (in contact) and a diagonal K_σ.
    #[test]
    fn the_compression_sensitivity_is_the_derivative_of_the_resting_shape() {
        let n = 6;
        let wall = law(50.0);
        let rest = BlockRest {
            load: vec![-0.5; n],
            contact: (0..n).collect(),
            factors: vec![1.0; n],
            gaps: vec![2.0; n],
            law: &wall,
            gap: 2.0,
            geometric: None,
            steady: Vec::new(),
        };
        let k = chain(n);
        let geometric = SymmetricSparse::from_column_fn(n, |j| vec![(j, 0.1 * (j + 1) as f64)]);
        let x = rest.shape(&k).unwrap();
        assert!(
            x.iter().any(|xi| xi.abs() > rest.gap),
            "the test needs a contact"
        );
        let dx = rest.compression_sensitivity(&k, &geometric, &x).unwrap();
        let compressed = |p: f64| {
            let kp = SymmetricSparse::from_column_fn(n, |j| {
                k.column(j)
                    .map(|(i, v)| (i, v - if i == j { p * geometric.get(i, j) } else { 0.0 }))
                    .collect()
            });
            rest.shape(&kp).unwrap()
        };
        let delta = 1e-5;
        let (plus, minus) = (compressed(delta), compressed(-delta));
        for i in 0..n {
            let fd = (plus[i] - minus[i]) / (2.0 * delta);
            approx::assert_relative_eq!(dx[i], fd, max_relative = 1e-5, epsilon = 1e-9);
        }
    }
}
