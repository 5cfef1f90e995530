//! faer's general sparse LU with partial pivoting (all faer code of the
//! solver lives in this module).
//!
//! It is the fallback when the block elimination meets a singular diagonal
//! block (global pivoting can still succeed), and the comparison point for
//! the ordering benchmark. It factorises the same matrix, taken from the
//! original (non-fill) sub-blocks of the block pattern; the symbolic analysis
//! (faer's default COLAMD column ordering) is done once, numeric
//! factorisations run sequentially (`Par::Seq`).

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, LuSymbolicParams, NumericLu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::traits::ComplexField;
use faer::{Conj, MatMut, Par};

use super::block_lu::BlockSymbolic;
use super::scalar::Scalar;
use crate::error::LinalgError;

/// The CSC pattern shared by the real and complex factorisations.
#[derive(Debug, Clone)]
pub struct FaerPattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Index into the block value array of each CSC entry.
    src: Vec<u32>,
    symbolic: SymbolicLu<usize>,
}

impl FaerPattern {
    /// Builds the CSC pattern of the original sub-blocks and runs faer's
    /// symbolic analysis.
    pub fn new(sym: &BlockSymbolic) -> Result<Self, LinalgError> {
        let n = sym.dim();
        let mut entries: Vec<(usize, usize, u32)> = Vec::with_capacity(sym.nnz_original());
        for (i, j, off, fill) in sym.sub_blocks() {
            if fill {
                continue;
            }
            let (si, ni) = sym.span(i);
            let (sj, nj) = sym.span(j);
            for r in 0..ni {
                for c in 0..nj {
                    entries.push((sj + c, si + r, (off + r * nj + c) as u32));
                }
            }
        }
        entries.sort_unstable();
        let mut col_ptr = vec![0usize; n + 1];
        for &(c, _, _) in &entries {
            col_ptr[c + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let row_idx: Vec<usize> = entries.iter().map(|e| e.1).collect();
        let src: Vec<u32> = entries.iter().map(|e| e.2).collect();
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_lu(pattern, LuSymbolicParams::default())
            .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
        Ok(Self { n, col_ptr, row_idx, src, symbolic })
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }
}

/// A numeric faer LU for one scalar type.
pub struct FaerLu<T: Scalar + ComplexField> {
    values: Vec<T>,
    numeric: NumericLu<usize, T>,
    mem: MemBuffer,
    factored: bool,
}

impl<T: Scalar + ComplexField> FaerLu<T> {
    /// Workspace for factorisations and solves with `pattern`.
    pub fn new(pattern: &FaerPattern) -> Self {
        let req = StackReq::any_of(&[
            pattern.symbolic.factorize_numeric_lu_scratch::<T>(Par::Seq, Default::default()),
            pattern.symbolic.solve_in_place_scratch::<T>(1, Par::Seq),
        ]);
        Self {
            values: vec![T::ZERO; pattern.nnz()],
            numeric: NumericLu::new(),
            mem: MemBuffer::new(req),
            factored: false,
        }
    }

    /// Factorises the matrix whose block values are `block_values`.
    pub fn factor(&mut self, pattern: &FaerPattern, block_values: &[T]) -> Result<(), LinalgError> {
        self.factored = false;
        for (v, &s) in self.values.iter_mut().zip(&pattern.src) {
            *v = block_values[s as usize];
        }
        let sym = SymbolicSparseColMatRef::new_checked(pattern.n, pattern.n, &pattern.col_ptr, None, &pattern.row_idx);
        let mat = SparseColMatRef::new(sym, &self.values);
        let stack = MemStack::new(&mut self.mem);
        pattern
            .symbolic
            .factorize_numeric_lu(&mut self.numeric, mat, Par::Seq, stack, Default::default())
            .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
        self.factored = true;
        Ok(())
    }

    /// Solves in place; `b` is ordered like the block unknowns.
    pub fn solve(&mut self, pattern: &FaerPattern, b: &mut [T]) -> Result<(), LinalgError> {
        if !self.factored {
            return Err(LinalgError::Faer("solve before a successful factorisation".to_string()));
        }
        let lu = LuRef::new_unchecked(&pattern.symbolic, &self.numeric);
        let stack = MemStack::new(&mut self.mem);
        let rhs = MatMut::from_column_major_slice_mut(b, pattern.n, 1);
        lu.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack);
        if b.iter().all(|x| x.finite()) {
            Ok(())
        } else {
            Err(LinalgError::NonFinite)
        }
    }
}
