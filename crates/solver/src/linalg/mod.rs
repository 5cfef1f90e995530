//! Sparse linear algebra for the iteration matrices
//! `[c^2 M + c D + K, G^T S; S G, 0]` (real `c`, and complex `c` for the
//! complex pair of Radau systems).
//!
//! [`block_lu`] is the default: a structure-aware block elimination whose
//! symbolic analysis is done once per model. [`faer_lu`] (faer's sparse LU
//! with COLAMD and partial pivoting) takes over for one factorisation when a
//! diagonal block turns out singular, and can be chosen outright for
//! comparison. Both run on the calling thread only.

pub mod block_lu;
pub mod faer_lu;
pub mod scalar;
pub mod small;

use faer::traits::ComplexField;

use crate::error::LinalgError;
use block_lu::{block_matvec, BlockLu, BlockSymbolic};
use faer_lu::{FaerLu, FaerPattern};
use scalar::Scalar;

/// Which sparse LU factorises the iteration matrices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LinearSolver {
    /// Block elimination, with faer as fallback on a singular block (default).
    #[default]
    Block,
    /// faer's sparse LU (COLAMD ordering, partial pivoting) for every factorisation.
    Faer,
}

/// The faer pattern of a model, built on first use and shared by the real
/// and complex solvers.
#[derive(Default)]
pub struct FaerCache(Option<FaerPattern>);

impl FaerCache {
    fn get(&mut self, sym: &BlockSymbolic) -> Result<&FaerPattern, LinalgError> {
        if self.0.is_none() {
            self.0 = Some(FaerPattern::new(sym)?);
        }
        Ok(self.0.as_ref().expect("just built"))
    }
}

/// A factorised iteration matrix of one scalar type.
pub struct KktSolver<T: Scalar + ComplexField> {
    mode: LinearSolver,
    block: BlockLu<T>,
    faer: Option<FaerLu<T>>,
    using_faer: bool,
    buffer: Vec<T>,
    /// Factorisations that needed the faer fallback.
    pub fallbacks: u64,
}

impl<T: Scalar + ComplexField> KktSolver<T> {
    /// Storage for the given structure.
    pub fn new(sym: &BlockSymbolic, mode: LinearSolver) -> Self {
        Self { mode, block: BlockLu::new(sym), faer: None, using_faer: false, buffer: Vec::new(), fallbacks: 0 }
    }

    /// Forms (with `form`, which writes the matrix in block layout) and
    /// factorises the matrix.
    pub fn factor(
        &mut self,
        sym: &BlockSymbolic,
        cache: &mut FaerCache,
        form: &dyn Fn(&mut [T]),
        describe: &dyn Fn(usize) -> String,
    ) -> Result<(), LinalgError> {
        self.using_faer = false;
        if self.mode == LinearSolver::Block {
            form(self.block.values_mut());
            match self.block.factor(sym, describe) {
                Ok(()) => return Ok(()),
                Err(LinalgError::Singular { .. }) => self.fallbacks += 1,
                Err(e) => return Err(e),
            }
        }
        self.buffer.resize(sym.nnz(), T::ZERO);
        form(&mut self.buffer);
        let pattern = cache.get(sym)?;
        let faer = self.faer.get_or_insert_with(|| FaerLu::new(pattern));
        faer.factor(pattern, &self.buffer)?;
        self.using_faer = true;
        Ok(())
    }

    /// Solves in place (unknowns in block order).
    pub fn solve(&mut self, sym: &BlockSymbolic, cache: &mut FaerCache, b: &mut [T]) -> Result<(), LinalgError> {
        if self.using_faer {
            let pattern = cache.get(sym)?;
            let faer = self.faer.as_mut().ok_or(LinalgError::NonFinite)?;
            let rhs = b.to_vec();
            faer.solve(pattern, b)?;
            // faer does not report a (numerically) singular matrix: check the residual
            let mut ax = vec![T::ZERO; b.len()];
            block_matvec(sym, &self.buffer, b, &mut ax);
            let scale = rhs.iter().map(|x| x.magnitude()).fold(0.0, f64::max);
            let worst = ax.iter().zip(&rhs).map(|(a, r)| (*a - *r).magnitude()).fold(0.0, f64::max);
            if worst > 1e-8 * scale.max(f64::MIN_POSITIVE) {
                return Err(LinalgError::Singular { location: "faer sparse LU".to_string(), pivot: worst, scale });
            }
            Ok(())
        } else {
            self.block.solve(sym, b);
            if b.iter().all(|x| x.finite()) {
                Ok(())
            } else {
                Err(LinalgError::NonFinite)
            }
        }
    }
}
