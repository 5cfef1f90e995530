//! The static correction for the modes a run leaves out (residual
//! flexibility; docs/bridge.md, "The static correction").
//!
//! A mode left out is taken as static: under the ground's acceleration
//! `a_g` along x and the joints' forces `f` at their points it sits at
//! `q_i = (-Gamma_i a_g + phi_i^T f) / w_i^2`, so the modes left out move
//! the points by `r a_g + R f` with
//!
//! - `R = F - sum_kept phi phi^T / w^2`, the full model's static
//!   flexibility `F` less the kept modes' (the residual flexibility), and
//! - `r = g + sum_kept phi Gamma_x / w^2`, the full model's static
//!   displacement under a unit ground acceleration `g = -K^-1 M r_x` less
//!   the kept modes' (both from the modes file's `[static]` table).
//!
//! In the coupled run `R` restricted to the joints' points, `R_PP = sum_k
//! v_k v_k^T / kappa_k` (its eigenvectors and eigenvalues `1/kappa_k`),
//! becomes one pseudo-mode per eigenvector: a coordinate `z_k` with the
//! spring `kappa_k`, a light mass (it is static), no damping, the ground's
//! push `-kappa_k v_k^T r_P a_g`, and the shape `v_k` at the joints'
//! points (`kappa_k R_oP v_k` at the others). Statically the pseudo-modes
//! then move the joints' points by exactly `R_PP f + r_P a_g`, the full
//! model's answer. This is the mode-acceleration method's correction (Cornwell,
//! Craig and Johnson 1983, Earthquake Eng. Struct. Dyn. 11:679) carried into
//! the time integration, where the joints' forces are unknowns.

use crate::error::ModelError;

use super::{KeptMode, ModalBridge};

/// One pseudo-mode of the static correction.
#[derive(Debug, Clone, PartialEq)]
pub struct PseudoMode {
    /// Its spring, `1 / eigenvalue of R_PP` \[N/m\] (its coordinate is the
    /// displacement along its unit eigenvector at the joints' points).
    pub stiffness: f64,
    /// Its shape at every point of the modes file [-]: the eigenvector at
    /// the joints' points, `kappa R_oP v` at the others.
    pub shape: Vec<f64>,
    /// The mass the ground's acceleration along x acts on, `-kappa v^T r_P`
    /// \[kg\].
    pub base_mass: f64,
}

/// The static correction of a run: its pseudo-modes and what remains of
/// the ground's static part at the points no joint holds.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StaticCorrection {
    /// The pseudo-modes (none when the kept modes hold all of the joints'
    /// points' flexibility).
    pub pseudo: Vec<PseudoMode>,
    /// At each point of the modes file, the displacement per unit ground
    /// acceleration along x the pseudo-modes do not give \[s^2\]: `r_o`
    /// less their static share (zero at the joints' points; zero for
    /// points across the bridge).
    pub ground: Vec<f64>,
}

/// Below this fraction of the largest static flexibility at the joints'
/// points an eigenvalue of the residual flexibility is taken as zero (the
/// kept modes hold that direction) [-].
const ZERO: f64 = 1e-9;

/// Down to minus this fraction of the largest static flexibility at the
/// joints' points an eigenvalue of the residual flexibility is taken as
/// round-off; below, the `[static]` table does not belong to the modes [-].
const NEGATIVE: f64 = 1e-6;

impl ModalBridge {
    /// The static displacement per unit ground acceleration along x of the
    /// modes left out at each point, `r` \[s^2\], for the `kept` modes of a
    /// run with `period_scale` (none without a `[static]` table or its
    /// `ground_x`).
    pub fn ground_residual(&self, kept: &[KeptMode], period_scale: f64) -> Option<Vec<f64>> {
        let s = self.static_response.as_ref().filter(|s| !s.ground_x.is_empty())?;
        let scale = period_scale * period_scale;
        Some(
            s.ground_x
                .iter()
                .enumerate()
                .map(|(p, g)| {
                    let x = self.points[p].direction == super::Direction::X;
                    let kept_part: f64 =
                        kept.iter().map(|k| k.shape[p] * k.gamma[0] / (k.omega * k.omega)).sum::<f64>();
                    if x {
                        g * scale + kept_part
                    } else {
                        0.0
                    }
                })
                .collect(),
        )
    }

    /// The static correction of a run keeping `kept` (with `period_scale`)
    /// whose joints move with the points `joints` (indices, any order,
    /// repeats allowed). Fails without a `[static]` table with
    /// `flexibility`, or when the table holds less flexibility than the
    /// kept modes (it does not belong to them).
    pub fn static_correction(
        &self,
        kept: &[KeptMode],
        joints: &[usize],
        period_scale: f64,
        file: &str,
    ) -> Result<StaticCorrection, ModelError> {
        let bad = |reason: String| ModelError::Invalid {
            field: "bridge.modal.static_correction".to_string(),
            value: "true".to_string(),
            reason,
        };
        let s = match &self.static_response {
            Some(s) if !s.flexibility.is_empty() => s,
            _ => {
                return Err(bad(format!(
                    "the modes file {file} has no [static] table with flexibility and ground_x (docs/bridge.md, \
                     \"The static correction\")"
                )))
            }
        };
        let n = self.points.len();
        let scale = period_scale * period_scale;
        let residual = |a: usize, b: usize| {
            s.flexibility[a][b] * scale
                - kept.iter().map(|k| k.shape[a] * k.shape[b] / (k.omega * k.omega)).sum::<f64>()
        };
        let r = self.ground_residual(kept, period_scale).unwrap_or_else(|| vec![0.0; n]);
        let mut points: Vec<usize> = joints.to_vec();
        points.sort_unstable();
        points.dedup();
        let largest = points.iter().fold(0.0f64, |m, &p| m.max(s.flexibility[p][p].abs() * scale));
        let rpp: Vec<Vec<f64>> = points.iter().map(|&a| points.iter().map(|&b| residual(a, b)).collect()).collect();
        let (values, vectors) = symmetric_eigen(rpp);
        let mut pseudo = Vec::new();
        for (lambda, v) in values.into_iter().zip(vectors) {
            if lambda < -NEGATIVE * largest {
                let names: Vec<&str> = points.iter().map(|&p| self.points[p].name.as_str()).collect();
                return Err(bad(format!(
                    "at the points {names:?} the kept modes hold more static flexibility than the [static] table \
                     of the modes file {file} ({lambda:.3e} m/N below it): the table does not belong to these modes"
                )));
            }
            if lambda <= ZERO * largest {
                continue;
            }
            let stiffness = 1.0 / lambda;
            let shape: Vec<f64> = (0..n)
                .map(|o| match points.iter().position(|&p| p == o) {
                    Some(i) => v[i],
                    None => stiffness * points.iter().zip(&v).map(|(&p, vp)| residual(o, p) * vp).sum::<f64>(),
                })
                .collect();
            let base_mass = -stiffness * points.iter().zip(&v).map(|(&p, vp)| vp * r[p]).sum::<f64>();
            pseudo.push(PseudoMode { stiffness, shape, base_mass });
        }
        let ground = (0..n)
            .map(|o| {
                if points.contains(&o) || self.points[o].direction != super::Direction::X {
                    return 0.0;
                }
                // (the pseudo-modes' static share: shape times -base_mass / kappa)
                r[o] - pseudo.iter().map(|m| m.shape[o] * -m.base_mass / m.stiffness).sum::<f64>()
            })
            .collect();
        Ok(StaticCorrection { pseudo, ground })
    }
}

/// The eigenvalues and unit eigenvectors of a small symmetric matrix, by
/// cyclic Jacobi rotations (Golub and Van Loan, Matrix Computations, 4th
/// ed., algorithm 8.5.3), in order of decreasing eigenvalue.
fn symmetric_eigen(mut a: Vec<Vec<f64>>) -> (Vec<f64>, Vec<Vec<f64>>) {
    let n = a.len();
    // (columns of v are the eigenvectors)
    let mut v: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect()).collect();
    let norm: f64 = a.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    for _sweep in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum::<f64>()
            .sqrt();
        if off <= 1e-15 * norm {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                if a[p][q] == 0.0 {
                    continue;
                }
                let tau = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = tau.signum() / (tau.abs() + (1.0 + tau * tau).sqrt());
                let t = if tau == 0.0 { 1.0 } else { t };
                let c = 1.0 / (1.0 + t * t).sqrt();
                let s = t * c;
                // A <- J^T A J with the rotation J in the plane (p, q)
                for row in a.iter_mut() {
                    let (akp, akq) = (row[p], row[q]);
                    row[p] = c * akp - s * akq;
                    row[q] = s * akp + c * akq;
                }
                let (row_p, row_q) = (a[p].clone(), a[q].clone());
                for (k, (apk, aqk)) in row_p.into_iter().zip(row_q).enumerate() {
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let values = order.iter().map(|&i| a[i][i]).collect();
    let vectors = order.iter().map(|&i| v.iter().map(|row| row[i]).collect()).collect();
    (values, vectors)
}

#[cfg(test)]
mod tests {
    use super::symmetric_eigen;

    /// A 3 x 3 matrix with known eigenvalues (1, 2, 4) and vectors: each
    /// pair comes back with `A v = lambda v` and unit, orthogonal vectors.
    #[test]
    fn jacobi_finds_the_eigenpairs_of_a_symmetric_matrix() {
        // A = Q diag(4, 2, 1) Q^T with Q a rotation
        let (c, s) = (0.6f64, 0.8f64);
        let q = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
        let d = [4.0, 2.0, 1.0];
        let a: Vec<Vec<f64>> =
            (0..3).map(|i| (0..3).map(|j| (0..3).map(|k| q[i][k] * d[k] * q[j][k]).sum()).collect()).collect();
        let (values, vectors) = symmetric_eigen(a.clone());
        for (l, want) in values.iter().zip(d) {
            assert!((l - want).abs() < 1e-14, "{values:?}");
        }
        for (l, v) in values.iter().zip(&vectors) {
            for i in 0..3 {
                let av: f64 = (0..3).map(|j| a[i][j] * v[j]).sum();
                assert!((av - l * v[i]).abs() < 1e-14);
            }
            assert!((v.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-14);
        }
        let dot: f64 = vectors[0].iter().zip(&vectors[1]).map(|(a, b)| a * b).sum();
        assert!(dot.abs() < 1e-14);
    }
}
