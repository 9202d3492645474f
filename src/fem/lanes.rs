//! Four `f64` lanes, one per Gauss point of an element ([`super::gauss_legendre_4`]), and the
//! arithmetic that `f64` and the lanes share.
//!
//! The element kernels evaluate their four Gauss points together, one point per lane, so the
//! compiler can keep them in packed SIMD registers. Each lane does exactly the operations of the
//! scalar code in the same order: a kernel written once over [`Real`] gives, lane by lane, bitwise
//! the results of its `f64` instance at each point.

use super::{ELEMENT_DOF, ElementVector};
use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

/// One value per Gauss point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Lanes(pub(super) [f64; 4]);

impl Lanes {
    /// The lanes added in order, from zero (as a loop over the points would accumulate them).
    #[inline(always)]
    pub(super) fn sum(self) -> f64 {
        let [a, b, c, d] = self.0;
        0.0 + a + b + c + d
    }
}

/// The [`Lanes::sum`] of each of four lanes, as the lanes of one: transposed and added lane-wise
/// (four packed additions instead of four horizontal sums), in the same order, so bitwise equal.
#[inline(always)]
fn sums(x: [Lanes; 4]) -> Lanes {
    let column = |p: usize| Lanes(x.map(|l| l.0[p]));
    Lanes::from(0.0) + column(0) + column(1) + column(2) + column(3)
}

/// The element vector of the Gauss-point sums of `f` ([`Lanes::sum`] of each entry, bitwise),
/// four entries at a time. Written out per entry, the horizontal sums kept the inertia kernel
/// from being vectorised at all (about 6 % of a seed run).
#[inline(always)]
pub(super) fn element_sums(f: &[Lanes; ELEMENT_DOF]) -> ElementVector {
    let mut out = ElementVector::zeros();
    for (chunk, x) in out
        .as_mut_slice()
        .chunks_exact_mut(4)
        .zip(f.chunks_exact(4))
    {
        chunk.copy_from_slice(&sums([x[0], x[1], x[2], x[3]]).0);
    }
    out
}

/// What the hand-written kernels need of a number: `f64`, or [`Lanes`]. Constants go on the right
/// (`x * 0.5`, not `0.5 * x`): a bound `where f64: Mul<T>` would also capture the kernels' plain
/// `f64` arithmetic. Swapping the operands of one product or sum does not change its rounding.
pub(super) trait Real:
    Copy
    + From<f64>
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Mul<f64, Output = Self>
    + AddAssign
    + SubAssign
{
    fn abs(self) -> Self;
}

impl Real for f64 {
    #[inline(always)]
    fn abs(self) -> f64 {
        f64::abs(self)
    }
}

impl Real for Lanes {
    #[inline(always)]
    fn abs(self) -> Self {
        let [a, b, c, d] = self.0;
        Lanes([a.abs(), b.abs(), c.abs(), d.abs()])
    }
}

impl From<f64> for Lanes {
    #[inline(always)]
    fn from(x: f64) -> Self {
        Lanes([x; 4])
    }
}

impl Neg for Lanes {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        let [a, b, c, d] = self.0;
        Lanes([-a, -b, -c, -d])
    }
}

/// Lane-wise `op` between lanes.
macro_rules! lanewise {
    ($trait_:ident, $method:ident, $op:tt) => {
        impl $trait_ for Lanes {
            type Output = Self;
            #[inline(always)]
            fn $method(self, o: Self) -> Self {
                let ([a, b, c, d], [e, f, g, h]) = (self.0, o.0);
                Lanes([a $op e, b $op f, c $op g, d $op h])
            }
        }
    };
}

/// Lane-wise `op` with the same `f64` in every lane.
macro_rules! lanewise_f64 {
    ($trait_:ident, $method:ident, $op:tt) => {
        impl $trait_<f64> for Lanes {
            type Output = Self;
            #[inline(always)]
            fn $method(self, y: f64) -> Self {
                let [a, b, c, d] = self.0;
                Lanes([a $op y, b $op y, c $op y, d $op y])
            }
        }
    };
}

lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);
lanewise_f64!(Add, add, +);
lanewise_f64!(Mul, mul, *);

impl AddAssign for Lanes {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl SubAssign for Lanes {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A kernel over [`Real`] with every operation.
    fn kernel<T: Real>(x: T, y: T) -> T {
        let mut acc = T::from(0.0);
        acc += x * 0.3 * y + (x + 1.0) / (y * 2.0) - (-x).abs();
        acc -= y + 2.0 + T::from(1.5) / x;
        acc
    }

    #[test]
    fn each_lane_is_bitwise_its_scalar_evaluation_and_sum_accumulates_in_order() {
        let xs = [0.1, -2.7, 3.3e5, 7e-9];
        let ys = [1.9, 0.45, -1e-3, 2.2e7];
        let lanes = kernel(Lanes(xs), Lanes(ys));
        for p in 0..4 {
            assert_eq!(lanes.0[p].to_bits(), kernel(xs[p], ys[p]).to_bits());
        }
        // In order: ((1 + 1e16) − 1e16) + 1 = 1 (pairwise would give 0).
        assert_eq!(Lanes([1.0, 1e16, -1e16, 1.0]).sum(), 1.0);
        // The transposed element sums are the entries' sums, bitwise.
        let f: [Lanes; ELEMENT_DOF] = std::array::from_fn(|j| {
            Lanes(std::array::from_fn(|p| {
                ((j * 4 + p) as f64 * 0.77).sin() * 10f64.powi(p as i32 * 5)
            }))
        });
        let sums = element_sums(&f);
        for (j, x) in f.iter().enumerate() {
            assert_eq!(sums[j].to_bits(), x.sum().to_bits(), "entry {j}");
        }
    }
}
