//! The dense kernels of the numeric factorisation and solve, on the small
//! row-major blocks (at most [`MAX_BLOCK`] unknowns a side): partial-pivoting
//! LU and inverse of a diagonal block, block products with the joint's
//! shapes fixed at compile time.

use super::MAX_BLOCK;
use crate::linalg::scalar::Scalar;
use crate::linalg::small::gemv_sub_fixed;

/// `y -= A x` for a row-major `A (y.len() x x.len())`; the block shapes of the
/// expansion joint go to kernels with the sizes fixed at compile time.
#[inline(always)]
pub(super) fn gemv_sub<T: Scalar>(y: &mut [T], a: &[T], x: &[T]) {
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
/// Returns `(largest pivot candidate, block scale)` when singular.
#[inline(always)]
pub(super) fn dense_lu<T: Scalar>(a: &mut [T], n: usize, piv: &mut [u8]) -> Result<(), (f64, f64)> {
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.magnitude()));
    let tol = 1e-13 * scale;
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
        // NaN fails both comparisons, so test for it explicitly
        if best.is_nan() || best <= tol || best.is_infinite() {
            return Err((best, scale));
        }
        piv[k] = p as u8;
        if p != k {
            for c in 0..n {
                a.swap(k * n + c, p * n + c);
            }
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
pub(super) fn dense_inverse<T: Scalar>(lu: &[T], n: usize, piv: &[u8], inv: &mut [T]) {
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
pub(super) fn gemm_set<T: Scalar>(c: &mut [T], a: &[T], b: &[T], n: usize, k: usize, m: usize) {
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
pub(super) fn gemm_sub<T: Scalar>(c: &mut [T], a: &[T], b: &[T], n: usize, k: usize, m: usize) {
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
pub(super) fn gemm_sub_fixed<T: Scalar, const N: usize, const K: usize, const M: usize>(c: &mut [T], a: &[T], b: &[T]) {
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
pub(super) fn gemm_sub_any<T: Scalar>(c: &mut [T], a: &[T], b: &[T], n: usize, k: usize, m: usize) {
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
