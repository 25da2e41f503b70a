//! The [`Field`] trait: write an algorithm once, run it exactly or in `f64`.
//!
//! `BigRational` is not `Copy`, so every operation takes references and returns
//! a new value. Implemented for [`Rational`] (exact), [`Interval`] (certified
//! `f64`) and plain `f64` (fast, uncertified: use only where no sign is decided).

use super::{interval::Interval, rational::rational_sign, Rational, Sign};
use num_bigint::BigInt;
use num_traits::{One, Zero};

/// Field operations, sign and conversion for a scalar type.
pub trait Field: Clone + std::fmt::Debug + Send + Sync {
    /// The additive identity.
    fn zero() -> Self;
    /// The multiplicative identity.
    fn one() -> Self;
    /// The exact value `n / d` (`d ≠ 0`), or the tightest enclosure the type has.
    fn from_ratio(n: i64, d: i64) -> Self;
    /// The rational `r`, exactly or enclosed.
    fn from_rational(r: &Rational) -> Self;
    /// `self + o`.
    fn add(&self, o: &Self) -> Self;
    /// `self − o`.
    fn sub(&self, o: &Self) -> Self;
    /// `self · o`.
    fn mul(&self, o: &Self) -> Self;
    /// Division; the caller guarantees a nonzero divisor in exact types.
    fn div(&self, o: &Self) -> Self;
    /// `−self`.
    fn neg(&self) -> Self;
    /// The sign: exact types never say `Uncertain`.
    fn sign(&self) -> Sign;
    /// A nearby `f64` (the nearest for exact types, the midpoint for intervals).
    fn approx(&self) -> f64;
    /// True when the value is exactly zero.
    fn is_exact_zero(&self) -> bool {
        self.sign() == Sign::Zero
    }
    /// `self · n` for a small integer `n`.
    fn mul_int(&self, n: i64) -> Self {
        self.mul(&Self::from_ratio(n, 1))
    }
    /// De Casteljau subdivision of one line of Bernstein coefficients at `t`: the pieces on
    /// `[0, t]` and `[t, 1]`. A type may do it faster than the generic recurrence.
    fn split_line(line: &[Self], t: &Self) -> (Vec<Self>, Vec<Self>) {
        crate::bernstein::poly::de_casteljau_split(line, t)
    }
    /// The value of one line of Bernstein coefficients at `t` (de Casteljau).
    fn eval_line(line: &[Self], t: &Self) -> Self {
        crate::bernstein::poly::de_casteljau_eval(line, t)
    }
    /// The linear combination `Σ_j w_j v_j` (the shorter of `weights` and `values` counts). A type
    /// may do it faster than one rounding or reduction per operation.
    fn dot<'v>(weights: &[Self], values: impl IntoIterator<Item = &'v Self>) -> Self
    where
        Self: 'v,
    {
        weights
            .iter()
            .zip(values)
            .fold(Self::zero(), |s, (w, v)| s.add(&w.mul(v)))
    }
}

impl Field for Rational {
    fn zero() -> Self {
        Zero::zero()
    }
    fn one() -> Self {
        One::one()
    }
    fn from_ratio(n: i64, d: i64) -> Self {
        Rational::new(BigInt::from(n), BigInt::from(d))
    }
    fn from_rational(r: &Rational) -> Self {
        r.clone()
    }
    // Dyadic values (power-of-two denominators: every f64, every dyadic split) are added,
    // subtracted and multiplied without a gcd; others through `num-rational`.
    // Values whose parts fit in `i64` go through `i128` with a machine-word gcd.
    fn add(&self, o: &Self) -> Self {
        super::rational::dyadic_add(self, o, false)
            .or_else(|| super::rational::small_add(self, o, false))
            .unwrap_or_else(|| self + o)
    }
    fn sub(&self, o: &Self) -> Self {
        super::rational::dyadic_add(self, o, true)
            .or_else(|| super::rational::small_add(self, o, true))
            .unwrap_or_else(|| self - o)
    }
    fn mul(&self, o: &Self) -> Self {
        super::rational::dyadic_mul(self, o)
            .or_else(|| super::rational::small_mul(self, o, false))
            .unwrap_or_else(|| self * o)
    }
    fn div(&self, o: &Self) -> Self {
        super::rational::small_mul(self, o, true).unwrap_or_else(|| self / o)
    }
    fn neg(&self) -> Self {
        -self
    }
    fn sign(&self) -> Sign {
        rational_sign(self)
    }
    fn approx(&self) -> f64 {
        super::rational_to_f64(self)
    }
    fn mul_int(&self, n: i64) -> Self {
        Rational::new(self.numer() * BigInt::from(n), self.denom().clone())
    }
    fn split_line(line: &[Self], t: &Self) -> (Vec<Self>, Vec<Self>) {
        super::rational::dyadic_split_line(line, t)
            .unwrap_or_else(|| super::rational::common_split_line(line, t))
    }
    fn eval_line(line: &[Self], t: &Self) -> Self {
        match super::rational::dyadic_split_line(line, t) {
            Some((mut left, _)) => left.pop().expect("a line has a coefficient"),
            None => super::rational::common_eval_line(line, t),
        }
    }
    fn dot<'v>(weights: &[Self], values: impl IntoIterator<Item = &'v Self>) -> Self {
        super::rational::common_dot(weights, values)
    }
}

impl Field for Interval {
    fn zero() -> Self {
        Interval::point(0.0)
    }
    fn one() -> Self {
        Interval::point(1.0)
    }
    fn from_ratio(n: i64, d: i64) -> Self {
        Interval::from_ratio(n, d)
    }
    fn from_rational(r: &Rational) -> Self {
        Interval::from_rational(r)
    }
    fn add(&self, o: &Self) -> Self {
        *self + *o
    }
    fn sub(&self, o: &Self) -> Self {
        *self - *o
    }
    fn mul(&self, o: &Self) -> Self {
        *self * *o
    }
    fn div(&self, o: &Self) -> Self {
        *self / *o
    }
    fn neg(&self) -> Self {
        -*self
    }
    fn sign(&self) -> Sign {
        Interval::sign(self)
    }
    fn approx(&self) -> f64 {
        self.mid()
    }
    /// At `t = ½` each de Casteljau step is a midpoint ([`Interval::midpoint_of`]): one
    /// outward-rounded addition instead of two interval products and a sum.
    /// Elsewhere, at a point `t` whose complement is exact, each step is a non-negative
    /// blend ([`Interval::blend`]); other `t` take the generic recurrence.
    fn split_line(line: &[Self], t: &Self) -> (Vec<Self>, Vec<Self>) {
        match t.exact_weights() {
            _ if t.is_half() => split_with(line, Interval::midpoint_of),
            Some((s, w)) => split_with(line, |a, b| Interval::blend(a, b, s, w)),
            None => crate::bernstein::poly::de_casteljau_split(line, t),
        }
    }
    fn eval_line(line: &[Self], t: &Self) -> Self {
        match t.exact_weights() {
            _ if t.is_half() => eval_with(line, Interval::midpoint_of),
            Some((s, w)) => eval_with(line, |a, b| Interval::blend(a, b, s, w)),
            None => crate::bernstein::poly::de_casteljau_eval(line, t),
        }
    }
}

/// De Casteljau's subdivision of an interval line with the step `(a, b) ↦ (1 − t)·a + t·b`
/// (each monomorphised, so the step inlines).
fn split_with(line: &[Interval], step: impl Fn(Interval, Interval) -> Interval) -> SplitLine {
    let n = line.len();
    let mut work = line.to_vec();
    let mut left = Vec::with_capacity(n);
    let mut right = vec![Interval::point(0.0); n];
    left.push(work[0]);
    right[n - 1] = work[n - 1];
    for r in 1..n {
        for i in 0..n - r {
            work[i] = step(work[i], work[i + 1]);
        }
        left.push(work[0]);
        right[n - 1 - r] = work[n - 1 - r];
    }
    (left, right)
}

/// The pieces of a split line on `[0, t]` and `[t, 1]`.
type SplitLine = (Vec<Interval>, Vec<Interval>);

/// De Casteljau's value of an interval line with the step of [`split_with`].
fn eval_with(line: &[Interval], step: impl Fn(Interval, Interval) -> Interval) -> Interval {
    let mut work = line.to_vec();
    for r in 1..work.len() {
        for i in 0..work.len() - r {
            work[i] = step(work[i], work[i + 1]);
        }
    }
    work[0]
}

/// Plain `f64`: fast and uncertified. Its `sign` is the sign of the rounded value,
/// so it must not be used for certified decisions.
impl Field for f64 {
    fn zero() -> Self {
        0.0
    }
    fn one() -> Self {
        1.0
    }
    fn from_ratio(n: i64, d: i64) -> Self {
        n as f64 / d as f64
    }
    fn from_rational(r: &Rational) -> Self {
        super::rational_to_f64(r)
    }
    fn add(&self, o: &Self) -> Self {
        self + o
    }
    fn sub(&self, o: &Self) -> Self {
        self - o
    }
    fn mul(&self, o: &Self) -> Self {
        self * o
    }
    fn div(&self, o: &Self) -> Self {
        self / o
    }
    fn neg(&self) -> Self {
        -self
    }
    fn sign(&self) -> Sign {
        if *self > 0.0 {
            Sign::Positive
        } else if *self < 0.0 {
            Sign::Negative
        } else if *self == 0.0 {
            Sign::Zero
        } else {
            Sign::Uncertain
        }
    }
    fn approx(&self) -> f64 {
        *self
    }
}
