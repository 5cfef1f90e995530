//! Finite-difference Jacobians with Curtis-Powell-Reid column colouring.
//!
//! Columns of `dF/dq` (and `dF/dv`, `dg/dq`) that share no row are
//! perturbed together, so a Jacobian costs two residual evaluations per
//! colour and variable (central differences) instead of two per column. This
//! is how the source paper computed its Jacobian; here it verifies the
//! analytic derivatives and can replace them ([`crate::JacobianMode`]). The
//! colour groups can be evaluated on the rayon pool.
//!
//! A. R. Curtis, M. J. D. Powell and J. K. Reid, "On the estimation of sparse
//! Jacobian matrices", IMA J. Appl. Math. 13 (1974) 117-119.

use rayon::prelude::*;

use crate::assembly::{Assembly, JacobianValues};

/// Column groups of a Jacobian pattern.
#[derive(Debug, Clone)]
pub struct Colouring {
    /// Columns of each colour.
    groups: Vec<Vec<u32>>,
    /// For each column: (row coordinate, position in K/D).
    rows: Vec<Vec<(u32, u32)>>,
    /// For each column: (equation, index into the G values).
    grad: Vec<Vec<(u32, u32)>>,
    /// Structural non-zeros of `dF/dq` (K pattern).
    nnz: usize,
}

impl Colouring {
    /// Greedy CPR colouring of the pattern of `asm` (largest column first).
    pub fn new(asm: &Assembly) -> Self {
        let (rows, grad) = pattern(asm);
        let n = rows.len();
        // columns of each row (coordinates and equations)
        let mut row_cols: Vec<Vec<u32>> = vec![Vec::new(); n + asm.equations()];
        for (c, r) in rows.iter().enumerate() {
            for &(i, _) in r {
                row_cols[i as usize].push(c as u32);
            }
        }
        for (c, r) in grad.iter().enumerate() {
            for &(e, _) in r {
                row_cols[n + e as usize].push(c as u32);
            }
        }
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by_key(|&c| std::cmp::Reverse(rows[c].len() + grad[c].len()));
        let mut colour = vec![u32::MAX; n];
        let mut used = Vec::new();
        for &c in &order {
            used.clear();
            for &(i, _) in &rows[c] {
                used.extend(row_cols[i as usize].iter().map(|&o| colour[o as usize]));
            }
            for &(e, _) in &grad[c] {
                used.extend(row_cols[n + e as usize].iter().map(|&o| colour[o as usize]));
            }
            used.sort_unstable();
            used.dedup();
            let mut k = 0u32;
            for &u in &used {
                if u == k {
                    k += 1;
                } else if u > k {
                    break;
                }
            }
            colour[c] = k;
        }
        let ncol = colour.iter().map(|&k| k as usize + 1).max().unwrap_or(0);
        let mut groups = vec![Vec::new(); ncol];
        for (c, &k) in colour.iter().enumerate() {
            groups[k as usize].push(c as u32);
        }
        let nnz = rows.iter().map(Vec::len).sum();
        Self { groups, rows, grad, nnz }
    }

    /// One colour per column (dense finite differences).
    pub fn dense(asm: &Assembly) -> Self {
        let (rows, grad) = pattern(asm);
        let groups = (0..rows.len() as u32).map(|c| vec![c]).collect();
        let nnz = rows.iter().map(Vec::len).sum();
        Self { groups, rows, grad, nnz }
    }

    /// Number of colours.
    pub fn colours(&self) -> usize {
        self.groups.len()
    }

    /// Structural non-zeros of `dF/dq`.
    pub fn nnz(&self) -> usize {
        self.nnz
    }
}

/// Rows (with K/D positions) and equations (with G indices) of each column.
type ColumnPattern = (Vec<Vec<(u32, u32)>>, Vec<Vec<(u32, u32)>>);

fn pattern(asm: &Assembly) -> ColumnPattern {
    let n = asm.coordinates();
    let sink = asm.layout.sink();
    let mut rows: Vec<Vec<(u32, u32)>> = vec![Vec::new(); n];
    for (row, col, p) in asm.element_entries() {
        rows[col as usize].push((row, p));
    }
    let prims = &asm.prims;
    let maps = prims.points.iter().map(|x| &x.1).chain(prims.lines.iter().map(|x| &x.1));
    for m in maps.chain(prims.angles.iter().map(|x| &x.1)).chain(prims.drivers.iter().map(|x| &x.1)) {
        for i in 0..6 {
            for j in 0..6 {
                let p = m.h[i * 6 + j];
                if m.f[i] < n as u32 && m.f[j] < n as u32 && p != sink {
                    rows[m.f[j] as usize].push((m.f[i], p));
                }
            }
        }
    }
    for (c, &p) in asm.mass_pos.iter().enumerate() {
        rows[c].push((c as u32, p));
    }
    for r in &mut rows {
        r.sort_unstable();
        r.dedup();
    }
    let mut grad: Vec<Vec<(u32, u32)>> = vec![Vec::new(); n];
    for (i, e) in asm.g_entries.iter().enumerate() {
        grad[e.coord as usize].push((e.eq, i as u32));
    }
    (rows, grad)
}

/// Differences of one colour group: (column, K values, D values, G values).
struct GroupResult {
    k: Vec<f64>,
    d: Vec<f64>,
    g: Vec<f64>,
}

fn eval_group(
    asm: &Assembly,
    col: &Colouring,
    group: &[u32],
    state: (f64, &[f64], &[f64], &[f64]),
    modes: Option<&crate::assembly::Workspace>,
) -> GroupResult {
    let (t, q, v, lam) = state;
    let mut ws = asm.workspace();
    if let Some(m) = modes {
        ws.copy_contacts(m);
    }
    let mut qp = q.to_vec();
    let mut vp = v.to_vec();
    // Central differences: truncation ~ h^2, round-off ~ eps |F| / h; these
    // steps balance the two for forces up to ~1e4 times the derivatives.
    let hq: Vec<f64> = group.iter().map(|&c| 1e-5 * q[c as usize].abs().max(0.1)).collect();
    let hv: Vec<f64> = group.iter().map(|&c| 1e-5 * v[c as usize].abs().max(1e-2)).collect();
    let mut out = GroupResult { k: Vec::new(), d: Vec::new(), g: Vec::new() };
    // positions
    let mut eval_q = |sign: f64, ws: &mut crate::assembly::Workspace| -> (Vec<f64>, Vec<f64>) {
        for (i, &c) in group.iter().enumerate() {
            qp[c as usize] = q[c as usize] + sign * hq[i];
        }
        asm.residual(ws, t, &qp, v, lam);
        (ws.forces().to_vec(), ws.constraints().to_vec())
    };
    let (fp, gp) = eval_q(1.0, &mut ws);
    let (fm, gm) = eval_q(-1.0, &mut ws);
    for (i, &c) in group.iter().enumerate() {
        for &(r, _) in &col.rows[c as usize] {
            out.k.push(-(fp[r as usize] - fm[r as usize]) / (2.0 * hq[i]));
        }
        for &(e, _) in &col.grad[c as usize] {
            out.g.push((gp[e as usize] - gm[e as usize]) / (2.0 * hq[i]));
        }
    }
    // velocities
    let mut eval_v = |sign: f64, ws: &mut crate::assembly::Workspace| -> Vec<f64> {
        for (i, &c) in group.iter().enumerate() {
            vp[c as usize] = v[c as usize] + sign * hv[i];
        }
        asm.residual(ws, t, q, &vp, lam);
        ws.forces().to_vec()
    };
    let fp = eval_v(1.0, &mut ws);
    let fm = eval_v(-1.0, &mut ws);
    for (i, &c) in group.iter().enumerate() {
        for &(r, _) in &col.rows[c as usize] {
            out.d.push(-(fp[r as usize] - fm[r as usize]) / (2.0 * hv[i]));
        }
    }
    out
}

/// Finite-difference Jacobian with a given colouring; returns the number of
/// residual evaluations. The mass entries of `K` are left at zero (the mass
/// enters the iteration matrix separately). The contacts' modes are those
/// of `modes` (all open without it).
pub fn jacobian_with(
    asm: &Assembly,
    colouring: &Colouring,
    state: (f64, &[f64], &[f64], &[f64]),
    jac: &mut JacobianValues,
    parallel: bool,
    modes: Option<&crate::assembly::Workspace>,
) -> usize {
    let results: Vec<GroupResult> = if parallel {
        colouring.groups.par_iter().map(|g| eval_group(asm, colouring, g, state, modes)).collect()
    } else {
        colouring.groups.iter().map(|g| eval_group(asm, colouring, g, state, modes)).collect()
    };
    jac.k.iter_mut().for_each(|x| *x = 0.0);
    jac.d.iter_mut().for_each(|x| *x = 0.0);
    jac.g.iter_mut().for_each(|x| *x = 0.0);
    for (group, res) in colouring.groups.iter().zip(&results) {
        let (mut ik, mut ig) = (0, 0);
        for &c in group {
            for &(_, pos) in &colouring.rows[c as usize] {
                jac.k[pos as usize] = res.k[ik];
                jac.d[pos as usize] = res.d[ik];
                ik += 1;
            }
            for &(_, gi) in &colouring.grad[c as usize] {
                jac.g[gi as usize] = res.g[ig];
                ig += 1;
            }
        }
    }
    4 * colouring.groups.len()
}

/// Coloured finite-difference Jacobian (builds the colouring).
pub fn coloured_jacobian(
    asm: &Assembly,
    t: f64,
    q: &[f64],
    v: &[f64],
    lam: &[f64],
    jac: &mut JacobianValues,
    parallel: bool,
) -> usize {
    let colouring = Colouring::new(asm);
    jacobian_with(asm, &colouring, (t, q, v, lam), jac, parallel, None)
}
