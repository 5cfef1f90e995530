//! The two scalar types of the iteration matrices: real (the real Radau
//! system) and complex (the complex-conjugate pair of Radau systems).

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

pub use num_complex::Complex64;

/// Arithmetic needed by the block elimination.
pub trait Scalar:
    Copy
    + Debug
    + Default
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
{
    /// Zero.
    const ZERO: Self;
    /// One.
    const ONE: Self;
    /// Whether small matrix-vector products accumulate column by column
    /// ([`super::small::gemv_sub_fixed`]; the faster form, measured).
    const BY_COLUMNS: bool;
    /// A cheap magnitude used for pivoting (|re| + |im|).
    fn magnitude(self) -> f64;
    /// Real value as this scalar.
    fn from_real(x: f64) -> Self;
    /// `self * x` for a real `x` (for a complex scalar two real products,
    /// not a complex one).
    fn mul_real(self, x: f64) -> Self;
    /// Whether the value is finite.
    fn finite(self) -> bool;
}

impl Scalar for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const BY_COLUMNS: bool = true;
    #[inline]
    fn magnitude(self) -> f64 {
        self.abs()
    }
    #[inline]
    fn from_real(x: f64) -> Self {
        x
    }
    #[inline]
    fn mul_real(self, x: f64) -> Self {
        self * x
    }
    #[inline]
    fn finite(self) -> bool {
        self.is_finite()
    }
}

impl Scalar for Complex64 {
    const ZERO: Self = Complex64::new(0.0, 0.0);
    const ONE: Self = Complex64::new(1.0, 0.0);
    const BY_COLUMNS: bool = false;
    #[inline]
    fn magnitude(self) -> f64 {
        self.re.abs() + self.im.abs()
    }
    #[inline]
    fn from_real(x: f64) -> Self {
        Complex64::new(x, 0.0)
    }
    #[inline]
    fn mul_real(self, x: f64) -> Self {
        Complex64::new(self.re * x, self.im * x)
    }
    #[inline]
    fn finite(self) -> bool {
        self.re.is_finite() && self.im.is_finite()
    }
}
