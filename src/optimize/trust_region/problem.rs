//! The argmin problem wrapping a [`BlackBox`] for the trust-region solver.

use std::borrow::Borrow;

use argmin::core::{CostFunction, Error, SendAlias, SyncAlias};

use crate::optimize::evaluation::{BlackBox, Evaluation};

/// The argmin problem: a [`BlackBox`] whose evaluations are sanitised (non-finite ⇒ failed) and
/// whose bulk evaluation goes through [`BlackBox::evaluate_batch`].
pub struct BlackBoxProblem<'a, B: ?Sized> {
    bb: &'a B,
}

impl<'a, B: BlackBox + ?Sized> BlackBoxProblem<'a, B> {
    /// Wraps a black box.
    pub fn new(bb: &'a B) -> Self {
        BlackBoxProblem { bb }
    }
}

impl<B: BlackBox + ?Sized> CostFunction for BlackBoxProblem<'_, B> {
    type Param = Vec<f64>;
    type Output = Evaluation;

    fn cost(&self, x: &Vec<f64>) -> Result<Evaluation, Error> {
        Ok(self.bb.evaluate(x).sanitized(self.bb.n_constraints()))
    }

    fn bulk_cost<P>(&self, params: &[P]) -> Result<Vec<Evaluation>, Error>
    where
        P: Borrow<Vec<f64>> + SyncAlias,
        Self::Output: SendAlias,
        Self: SyncAlias,
    {
        let xs: Vec<Vec<f64>> = params.iter().map(|p| p.borrow().clone()).collect();
        let m = self.bb.n_constraints();
        let mut out: Vec<Evaluation> = self
            .bb
            .evaluate_batch(&xs)
            .into_iter()
            .map(|e| e.sanitized(m))
            .collect();
        // A batch of the wrong length is a black-box bug: missing results count as failures.
        out.resize(xs.len(), Evaluation::failure(m));
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct ShortBatch;
    impl BlackBox for ShortBatch {
        fn dim(&self) -> usize {
            1
        }
        fn n_constraints(&self) -> usize {
            1
        }
        fn evaluate(&self, x: &[f64]) -> Evaluation {
            Evaluation::new(x[0], vec![f64::NAN])
        }
        fn evaluate_batch(&self, xs: &[Vec<f64>]) -> Vec<Evaluation> {
            xs.iter()
                .skip(1)
                .map(|x| Evaluation::new(x[0], vec![0.0]))
                .collect()
        }
    }

    /// Non-finite values and missing batch results become failures, never panics.
    #[test]
    fn problem_sanitises_evaluations() {
        let p = BlackBoxProblem::new(&ShortBatch);
        assert!(p.cost(&vec![1.0]).unwrap().failed);
        let batch = p.bulk_cost(&[vec![1.0], vec![2.0], vec![3.0]]).unwrap();
        assert_eq!(batch.len(), 3);
        assert!(!batch[0].failed && !batch[1].failed && batch[2].failed);
    }
}
