//! Where each element's and constraint's values go: scatter maps into the
//! force vector `F` (length `n + 1`) and into the Jacobian arrays, which are
//! laid out like the block iteration matrix (one extra entry at the end).
//! Locked coordinates, and the ground's, point to the extra "sink" entry of
//! either, so the kernels never test whether a slot is free.

use super::kin::Mat6;

/// How a force element's local values (over its slots) are added into `F`
/// and into the stiffness and damping arrays.
pub(crate) trait Scatter {
    /// The element's generalised forces over its slots.
    type Vector;
    /// A derivative over its slots (a stiffness or a damping block); its
    /// `Default` is zero.
    type Matrix: Default;
    /// Adds `q` into `f`.
    fn add_vector(&self, f: &mut [f64], q: &Self::Vector);
    /// Adds `m` into the Jacobian array `vals`.
    fn add_matrix(&self, vals: &mut [f64], m: &Self::Matrix);
    /// Calls `entry(row, column, position)` for every entry of the element's
    /// block between free coordinates (rows and columns are coordinates,
    /// positions those of the Jacobian arrays), for the structural analysis.
    fn for_each_entry(&self, n: u32, entry: impl FnMut(u32, u32, u32));
}

/// Scatter map of a two-body element over `z = (x_a, y_a, phi_a, x_b, y_b, phi_b)`.
#[derive(Debug, Clone)]
pub(crate) struct PairMap {
    /// Index into `F` of each of the 6 slots (the sink `n` when locked).
    pub f: [u32; 6],
    /// Position in the Jacobian arrays of each entry of the 6x6 block.
    pub jac: [u32; 36],
}

impl Scatter for PairMap {
    type Vector = [f64; 6];
    type Matrix = Mat6;

    #[inline]
    fn add_vector(&self, f: &mut [f64], q: &[f64; 6]) {
        for i in 0..6 {
            f[self.f[i] as usize] += q[i];
        }
    }

    #[inline]
    fn add_matrix(&self, vals: &mut [f64], m: &Mat6) {
        add_block(vals, &self.jac, m);
    }

    fn for_each_entry(&self, n: u32, mut entry: impl FnMut(u32, u32, u32)) {
        for i in 0..6 {
            for j in 0..6 {
                if self.f[i] < n && self.f[j] < n {
                    entry(self.f[i], self.f[j], self.jac[i * 6 + j]);
                }
            }
        }
    }
}

/// Scatter map of an element on one free coordinate (to the ground).
#[derive(Debug, Clone)]
pub(crate) struct CoordMap {
    /// The coordinate (its index into `F`).
    pub f: u32,
    /// Position of its diagonal entry in the Jacobian arrays.
    pub jac: u32,
}

impl Scatter for CoordMap {
    type Vector = f64;
    type Matrix = f64;

    #[inline]
    fn add_vector(&self, f: &mut [f64], q: &f64) {
        f[self.f as usize] += q;
    }

    #[inline]
    fn add_matrix(&self, vals: &mut [f64], m: &f64) {
        vals[self.jac as usize] += m;
    }

    fn for_each_entry(&self, _n: u32, mut entry: impl FnMut(u32, u32, u32)) {
        entry(self.f, self.f, self.jac);
    }
}

/// Adds a 6x6 block into `vals` at the positions `pos` (row by row).
#[inline]
pub(crate) fn add_block(vals: &mut [f64], pos: &[u32; 36], m: &Mat6) {
    for i in 0..6 {
        for j in 0..6 {
            vals[pos[i * 6 + j] as usize] += m[i][j];
        }
    }
}

/// Scatter map of a constraint primitive.
#[derive(Debug, Clone)]
pub(crate) struct PrimMap {
    /// First equation index.
    pub eq: u32,
    /// Number of equations (1 or 2).
    pub rows: u8,
    /// Index into `F` of each of the 6 slots.
    pub f: [u32; 6],
    /// Hessian positions (6x6).
    pub h: [u32; 36],
    /// First entry in [`super::Assembly::g_entries`] and how many.
    pub g_start: u32,
    pub g_count: u8,
}

/// One stored entry of `G`: its position in the matrix, the position of its
/// transpose, and which row and slot of the primitive it is.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GEntry {
    pub pos: u32,
    pub pos_t: u32,
    pub eq: u32,
    pub coord: u32,
    pub row: u8,
    pub slot: u8,
}
