//! Structure-aware sparse LU: block Gaussian elimination over small dense
//! blocks.
//!
//! Every unknown belongs to a block: one body's free coordinates followed by
//! the constraint equations matched to them (at most 3 + 3 unknowns). The
//! matrix is stored as dense sub-blocks `(i, j)` of a block pattern that is
//! symmetric in structure (not in value). The symbolic analysis, done once per
//! model, orders the blocks by minimum (size-weighted) degree, computes the
//! fill and the list of block updates; the numeric factorisation then runs a
//! fixed sequence of small dense operations, pivoting (partially) inside each
//! diagonal block only. A diagonal block that is singular is reported, never
//! divided by.
//!
//! In the expansion joint this eliminates each bearing (3 coordinates and its
//! 2 prismatic equations) locally first, then the center beams, leaving a
//! small dense block for the support beams and the deck.
//!
//! Parts: `symbolic.rs` (the analysis: order, fill, update lists, solve
//! shapes); this file holds the numeric side: the factorisation, the solve
//! and their small dense kernels.

mod symbolic;

use super::scalar::Scalar;
use super::small::gemv_sub_fixed;
use crate::error::LinalgError;
use symbolic::Shape;

pub use symbolic::{block_matvec, BlockOrdering, BlockSymbolic};

/// Largest block: 3 coordinates and 3 matched equations.
pub const MAX_BLOCK: usize = 6;

/// A numeric block LU factorisation for one scalar type (diagonal blocks
/// stored inverted).
#[derive(Debug, Clone)]
pub struct BlockLu<T: Scalar> {
    values: Vec<T>,
    scratch_col: Vec<T>,
    scratch_row: Vec<T>,
}

impl<T: Scalar> BlockLu<T> {
    /// Storage for a factorisation with the given structure.
    pub fn new(sym: &BlockSymbolic) -> Self {
        Self {
            values: vec![T::ZERO; sym.nnz],
            scratch_col: Vec::with_capacity(sym.n * MAX_BLOCK),
            scratch_row: Vec::with_capacity(sym.n * MAX_BLOCK),
        }
    }

    /// The value array to be filled with the matrix before [`Self::factor`].
    pub fn values_mut(&mut self) -> &mut [T] {
        &mut self.values
    }

    /// Factorises in place. `describe` names a position in error messages.
    ///
    /// Each diagonal block is factorised with partial pivoting (which decides
    /// whether it is singular) and then replaced by its inverse, so that
    /// `X_kj = D_kk^-1 A_kj` and the solves are small matrix products.
    pub fn factor(&mut self, sym: &BlockSymbolic, describe: &dyn Fn(usize) -> String) -> Result<(), LinalgError> {
        crate::isa::run(
            #[inline(always)]
            || self.factor_impl(sym, describe),
        )
    }

    /// [`Self::factor`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn factor_impl(&mut self, sym: &BlockSymbolic, describe: &dyn Fn(usize) -> String) -> Result<(), LinalgError> {
        let values = &mut self.values;
        let mut lu = [T::ZERO; MAX_BLOCK * MAX_BLOCK];
        let mut piv = [0u8; MAX_BLOCK];
        let mut tmp = [T::ZERO; MAX_BLOCK * MAX_BLOCK];
        for k in 0..sym.sizes.len() {
            let nk = sym.sizes[k] as usize;
            let dk = sym.diag[k] as usize;
            lu[..nk * nk].copy_from_slice(&values[dk..dk + nk * nk]);
            dense_lu(&mut lu[..nk * nk], nk, &mut piv[..nk]).map_err(|(pivot, scale)| LinalgError::Singular {
                location: describe(k),
                pivot,
                scale,
            })?;
            let dinv = &mut values[dk..dk + nk * nk];
            dense_inverse(&lu[..nk * nk], nk, &piv[..nk], dinv);
            let (l0, l1) = (sym.later_ptr[k] as usize, sym.later_ptr[k + 1] as usize);
            if l0 == l1 {
                continue;
            }
            let mut dcopy = [T::ZERO; MAX_BLOCK * MAX_BLOCK];
            dcopy[..nk * nk].copy_from_slice(&values[dk..dk + nk * nk]);
            // X_kj = D_kk^-1 A_kj in place of A_kj; keep copies of row and column k
            self.scratch_col.clear();
            self.scratch_row.clear();
            for t in l0..l1 {
                let j = sym.later_pos[t] as usize;
                let nj = sym.sizes[j] as usize;
                let okj = sym.off_kj[t] as usize;
                let x = &mut values[okj..okj + nk * nj];
                tmp[..nk * nj].copy_from_slice(x);
                gemm_set(x, &dcopy[..nk * nk], &tmp[..nk * nj], nk, nk, nj);
                self.scratch_row.extend_from_slice(x);
                let ojk = sym.off_jk[t] as usize;
                self.scratch_col.extend_from_slice(&values[ojk..ojk + nj * nk]);
            }
            // A_ij -= A_ik X_kj
            let mut u = sym.update_ptr[k] as usize;
            let mut col_at = 0usize;
            for ti in l0..l1 {
                let ni = sym.sizes[sym.later_pos[ti] as usize] as usize;
                let a_ik = &self.scratch_col[col_at..col_at + ni * nk];
                col_at += ni * nk;
                let mut row_at = 0usize;
                for tj in l0..l1 {
                    let nj = sym.sizes[sym.later_pos[tj] as usize] as usize;
                    let x_kj = &self.scratch_row[row_at..row_at + nk * nj];
                    row_at += nk * nj;
                    let o = sym.update_off[u] as usize;
                    u += 1;
                    gemm_sub(&mut values[o..o + ni * nj], a_ik, x_kj, ni, nk, nj);
                }
            }
        }
        Ok(())
    }

    /// Solves `A x = b` in place (`b` in block-position order of unknowns).
    pub fn solve(&self, sym: &BlockSymbolic, b: &mut [T]) {
        crate::isa::run(
            #[inline(always)]
            || self.solve_impl(sym, b),
        )
    }

    /// [`Self::solve`], compiled into each version of [`crate::isa::run`].
    #[inline(always)]
    fn solve_impl(&self, sym: &BlockSymbolic, b: &mut [T]) {
        let values = &self.values[..];
        let s = SolveView::of(sym);
        let nb = s.sizes.len();
        for k in 0..nb {
            match s.shapes[k] {
                Shape::Three => {
                    forward_three(values, &s, b, k);
                    continue;
                }
                Shape::General => {}
            }
            let nk = s.sizes[k] as usize;
            let pk = s.starts[k] as usize;
            let dk = s.diag[k] as usize;
            // y = D_kk^-1 b_k (as -(0 - D b), exact)
            let mut y = [T::ZERO; MAX_BLOCK];
            gemv_sub(&mut y[..nk], &values[dk..dk + nk * nk], &b[pk..pk + nk]);
            for (bk, yk) in b[pk..pk + nk].iter_mut().zip(y.iter_mut()) {
                *yk = -*yk;
                *bk = *yk;
            }
            for t in s.later_ptr[k] as usize..s.later_ptr[k + 1] as usize {
                let i = s.later_pos[t] as usize;
                let ni = s.sizes[i] as usize;
                let pi = s.starts[i] as usize;
                let o = s.off_jk[t] as usize;
                gemv_sub(&mut b[pi..pi + ni], &values[o..o + ni * nk], &y[..nk]);
            }
        }
        for k in (0..nb).rev() {
            match s.shapes[k] {
                Shape::Three => {
                    backward_three(values, &s, b, k);
                    continue;
                }
                Shape::General => {}
            }
            let nk = s.sizes[k] as usize;
            let pk = s.starts[k] as usize;
            let mut acc = [T::ZERO; MAX_BLOCK];
            for t in s.later_ptr[k] as usize..s.later_ptr[k + 1] as usize {
                let j = s.later_pos[t] as usize;
                let nj = s.sizes[j] as usize;
                let pj = s.starts[j] as usize;
                let o = s.off_kj[t] as usize;
                gemv_sub(&mut acc[..nk], &values[o..o + nk * nj], &b[pj..pj + nj]);
            }
            for r in 0..nk {
                b[pk + r] += acc[r];
            }
        }
    }
}

/// The arrays of a [`BlockSymbolic`] that a solve reads, as slices taken
/// once (through the vectors, every store into the right-hand side would
/// make the compiler reload their addresses).
struct SolveView<'a> {
    sizes: &'a [u32],
    starts: &'a [u32],
    diag: &'a [u32],
    shapes: &'a [Shape],
    later_ptr: &'a [u32],
    later_pos: &'a [u32],
    off_kj: &'a [u32],
    off_jk: &'a [u32],
}

impl<'a> SolveView<'a> {
    #[inline(always)]
    fn of(sym: &'a BlockSymbolic) -> Self {
        Self {
            sizes: &sym.sizes,
            starts: &sym.starts,
            diag: &sym.diag,
            shapes: &sym.shapes,
            later_ptr: &sym.later_ptr,
            later_pos: &sym.later_pos,
            off_kj: &sym.off_kj,
            off_jk: &sym.off_jk,
        }
    }
}

/// The forward step at a position of [`Shape::Three`] (as the general
/// loop's, in the same order).
#[inline(always)]
fn forward_three<T: Scalar>(values: &[T], sym: &SolveView<'_>, b: &mut [T], k: usize) {
    let pk = sym.starts[k] as usize;
    let dk = sym.diag[k] as usize;
    let mut y = [T::ZERO; 3];
    gemv_sub_fixed::<T, 3, 3>(&mut y, &values[dk..dk + 9], &b[pk..pk + 3]);
    for r in 0..3 {
        y[r] = -y[r];
        b[pk + r] = y[r];
    }
    for t in sym.later_ptr[k] as usize..sym.later_ptr[k + 1] as usize {
        let i = sym.later_pos[t] as usize;
        let (pi, o) = (sym.starts[i] as usize, sym.off_jk[t] as usize);
        match sym.sizes[i] {
            3 => gemv_sub_fixed::<T, 3, 3>(&mut b[pi..pi + 3], &values[o..o + 9], &y),
            5 => gemv_sub_fixed::<T, 5, 3>(&mut b[pi..pi + 5], &values[o..o + 15], &y),
            6 => gemv_sub_fixed::<T, 6, 3>(&mut b[pi..pi + 6], &values[o..o + 18], &y),
            _ => unreachable!("Shape::Three admits neighbours of 3, 5 and 6 unknowns only"),
        }
    }
}

/// The backward step at a position of [`Shape::Three`].
#[inline(always)]
fn backward_three<T: Scalar>(values: &[T], sym: &SolveView<'_>, b: &mut [T], k: usize) {
    let pk = sym.starts[k] as usize;
    let mut acc = [T::ZERO; 3];
    for t in sym.later_ptr[k] as usize..sym.later_ptr[k + 1] as usize {
        let j = sym.later_pos[t] as usize;
        let (pj, o) = (sym.starts[j] as usize, sym.off_kj[t] as usize);
        match sym.sizes[j] {
            3 => gemv_sub_fixed::<T, 3, 3>(&mut acc, &values[o..o + 9], &b[pj..pj + 3]),
            5 => gemv_sub_fixed::<T, 3, 5>(&mut acc, &values[o..o + 15], &b[pj..pj + 5]),
            6 => gemv_sub_fixed::<T, 3, 6>(&mut acc, &values[o..o + 18], &b[pj..pj + 6]),
            _ => unreachable!("Shape::Three admits neighbours of 3, 5 and 6 unknowns only"),
        }
    }
    for r in 0..3 {
        b[pk + r] += acc[r];
    }
}

/// `y -= A x` for a row-major `A (y.len() x x.len())`; the block shapes of the
/// expansion joint go to kernels with the sizes fixed at compile time.
#[inline(always)]
fn gemv_sub<T: Scalar>(y: &mut [T], a: &[T], x: &[T]) {
    match (y.len(), x.len()) {
        (6, 3) => gemv_sub_fixed::<T, 6, 3>(y, a, x),
        (3, 3) => gemv_sub_fixed::<T, 3, 3>(y, a, x),
        (5, 5) => gemv_sub_fixed::<T, 5, 5>(y, a, x),
        (3, 6) => gemv_sub_fixed::<T, 3, 6>(y, a, x),
        (6, 6) => gemv_sub_fixed::<T, 6, 6>(y, a, x),
        (6, 5) => gemv_sub_fixed::<T, 6, 5>(y, a, x),
        (5, 6) => gemv_sub_fixed::<T, 5, 6>(y, a, x),
        (3, 5) => gemv_sub_fixed::<T, 3, 5>(y, a, x),
        (5, 3) => gemv_sub_fixed::<T, 5, 3>(y, a, x),
        (ny, nx) => {
            for (r, row) in a.chunks_exact(nx).take(ny).enumerate() {
                let mut s = T::ZERO;
                for (&arc, &xc) in row.iter().zip(x) {
                    s += arc * xc;
                }
                y[r] -= s;
            }
        }
    }
}

/// Dense LU with partial pivoting of a row-major `n x n` block, in place.
/// Returns `(largest pivot candidate, its row's scale)` when singular.
///
/// A pivot is taken as zero below `1e-13` times the largest entry of the
/// row it comes from (scaled partial pivoting's test; the choice of the
/// pivot stays the largest magnitude). A block mixes rows of different
/// units: a body's coordinates (stiffness and mass, up to 1e15 in the
/// iteration matrix) and the constraint equations matched to it (entries
/// of order one, and a Schur complement that can be small). Measured
/// against the whole block's largest entry, a constraint row's pivot of
/// 1e-2 beside a stiffness of 1e15 looked singular though its row is
/// well determined: a deck end tied to few modes of a bridge (whose two
/// ends the modes move almost alike) fell back to faer at every
/// factorisation, 12 to 15 times the cost.
#[inline(always)]
fn dense_lu<T: Scalar>(a: &mut [T], n: usize, piv: &mut [u8]) -> Result<(), (f64, f64)> {
    let mut rows = [0.0f64; MAX_BLOCK];
    for (r, scale) in rows.iter_mut().enumerate().take(n) {
        *scale = a[r * n..(r + 1) * n].iter().fold(0.0f64, |m, x| m.max(x.magnitude()));
    }
    for k in 0..n {
        let mut p = k;
        let mut best = a[k * n + k].magnitude();
        for r in k + 1..n {
            let m = a[r * n + k].magnitude();
            if m > best {
                best = m;
                p = r;
            }
        }
        let scale = rows[p];
        // NaN fails both comparisons, so test for it explicitly
        if best.is_nan() || best <= 1e-13 * scale || best.is_infinite() {
            return Err((best, scale));
        }
        piv[k] = p as u8;
        if p != k {
            for c in 0..n {
                a.swap(k * n + c, p * n + c);
            }
            rows.swap(k, p);
        }
        let inv = T::ONE / a[k * n + k];
        for r in k + 1..n {
            let f = a[r * n + k] * inv;
            a[r * n + k] = f;
            if f != T::ZERO {
                for c in k + 1..n {
                    let u = a[k * n + c];
                    a[r * n + c] -= f * u;
                }
            }
        }
    }
    Ok(())
}

/// The inverse of `P^T L U` (row-major `n x n` LU with pivots) into `inv`.
#[inline(always)]
fn dense_inverse<T: Scalar>(lu: &[T], n: usize, piv: &[u8], inv: &mut [T]) {
    // solve LU X = P I column by column: start from the permuted identity
    inv.iter_mut().for_each(|x| *x = T::ZERO);
    let mut perm = [0usize; MAX_BLOCK];
    for (i, p) in perm.iter_mut().enumerate().take(n) {
        *p = i;
    }
    for k in 0..n {
        perm.swap(k, piv[k] as usize);
    }
    for (r, &p) in perm.iter().enumerate().take(n) {
        inv[r * n + p] = T::ONE;
    }
    for k in 0..n {
        for r in k + 1..n {
            let f = lu[r * n + k];
            for c in 0..n {
                let v = inv[k * n + c];
                inv[r * n + c] -= f * v;
            }
        }
    }
    for k in (0..n).rev() {
        let d = T::ONE / lu[k * n + k];
        for c in 0..n {
            inv[k * n + c] *= d;
        }
        for r in 0..k {
            let f = lu[r * n + k];
            for c in 0..n {
                let v = inv[k * n + c];
                inv[r * n + c] -= f * v;
            }
        }
    }
}

/// `c = a b` for row-major `a (n x k)`, `b (k x m)`, `c (n x m)`.
#[inline(always)]
fn gemm_set<T: Scalar>(c: &mut [T], a: &[T], b: &[T], n: usize, k: usize, m: usize) {
    c.iter_mut().for_each(|x| *x = T::ZERO);
    for r in 0..n {
        let cr = &mut c[r * m..r * m + m];
        for (p, &arp) in a[r * k..r * k + k].iter().enumerate() {
            for (cv, &bv) in cr.iter_mut().zip(&b[p * m..p * m + m]) {
                *cv += arp * bv;
            }
        }
    }
}

/// `c -= a b` for row-major `a (n x k)`, `b (k x m)`, `c (n x m)`.
///
/// The shapes of the expansion joint's updates (center beam on support beam
/// pairs, bearings on their neighbours) go to kernels with the sizes fixed at
/// compile time, which the compiler unrolls and vectorises; the others to a
/// loop that skips the structural zeros of constraint blocks.
#[inline(always)]
fn gemm_sub<T: Scalar>(c: &mut [T], a: &[T], b: &[T], n: usize, k: usize, m: usize) {
    match (n, k, m) {
        (6, 3, 6) => gemm_sub_fixed::<T, 6, 3, 6>(c, a, b),
        (6, 6, 6) => gemm_sub_fixed::<T, 6, 6, 6>(c, a, b),
        (6, 5, 6) => gemm_sub_fixed::<T, 6, 5, 6>(c, a, b),
        (3, 5, 6) => gemm_sub_fixed::<T, 3, 5, 6>(c, a, b),
        (6, 5, 3) => gemm_sub_fixed::<T, 6, 5, 3>(c, a, b),
        (5, 3, 6) => gemm_sub_fixed::<T, 5, 3, 6>(c, a, b),
        (6, 3, 5) => gemm_sub_fixed::<T, 6, 3, 5>(c, a, b),
        (3, 5, 3) => gemm_sub_fixed::<T, 3, 5, 3>(c, a, b),
        _ => gemm_sub_any(c, a, b, n, k, m),
    }
}

/// [`gemm_sub`] with the sizes known at compile time.
#[inline(always)]
fn gemm_sub_fixed<T: Scalar, const N: usize, const K: usize, const M: usize>(c: &mut [T], a: &[T], b: &[T]) {
    let (c, a, b) = (&mut c[..N * M], &a[..N * K], &b[..K * M]);
    for r in 0..N {
        let mut acc = [T::ZERO; M];
        acc.copy_from_slice(&c[r * M..r * M + M]);
        for p in 0..K {
            let arp = a[r * K + p];
            if arp == T::ZERO {
                continue;
            }
            for (x, &bv) in acc.iter_mut().zip(&b[p * M..p * M + M]) {
                *x -= arp * bv;
            }
        }
        c[r * M..r * M + M].copy_from_slice(&acc);
    }
}

/// [`gemm_sub`] for any sizes.
fn gemm_sub_any<T: Scalar>(c: &mut [T], a: &[T], b: &[T], n: usize, k: usize, m: usize) {
    for r in 0..n {
        let ar = &a[r * k..r * k + k];
        let cr = &mut c[r * m..r * m + m];
        for (p, &arp) in ar.iter().enumerate() {
            // constraint blocks carry many structural zeros
            if arp == T::ZERO {
                continue;
            }
            let bp = &b[p * m..p * m + m];
            for (cv, &bv) in cr.iter_mut().zip(bp) {
                *cv -= arp * bv;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::scalar::Complex64;

    /// Deterministic pseudo-random numbers for tests.
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    }

    fn dense_of<T: Scalar>(sym: &BlockSymbolic, vals: &[T]) -> Vec<Vec<T>> {
        let n = sym.dim();
        let mut a = vec![vec![T::ZERO; n]; n];
        for (i, j, off, _) in sym.sub_blocks() {
            let (si, ni) = sym.span(i);
            let (sj, nj) = sym.span(j);
            for r in 0..ni {
                for c in 0..nj {
                    a[si + r][sj + c] = vals[off + r * nj + c];
                }
            }
        }
        a
    }

    fn check_solve<T: Scalar>(make: impl Fn(f64, f64) -> T) {
        // A chain of 5 blocks with a star centre; sizes 3..5.
        let chain = (
            vec![5u32, 3, 5, 3, 6, 4, 1],
            vec![(0, 1), (1, 2), (2, 3), (3, 4), (4, 0), (5, 1), (5, 3), (6, 4), (6, 2)],
        );
        // Bearings: blocks of 3 each coupled to one of two beams (3) and one
        // of three supports (6, 5, 3), eliminated first ([`Shape::Three`]).
        let mut bearings = (vec![3u32, 3, 6, 5, 3], vec![(0, 2), (1, 3), (0, 4)]);
        for i in 0..12u32 {
            bearings.0.push(3);
            bearings.1.extend([(5 + i, i % 2), (5 + i, 2 + i % 3)]);
        }
        for ((sizes, edges), ordering) in [chain, bearings]
            .into_iter()
            .flat_map(|s| [(s.clone(), BlockOrdering::MinimumDegree), (s, BlockOrdering::Natural)])
        {
            let sym = BlockSymbolic::analyse(&sizes, &edges, ordering);
            let mut lu = BlockLu::<T>::new(&sym);
            let mut seed = 7u64;
            // fill original blocks with random values, diagonal dominant; fill blocks stay zero
            let mut vals = vec![T::ZERO; sym.nnz()];
            for (i, j, off, fill) in sym.sub_blocks() {
                if fill {
                    continue;
                }
                let (_, ni) = sym.span(i);
                let (_, nj) = sym.span(j);
                for r in 0..ni {
                    for c in 0..nj {
                        let mut v = make(lcg(&mut seed), lcg(&mut seed));
                        if i == j && r == c {
                            v += T::from_real(8.0);
                        }
                        vals[off + r * nj + c] = v;
                    }
                }
            }
            let a = dense_of(&sym, &vals);
            lu.values_mut().copy_from_slice(&vals);
            lu.factor(&sym, &|k| format!("block {k}")).unwrap();
            let n = sym.dim();
            let x_true: Vec<T> = (0..n).map(|i| make(i as f64 * 0.3 - 1.0, 0.1 * i as f64)).collect();
            let mut b: Vec<T> = (0..n)
                .map(|r| {
                    let mut s = T::ZERO;
                    for c in 0..n {
                        s += a[r][c] * x_true[c];
                    }
                    s
                })
                .collect();
            if sizes.len() == 17 && ordering == BlockOrdering::MinimumDegree {
                // (blocks 5.. are the bearings)
                let shape = |b: usize| sym.shapes[sym.position_of(b)];
                assert!((5..17).all(|b| shape(b) == Shape::Three), "every bearing takes fixed sizes");
                assert!(sym.shapes.contains(&Shape::General), "the others the general loop");
            }
            // the kernels of fixed size do what the general loop does, bit for bit
            let general = BlockSymbolic { shapes: vec![Shape::General; sym.blocks()], ..sym.clone() };
            let mut b_general = b.clone();
            lu.solve(&general, &mut b_general);
            lu.solve(&sym, &mut b);
            assert_eq!(b, b_general, "{ordering:?}: fixed-size kernels against the general loop");
            for i in 0..n {
                assert!((b[i] - x_true[i]).magnitude() < 1e-12, "{ordering:?} {i}: {:?} vs {:?}", b[i], x_true[i]);
            }
        }
    }

    /// Bearing-like blocks (3 unknowns, eliminated first, two neighbours)
    /// take the kernels of fixed size; the others the general loop.
    #[test]
    fn bearing_blocks_take_the_fixed_size_kernels() {
        let sym =
            BlockSymbolic::analyse(&[3, 6, 3, 3, 2], &[(0, 1), (0, 2), (3, 1), (3, 2), (4, 1)], BlockOrdering::Natural);
        assert_eq!(sym.shapes[..2], [Shape::Three, Shape::General]);
    }

    #[test]
    fn block_lu_solves_real_systems() {
        check_solve::<f64>(|a, _| a);
    }

    #[test]
    fn block_lu_solves_complex_systems() {
        check_solve::<Complex64>(Complex64::new);
    }

    #[test]
    fn zero_diagonal_inside_a_block_is_pivoted() {
        // A 2x2 KKT-like block [[1, 1], [1, 0]] needs a row interchange.
        let sym = BlockSymbolic::analyse(&[2], &[], BlockOrdering::MinimumDegree);
        let mut lu = BlockLu::<f64>::new(&sym);
        lu.values_mut().copy_from_slice(&[0.0, 1.0, 1.0, 1.0]);
        lu.factor(&sym, &|_| String::new()).unwrap();
        let mut b = [1.0, 3.0];
        lu.solve(&sym, &mut b);
        assert!((b[0] - 2.0).abs() < 1e-15 && (b[1] - 1.0).abs() < 1e-15);
    }

    #[test]
    fn singular_block_is_an_error_not_a_panic() {
        let sym = BlockSymbolic::analyse(&[2], &[], BlockOrdering::MinimumDegree);
        let mut lu = BlockLu::<f64>::new(&sym);
        lu.values_mut().copy_from_slice(&[1.0, 2.0, 2.0, 4.0]);
        let err = lu.factor(&sym, &|k| format!("block {k}")).unwrap_err();
        assert!(matches!(err, LinalgError::Singular { .. }), "{err:?}");
    }

    #[test]
    fn minimum_degree_eliminates_leaves_first() {
        // star: centre 0 with leaves 1..5 -> leaves first, no fill
        let sizes = [3u32, 5, 5, 5, 5, 5];
        let edges: Vec<(u32, u32)> = (1..6).map(|i| (0, i)).collect();
        let sym = BlockSymbolic::analyse(&sizes, &edges, BlockOrdering::MinimumDegree);
        assert_eq!(sym.block_at(5), 0, "centre last");
        assert!(sym.sub_blocks().all(|s| !s.3), "no fill");
    }
}
