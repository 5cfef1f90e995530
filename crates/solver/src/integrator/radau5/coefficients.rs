//! The coefficients of Radau IIA (s = 3) and RADAU5's constants (Hairer and
//! Wanner, Section IV.8, and the RADAU5 code).

pub(super) const SQ6: f64 = 2.449_489_742_783_178;
/// Stage abscissae `c_i`.
pub const C: [f64; 3] = [0.155_051_025_721_682_2, 0.644_948_974_278_317_8, 1.0];
pub(super) const C1M1: f64 = C[0] - 1.0;
pub(super) const C2M1: f64 = C[1] - 1.0;
pub(super) const C1MC2: f64 = C[0] - C[1];
/// Butcher matrix of Radau IIA (s = 3).
pub const A: [[f64; 3]; 3] = [
    [0.196_815_477_223_660_43, -0.065_535_425_850_198_39, 0.023_770_974_348_220_15],
    [0.394_424_314_739_087_3, 0.292_073_411_665_228_46, -0.041_548_752_125_997_93],
    [0.376_403_062_700_467_27, 0.512_485_826_188_421_6, 1.0 / 9.0],
];
/// `T` with `T^-1 A^-1 T = [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]]`.
pub const T: [[f64; 3]; 3] = [
    [9.123_239_487_089_295e-2, -0.141_255_295_020_954_2, -3.002_919_410_514_742_4e-2],
    [0.241_717_932_707_107, 0.204_129_352_293_799_93, 0.382_942_112_757_261_9],
    [0.966_048_182_615_093, 1.0, 0.0],
];
/// `T^-1`.
pub const TI: [[f64; 3]; 3] = [
    [4.325_579_890_063_155, 0.339_199_251_815_809_87, 0.541_770_539_935_874_9],
    [-4.178_718_591_551_905, -0.327_682_820_761_062_4, 0.476_623_554_500_550_45],
    [-0.502_872_634_945_786_9, 2.571_926_949_855_605, -0.596_039_204_828_224_9],
];
/// Real eigenvalue of `A^-1`.
pub const GAMMA: f64 = 3.637_834_252_744_496;
/// Real part of the complex eigenvalues of `A^-1`.
pub const ALPHA: f64 = 2.681_082_873_627_752;
/// Imaginary part of the complex eigenvalues of `A^-1`.
pub const BETA: f64 = 3.050_430_199_247_410_6;
/// Coefficients of the embedded error estimate.
pub(super) const DD: [f64; 3] = [-(13.0 + 7.0 * SQ6) / 3.0, (-13.0 + 7.0 * SQ6) / 3.0, -1.0 / 3.0];

pub(super) const UROUND: f64 = f64::EPSILON;
pub(super) const SAFE: f64 = 0.9;
pub(super) const FACL: f64 = 5.0;
pub(super) const FACR: f64 = 0.125;
/// Keep h (and the factorisation) while `QUOT1 <= h_new / h <= QUOT2`.
/// RADAU5 uses 1.0; 0.8 halves the factorisations of the expansion-joint
/// runs (medium model: 1.9k -> 0.8k) and takes 7 % fewer steps.
pub(super) const QUOT1: f64 = 0.8;
pub(super) const QUOT2: f64 = 1.2;
/// Relative difference of step sizes below which a factorisation is reused.
pub(super) const FACT_RTOL: f64 = 1e-9;
/// Largest first step after a contact changes mode [s]: impacts of stiff
/// contacts last milliseconds; the error control takes it from there.
pub(super) const CONTACT_STEP: f64 = 1e-4;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transformation_diagonalises_the_inverse_butcher_matrix() {
        // A^-1 by cofactors: (A^-1)_ij = C_ji / det A
        let a = A;
        let minor = |r: usize, c: usize| {
            let rows: Vec<usize> = (0..3).filter(|&x| x != r).collect();
            let cols: Vec<usize> = (0..3).filter(|&x| x != c).collect();
            a[rows[0]][cols[0]] * a[rows[1]][cols[1]] - a[rows[0]][cols[1]] * a[rows[1]][cols[0]]
        };
        let det = (0..3).map(|c| a[0][c] * minor(0, c) * if c % 2 == 0 { 1.0 } else { -1.0 }).sum::<f64>();
        let mut ai = [[0.0; 3]; 3];
        for (i, row) in ai.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                let sign = if (i + j) % 2 == 0 { 1.0 } else { -1.0 };
                *x = sign * minor(j, i) / det;
            }
        }
        let mut prod = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                for k in 0..3 {
                    for l in 0..3 {
                        prod[i][j] += TI[i][k] * ai[k][l] * T[l][j];
                    }
                }
            }
        }
        let expect = [[GAMMA, 0.0, 0.0], [0.0, ALPHA, -BETA], [0.0, BETA, ALPHA]];
        for i in 0..3 {
            for j in 0..3 {
                assert!((prod[i][j] - expect[i][j]).abs() < 1e-12, "{i}{j}: {}", prod[i][j]);
            }
        }
        // collocation: row sums of A are the abscissae
        for i in 0..3 {
            assert!((A[i].iter().sum::<f64>() - C[i]).abs() < 1e-15);
        }
    }
}
