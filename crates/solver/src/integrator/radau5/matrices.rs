//! The iteration matrices of Radau IIA and the products with their parts,
//! formed from the assembly's Jacobian arrays: the assembly gives `K`, `D`
//! and `G`, the integrator supplies the factors.

use crate::assembly::{Assembly, JacobianValues};
use crate::linalg::scalar::{Complex64, Scalar};

/// Writes the matrix `c2 M + c1 D + kcoef K` with the constraint blocks
/// `G` and `G^T` scaled by `gscale * m_ref` (per equation) into `out`, in
/// the block layout; `out` has [`crate::linalg::block_lu::BlockSymbolic::nnz`]
/// entries. With `(1, 0, 0, 1)` it is the projection's `[M, G^T S; S G, 0]`.
pub(crate) fn form<T: Scalar>(
    asm: &Assembly,
    c2: T,
    c1: T,
    kcoef: f64,
    gscale: f64,
    jac: &JacobianValues,
    out: &mut [T],
) {
    let nnz = out.len();
    for ((o, &k), &d) in out.iter_mut().zip(&jac.k[..nnz]).zip(&jac.d[..nnz]) {
        *o = T::from_real(kcoef * k) + c1.mul_real(d);
    }
    for (&p, &m) in asm.mass_pos.iter().zip(&asm.coord_mass) {
        out[p as usize] += c2.mul_real(m);
    }
    for (e, &g) in asm.g_entries.iter().zip(&jac.g) {
        let v = T::from_real(gscale * asm.eq_mref[e.eq as usize] * g);
        out[e.pos as usize] = v;
        out[e.pos_t as usize] = v;
    }
}

/// The real Radau iteration matrix `[c^2 M + c D + K, G^T S; S G, 0]`
/// (`S = c^2 m_ref` per equation; `c = gamma / h` [1/s]) of the system
/// `asm` at the Jacobian `jac`, in block layout; `out` has
/// [`crate::linalg::block_lu::BlockSymbolic::nnz`] entries.
pub fn form_real(asm: &Assembly, c: f64, jac: &JacobianValues, out: &mut [f64]) {
    form(asm, c * c, c, 1.0, c * c, jac, out);
}

/// The complex Radau iteration matrix for a complex `c` (`(alpha + i beta) / h`
/// [1/s]), its constraint rows scaled with `|c|^2`; as [`form_real`].
pub fn form_complex(asm: &Assembly, c: Complex64, jac: &JacobianValues, out: &mut [Complex64]) {
    form(asm, c * c, c, 1.0, c.norm_sqr(), jac, out);
}

/// `out = (c M + D) x` for a coordinate vector `x` (the error estimate).
pub(crate) fn mass_damping_product(asm: &Assembly, c: f64, jac: &JacobianValues, x: &[f64], out: &mut [f64]) {
    crate::isa::run(
        #[inline(always)]
        || mass_damping_product_impl(asm, c, jac, x, out),
    )
}

/// [`mass_damping_product`], compiled into each version of [`crate::isa::run`].
#[inline(always)]
fn mass_damping_product_impl(asm: &Assembly, c: f64, jac: &JacobianValues, x: &[f64], out: &mut [f64]) {
    // (by row, the sum in a register: the same additions in the same
    // order as entry by entry, without each waiting on the last one's
    // store to its row)
    for (r, o) in out.iter_mut().enumerate() {
        let mut s = c * asm.coord_mass[r] * x[r];
        for &(col, p) in &asm.d_cols[asm.d_row_ptr[r] as usize..asm.d_row_ptr[r + 1] as usize] {
            s += jac.d[p as usize] * x[col as usize];
        }
        *o = s;
    }
}

/// `out = G x` with the gradient values of `jac` (`x` over coordinates,
/// `out` over equations).
pub(crate) fn gradient_product<T: Scalar>(asm: &Assembly, jac: &JacobianValues, x: &[T], out: &mut [T]) {
    out.iter_mut().for_each(|o| *o = T::ZERO);
    for (e, &gv) in asm.g_entries.iter().zip(&jac.g) {
        out[e.eq as usize] += T::from_real(gv) * x[e.coord as usize];
    }
}
