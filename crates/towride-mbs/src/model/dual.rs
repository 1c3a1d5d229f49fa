//! Forward-mode dual numbers for exact element Jacobians.
//!
//! Every joint and force element is written once, generic over [`Scalar`]. Evaluated with
//! `f64` it gives the residual; with [`Dual`] it gives exact first derivatives; with a dual
//! of duals it gives the second derivatives the Newton matrix needs for terms such as
//! d(B^T lambda)/dq. This keeps the analytic Jacobian of every element correct by
//! construction (and the tests still compare it with finite differences).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// The arithmetic an element needs.
pub trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    fn cst(v: f64) -> Self;
    /// The real (value) part.
    fn re(&self) -> f64;
    fn sqrt(self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn atan2(self, x: Self) -> Self;
    fn exp(self) -> Self;
    fn tanh(self) -> Self;
    /// Applies a scalar function given its value and first two derivatives at `re()`
    /// (tabulated curves); exact to second order, which is all the nesting needs.
    fn chain(self, f: f64, df: f64, d2f: f64) -> Self;
}

impl Scalar for f64 {
    #[inline]
    fn cst(v: f64) -> Self {
        v
    }
    #[inline]
    fn re(&self) -> f64 {
        *self
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline]
    fn sin(self) -> Self {
        f64::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        f64::cos(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
    #[inline]
    fn exp(self) -> Self {
        f64::exp(self)
    }
    #[inline]
    fn tanh(self) -> Self {
        f64::tanh(self)
    }
    #[inline]
    fn chain(self, f: f64, _df: f64, _d2f: f64) -> Self {
        f
    }
}

/// A value with N directional derivatives; the value may itself be a dual.
#[derive(Clone, Copy, Debug)]
pub struct Dual<S: Scalar, const N: usize> {
    pub v: S,
    pub d: [S; N],
}

impl<S: Scalar, const N: usize> Dual<S, N> {
    /// A constant (all derivatives zero).
    #[inline]
    pub fn constant(v: S) -> Self {
        Dual {
            v,
            d: [S::cst(0.0); N],
        }
    }

    /// An independent variable: derivative 1 in direction `i`.
    #[inline]
    pub fn var(v: S, i: usize) -> Self {
        let mut d = [S::cst(0.0); N];
        d[i] = S::cst(1.0);
        Dual { v, d }
    }

    /// Chain rule with f(v) and f'(v) already evaluated in S.
    #[inline]
    fn apply(self, f: S, df: S) -> Self {
        let mut d = self.d;
        for x in d.iter_mut() {
            *x = *x * df;
        }
        Dual { v: f, d }
    }
}

impl<S: Scalar, const N: usize> Add for Dual<S, N> {
    type Output = Self;
    #[inline]
    fn add(mut self, o: Self) -> Self {
        self.v = self.v + o.v;
        for i in 0..N {
            self.d[i] = self.d[i] + o.d[i];
        }
        self
    }
}

impl<S: Scalar, const N: usize> Sub for Dual<S, N> {
    type Output = Self;
    #[inline]
    fn sub(mut self, o: Self) -> Self {
        self.v = self.v - o.v;
        for i in 0..N {
            self.d[i] = self.d[i] - o.d[i];
        }
        self
    }
}

impl<S: Scalar, const N: usize> Mul for Dual<S, N> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let mut d = self.d;
        for i in 0..N {
            d[i] = self.d[i] * o.v + self.v * o.d[i];
        }
        Dual { v: self.v * o.v, d }
    }
}

impl<S: Scalar, const N: usize> Div for Dual<S, N> {
    type Output = Self;
    #[inline]
    fn div(self, o: Self) -> Self {
        let inv = S::cst(1.0) / o.v;
        let q = self.v * inv;
        let mut d = self.d;
        for i in 0..N {
            d[i] = (self.d[i] - q * o.d[i]) * inv;
        }
        Dual { v: q, d }
    }
}

impl<S: Scalar, const N: usize> Neg for Dual<S, N> {
    type Output = Self;
    #[inline]
    fn neg(mut self) -> Self {
        self.v = -self.v;
        for x in self.d.iter_mut() {
            *x = -*x;
        }
        self
    }
}

impl<S: Scalar, const N: usize> Add<f64> for Dual<S, N> {
    type Output = Self;
    #[inline]
    fn add(mut self, o: f64) -> Self {
        self.v = self.v + o;
        self
    }
}

impl<S: Scalar, const N: usize> Sub<f64> for Dual<S, N> {
    type Output = Self;
    #[inline]
    fn sub(mut self, o: f64) -> Self {
        self.v = self.v - o;
        self
    }
}

impl<S: Scalar, const N: usize> Mul<f64> for Dual<S, N> {
    type Output = Self;
    #[inline]
    fn mul(mut self, o: f64) -> Self {
        self.v = self.v * o;
        for x in self.d.iter_mut() {
            *x = *x * o;
        }
        self
    }
}

impl<S: Scalar, const N: usize> Div<f64> for Dual<S, N> {
    type Output = Self;
    #[inline]
    fn div(self, o: f64) -> Self {
        self * (1.0 / o)
    }
}

impl<S: Scalar, const N: usize> Scalar for Dual<S, N> {
    #[inline]
    fn cst(v: f64) -> Self {
        Dual::constant(S::cst(v))
    }
    #[inline]
    fn re(&self) -> f64 {
        self.v.re()
    }
    #[inline]
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.apply(s, S::cst(0.5) / s)
    }
    #[inline]
    fn sin(self) -> Self {
        self.apply(self.v.sin(), self.v.cos())
    }
    #[inline]
    fn cos(self) -> Self {
        self.apply(self.v.cos(), -self.v.sin())
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        // d atan2(y, x) = (x dy - y dx) / (x^2 + y^2)
        let r2 = self.v * self.v + x.v * x.v;
        let mut d = self.d;
        for i in 0..N {
            d[i] = (x.v * self.d[i] - self.v * x.d[i]) / r2;
        }
        Dual {
            v: self.v.atan2(x.v),
            d,
        }
    }
    #[inline]
    fn exp(self) -> Self {
        let e = self.v.exp();
        self.apply(e, e)
    }
    #[inline]
    fn tanh(self) -> Self {
        let t = self.v.tanh();
        self.apply(t, S::cst(1.0) - t * t)
    }
    #[inline]
    fn chain(self, f: f64, df: f64, d2f: f64) -> Self {
        let slope = self.v.chain(df, d2f, 0.0);
        let mut d = self.d;
        for x in d.iter_mut() {
            *x = *x * slope;
        }
        Dual {
            v: self.v.chain(f, df, d2f),
            d,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_of_a_composite_function() {
        // f(x, y) = sin(x) * y / sqrt(x^2 + y^2)
        let f = |x: Dual<f64, 2>, y: Dual<f64, 2>| x.sin() * y / (x * x + y * y).sqrt();
        let (x0, y0) = (0.7, -1.3);
        let r = f(Dual::var(x0, 0), Dual::var(y0, 1));
        let h = 1e-6;
        let fd = |dx: f64, dy: f64| {
            let g = |x: f64, y: f64| x.sin() * y / (x * x + y * y).sqrt();
            (g(x0 + dx, y0 + dy) - g(x0 - dx, y0 - dy)) / (2.0 * h)
        };
        assert!((r.d[0] - fd(h, 0.0)).abs() < 1e-8);
        assert!((r.d[1] - fd(0.0, h)).abs() < 1e-8);
    }

    #[test]
    fn nested_duals_give_second_derivatives() {
        // f = x^2 y^3: d2f/dxdy = 6 x y^2
        type D1 = Dual<f64, 2>;
        type D2 = Dual<D1, 2>;
        let (x0, y0) = (1.5, 0.5);
        let x = D2 {
            v: D1::var(x0, 0),
            d: [D1::cst(1.0), D1::cst(0.0)],
        };
        let y = D2 {
            v: D1::var(y0, 1),
            d: [D1::cst(0.0), D1::cst(1.0)],
        };
        let f = x * x * y * y * y;
        assert!((f.d[0].d[1] - 6.0 * x0 * y0 * y0).abs() < 1e-12);
        assert!((f.d[1].d[0] - 6.0 * x0 * y0 * y0).abs() < 1e-12);
    }
}
