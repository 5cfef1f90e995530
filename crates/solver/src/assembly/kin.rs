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
    #[inline]
    pub fn norm(self) -> f64 {
        self.x.hypot(self.y)
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
        let (s, c) = phi.sin_cos();
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
