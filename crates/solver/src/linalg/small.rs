//! Small dense kernels of fixed size: the 3 x 3 solve of a bearing's local
//! friction problem and the block products of the block elimination.
//!
//! Both were measured against nalgebra's stack-allocated fixed-size matrices
//! (`cargo bench -p quakejoint-solver --bench small`, docs/performance.md,
//! "Small kernels"), which are made for this kind of algebra; the numbers
//! there decide which is used: the hand-written kernels. nalgebra's
//! products are faster only on column-major storage (0.89 to 1.0 us per 270
//! against 1.0 to 1.8 us); viewed in place on the row-major blocks the block
//! elimination stores they are not (1.1 to 2.0 us), and its complex
//! products are 1.7 to 2.1 times slower. Its 3 x 3 LU: see [`solve3`] and
//! [`solve3_adjugate`] (5.1 us per 270 against its 8.9 us).

use super::scalar::Scalar;

/// `y -= A x` for a row-major `A` of `R x C` (sizes fixed at compile time,
/// which lets the compiler unroll the loops). Real products accumulate
/// column by column (R independent sums, 1.3 to 1.9 times faster than row
/// dot products; the reference run 1.5 % faster, with the same sums in the
/// same order, so bit-identical results), complex ones row by row (their
/// multiply already has the parallelism, and the column form is 1.1 to 1.2
/// times slower).
#[inline(always)]
pub fn gemv_sub_fixed<T: Scalar, const R: usize, const C: usize>(y: &mut [T], a: &[T], x: &[T]) {
    let (y, a, x) = (&mut y[..R], &a[..R * C], &x[..C]);
    if T::BY_COLUMNS {
        let mut acc = [T::ZERO; R];
        for c in 0..C {
            let xc = x[c];
            for r in 0..R {
                acc[r] += a[r * C + c] * xc;
            }
        }
        for r in 0..R {
            y[r] -= acc[r];
        }
    } else {
        for r in 0..R {
            let mut s = T::ZERO;
            for c in 0..C {
                s += a[r * C + c] * x[c];
            }
            y[r] -= s;
        }
    }
}

/// Solves a 3x3 system by Gaussian elimination with partial pivoting
/// (None if singular or not finite). nalgebra's LU is 1.35 times faster on
/// its own (`benches/small.rs`) but made the reference run 3 % slower inside
/// the local friction solve (3.99 s against 3.87 s): kept hand-written.
#[inline(always)]
pub fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    for k in 0..3 {
        let p = (k..3).max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))?;
        if a[p][k] == 0.0 || !a[p][k].is_finite() {
            return None;
        }
        a.swap(k, p);
        b.swap(k, p);
        for i in k + 1..3 {
            let f = a[i][k] / a[k][k];
            let pivot_row = a[k];
            for (x, p) in a[i].iter_mut().zip(pivot_row).skip(k) {
                *x -= f * p;
            }
            b[i] -= f * b[k];
        }
    }
    let mut x = [0.0; 3];
    for k in (0..3).rev() {
        let s: f64 = (k + 1..3).map(|j| a[k][j] * x[j]).sum();
        x[k] = (b[k] - s) / a[k][k];
    }
    Some(x)
}

/// Solves a 3x3 system by the adjugate (Cramer's rule): one division and no
/// pivoting branches. In the local friction solve it made the reference run
/// 6 % faster than [`solve3`] (2.96 against 3.15 s; the pivot search's
/// branches are what cost). Cramer's rule is accurate while the matrix is
/// well conditioned, as the local friction matrices are (`m/h A^-1 + h k A +
/// c I` plus a non-negative diagonal); should the rows be close to
/// dependent (`det^2` below `1e-12` times the product of the squared row
/// norms, Hadamard's bound), the pivoted elimination [`solve3`] is used.
/// None if singular or not finite.
#[inline(always)]
pub fn solve3_adjugate(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    let c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    let c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    let det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    let row2 = |r: [f64; 3]| r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    let hadamard = row2(a[0]) * row2(a[1]) * row2(a[2]);
    // (also false for NaN, and for a product that overflows)
    if !(det * det > 1e-12 * hadamard && hadamard.is_finite()) {
        return solve3(a, b);
    }
    let r = 1.0 / det;
    let x = [
        r * (c00 * b[0]
            + (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * b[1]
            + (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * b[2]),
        r * (c01 * b[0]
            + (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * b[1]
            + (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * b[2]),
        r * (c02 * b[0]
            + (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * b[1]
            + (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * b[2]),
    ];
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solve3_pivots_and_refuses_singular_systems() {
        let x = solve3([[0.0, 2.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 3.0]], [3.0, 1.0, 4.0]).unwrap();
        for (got, want) in x.iter().zip([1.0, 1.0, 1.0]) {
            assert!((got - want).abs() < 1e-14, "{x:?}");
        }
        assert!(solve3([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]], [1.0, 2.0, 3.0]).is_none());
    }

    #[test]
    fn gemv_subtracts_the_row_major_product() {
        let a = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let mut y = [10.0, 20.0];
        gemv_sub_fixed::<f64, 2, 3>(&mut y, &a, &[1.0, 1.0, 1.0]);
        assert_eq!(y, [4.0, 5.0]);
    }
}
