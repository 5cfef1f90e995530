//! Planar vector helpers and the per-evaluation body kinematics cache.

use std::ops::{Add, Mul, Neg, Sub};

/// A plane vector.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct V2 {
    pub x: f64,
    pub y: f64,
}

impl V2 {
    pub const fn new(x: f64, y: f64) -> Self {
        Self { x, y }
    }
    pub fn from(a: [f64; 2]) -> Self {
        Self { x: a[0], y: a[1] }
    }
    /// `S v` with `S = [[0,-1],[1,0]]` (rotation by +90 degrees).
    #[inline]
    pub fn perp(self) -> V2 {
        V2 { x: -self.y, y: self.x }
    }
    #[inline]
    pub fn dot(self, o: V2) -> f64 {
        self.x * o.x + self.y * o.y
    }
    /// z component of the cross product.
    #[inline]
    pub fn cross(self, o: V2) -> f64 {
        self.x * o.y - self.y * o.x
    }
    /// Euclidean length (`sqrt`, not `hypot`: lengths and speeds here are
    /// far from overflow, and `hypot` costs several times more).
    #[inline]
    pub fn norm(self) -> f64 {
        self.norm_squared().sqrt()
    }
    /// `x^2 + y^2`.
    #[inline]
    pub fn norm_squared(self) -> f64 {
        self.x * self.x + self.y * self.y
    }
    #[inline]
    pub fn scale(self, s: f64) -> V2 {
        V2 { x: self.x * s, y: self.y * s }
    }
}

impl Add for V2 {
    type Output = V2;
    #[inline]
    fn add(self, o: V2) -> V2 {
        V2 { x: self.x + o.x, y: self.y + o.y }
    }
}

impl Sub for V2 {
    type Output = V2;
    #[inline]
    fn sub(self, o: V2) -> V2 {
        V2 { x: self.x - o.x, y: self.y - o.y }
    }
}

impl Neg for V2 {
    type Output = V2;
    #[inline]
    fn neg(self) -> V2 {
        V2 { x: -self.x, y: -self.y }
    }
}

impl Mul<V2> for f64 {
    type Output = V2;
    #[inline]
    fn mul(self, v: V2) -> V2 {
        v.scale(self)
    }
}

/// A rotation matrix `A(phi) = [[c, -s], [s, c]]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rot {
    pub c: f64,
    pub s: f64,
}

impl Rot {
    pub fn new(phi: f64) -> Self {
        let (s, c) = sin_cos(phi);
        Self { c, s }
    }
    /// `A v`.
    #[inline]
    pub fn apply(self, v: V2) -> V2 {
        V2 { x: self.c * v.x - self.s * v.y, y: self.s * v.x + self.c * v.y }
    }
    /// `A^T v`.
    #[inline]
    pub fn apply_t(self, v: V2) -> V2 {
        V2 { x: self.c * v.x + self.s * v.y, y: -self.s * v.x + self.c * v.y }
    }
}

/// Position, orientation and velocity of one body at one evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BodyKin {
    pub r: V2,
    pub phi: f64,
    pub rot: Rot,
    pub v: V2,
    pub w: f64,
}

impl Default for BodyKin {
    fn default() -> Self {
        Self { r: V2::default(), phi: 0.0, rot: Rot { c: 1.0, s: 0.0 }, v: V2::default(), w: 0.0 }
    }
}

/// Per-body data for loading the kinematics.
#[derive(Debug, Clone)]
pub(crate) struct BodyStatic {
    /// Coordinate of each slot (x, y, phi), `NONE` where locked.
    pub coord: [u32; 3],
    /// The pose as given (the locked slots keep it).
    pub pose0: [f64; 3],
    /// Rotation at `pose0[2]` (used while the angle is not a coordinate).
    pub rot0: Rot,
}

/// A dense 6x6 block over the coordinates (x_a, y_a, phi_a, x_b, y_b, phi_b)
/// of a two-body element; rows are generalised-force components.
pub(crate) type Mat6 = [[f64; 6]; 6];

/// Adds `B^T C B` to `out` for a 2x6 `B` (given by columns) and symmetric 2x2 `C`.
#[inline]
pub(crate) fn add_btcb(out: &mut Mat6, b: &[V2; 6], c: [[f64; 2]; 2]) {
    let mut cb = [V2::default(); 6];
    for (j, col) in b.iter().enumerate() {
        cb[j] = V2::new(c[0][0] * col.x + c[0][1] * col.y, c[1][0] * col.x + c[1][1] * col.y);
    }
    for i in 0..6 {
        for j in 0..6 {
            out[i][j] += b[i].dot(cb[j]);
        }
    }
}

/// Adds `B^T C P` to `out` (rows from `B`, columns from `P`).
#[inline]
pub(crate) fn add_btcp(out: &mut Mat6, b: &[V2; 6], c: [[f64; 2]; 2], p: &[V2; 6]) {
    let mut cp = [V2::default(); 6];
    for (j, col) in p.iter().enumerate() {
        cp[j] = V2::new(c[0][0] * col.x + c[0][1] * col.y, c[1][0] * col.x + c[1][1] * col.y);
    }
    for i in 0..6 {
        for j in 0..6 {
            out[i][j] += b[i].dot(cp[j]);
        }
    }
}

/// Taylor coefficients of `sin(x) / x` in `x^2` (`(-1)^k / (2k+1)!`).
const SIN_COEFFS: [f64; 9] = [
    1.0,
    -0.16666666666666666,
    0.008333333333333333,
    -0.0001984126984126984,
    2.7557319223985893e-06,
    -2.505210838544172e-08,
    1.6059043836821613e-10,
    -7.647163731819816e-13,
    2.8114572543455206e-15,
];

/// Taylor coefficients of `cos(x)` in `x^2` (`(-1)^k / (2k)!`).
const COS_COEFFS: [f64; 10] = [
    1.0,
    -0.5,
    0.041666666666666664,
    -0.001388888888888889,
    2.48015873015873e-05,
    -2.755731922398589e-07,
    2.08767569878681e-09,
    -1.1470745597729725e-11,
    4.779477332387385e-14,
    -1.5619206968586225e-16,
];

/// `(sin x, cos x)`. The angles of a planar mechanism are mostly small, so
/// for `|x| <= pi/4` the Taylor series are summed directly (truncation below
/// 1e-19, a few ulp of rounding; several times cheaper than the C library's
/// `sincos`, the largest single cost of loading the kinematics), and the
/// library is used beyond.
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() > std::f64::consts::FRAC_PI_4 {
        return x.sin_cos();
    }
    let x2 = x * x;
    let s = SIN_COEFFS.iter().rev().fold(0.0, |acc, &c| acc * x2 + c);
    let c = COS_COEFFS.iter().rev().fold(0.0, |acc, &c| acc * x2 + c);
    (x * s, c)
}

#[cfg(test)]
mod tests {
    use super::sin_cos;

    #[test]
    fn series_sin_cos_agrees_with_the_library_to_a_few_ulp() {
        let mut worst = 0.0f64;
        let n = 200_000;
        for i in 0..=n {
            let x = -1.0 + 2.0 * i as f64 / n as f64; // beyond pi/4 on both sides
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        assert!(worst <= 4.0 * f64::EPSILON, "largest difference {worst:e}");
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert_eq!(sin_cos(2.0), 2.0f64.sin_cos());
    }
}
