//! Linear constraints over any number of coordinates ([`crate::Linear`]):
//! `g = sum_k c_k (q_k - q_k0)`, with constant gradient rows, no Hessian
//! and no time dependence. Their terms can span many bodies (a point of a
//! modal structure and every mode), so they are kept apart from the
//! two-body primitives of `constraints`, and each evaluation below is the
//! counterpart of one over the primitives.

use super::kin::BodyKin;

/// One linear equation.
#[derive(Debug, Clone)]
pub(crate) struct LinearK {
    /// Its equation index.
    pub eq: u32,
    /// `(body, slot, coordinate, coefficient c_k)` of each term.
    pub terms: Vec<(u32, u8, u32, f64)>,
    /// `sum_k c_k q_k0` [m or rad].
    pub offset: f64,
    /// Its first entry in [`super::Assembly::g_entries`] (one per term, in
    /// the order of the terms).
    pub g_start: u32,
}

impl LinearK {
    /// `g` at the kinematics `kin` [m or rad].
    #[inline]
    pub fn value(&self, kin: &[BodyKin]) -> f64 {
        let mut s = 0.0;
        for &(b, slot, _, c) in &self.terms {
            let k = &kin[b as usize];
            let q = match slot {
                0 => k.r.x,
                1 => k.r.y,
                _ => k.phi,
            };
            s += c * q;
        }
        s - self.offset
    }

    /// Writes `g`, `G q'` and, with multipliers, subtracts `G^T lambda`
    /// from `f` (`vx` is `q'` with a zero sink entry).
    #[inline]
    pub fn apply(&self, kin: &[BodyKin], vx: &[f64], f: &mut [f64], g: &mut [f64], w: &mut [f64], lam: Option<&[f64]>) {
        let e = self.eq as usize;
        g[e] = self.value(kin);
        w[e] = self.terms.iter().map(|&(_, _, c, k)| k * vx[c as usize]).sum();
        if let Some(l) = lam.map(|lam| lam[e]).filter(|&l| l != 0.0) {
            for &(_, _, c, k) in &self.terms {
                f[c as usize] -= k * l;
            }
        }
    }

    /// Stores its gradient entries (the coefficients) into `g`.
    #[inline]
    pub fn store_gradient(&self, g: &mut [f64]) {
        let start = self.g_start as usize;
        for (i, &(_, _, _, k)) in self.terms.iter().enumerate() {
            g[start + i] = k;
        }
    }
}
