//! The fast path: `f64` coefficients with one rigorous forward error bound.
//!
//! Invariant: every stored coefficient `c_k` satisfies `|c_k − e_k| ≤ err`, where `e_k`
//! is the exact coefficient of the polynomial this value stands for. Signs are certified
//! when `|c_k| > err`. Rounding is the default round-to-nearest; bounds are computed with
//! slack and rounded up with `next_up` (no change of FPU rounding mode).
//!
//! Subdivision at ½: `fl((a+b)·½)` errs from `(a+b)/2` by at most `u·|a+b|/2` plus half the
//! smallest subnormal, so one de Casteljau pass of degree `d` adds at most
//! `d·(u·M·(1+u)^d + 2⁻¹⁰⁷⁴)` with `M` the largest coefficient magnitude (convex combinations
//! do not grow). We add `2·d·u·M + d·2⁻¹⁰⁷³`, a safe over-estimate.

use super::poly::{coefficient_count, strides, Bernstein};
use super::{binomial_f64, BernsteinError, MAX_EXACT_BINOMIAL_F64};
use crate::num::{gamma, Field, Rational, Sign, UNIT_ROUNDOFF};

/// Largest degree per axis the fast path handles (stack line buffers).
pub(crate) const MAX_FAST_DEGREE: usize = 63;

/// Smallest positive subnormal.
const ETA: f64 = 5e-324;

/// An `f64` tensor Bernstein polynomial with a certified error bound.
#[derive(Clone, Debug, PartialEq)]
pub struct FastBernstein {
    degrees: Vec<usize>,
    coeffs: Vec<f64>,
    err: f64,
}

impl FastBernstein {
    /// Exact `f64` coefficients (error bound 0). Non-finite values are an error.
    pub fn from_exact_f64(degrees: Vec<usize>, coeffs: Vec<f64>) -> Result<Self, BernsteinError> {
        Self::with_error(degrees, coeffs, 0.0)
    }

    /// Coefficients known to within `err` of the exact ones.
    pub fn with_error(
        degrees: Vec<usize>,
        coeffs: Vec<f64>,
        err: f64,
    ) -> Result<Self, BernsteinError> {
        let expected = coefficient_count(&degrees);
        if coeffs.len() != expected {
            return Err(BernsteinError::CoefficientCount {
                expected,
                found: coeffs.len(),
            });
        }
        if let Some(&d) = degrees.iter().find(|&&d| d > MAX_FAST_DEGREE) {
            return Err(BernsteinError::DegreeTooHigh {
                degree: d,
                limit: MAX_FAST_DEGREE,
            });
        }
        if let Some(index) = coeffs.iter().position(|c| !c.is_finite()) {
            return Err(BernsteinError::NonFinite { index });
        }
        if err.is_nan() || err < 0.0 {
            return Err(BernsteinError::NonFinite { index: usize::MAX });
        }
        Ok(FastBernstein {
            degrees,
            coeffs,
            err,
        })
    }

    /// Rounds an exact polynomial to nearest; the bound covers the rounding.
    pub fn from_rational(p: &Bernstein<Rational>) -> Result<Self, BernsteinError> {
        let coeffs: Vec<f64> = p.coeffs().iter().map(|c| c.approx()).collect();
        // Round-to-nearest errs by at most u·|c| (normal range) or half a subnormal step.
        let m = coeffs.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        let err = if m.is_finite() {
            (2.0 * UNIT_ROUNDOFF * m + ETA).next_up()
        } else {
            f64::INFINITY
        };
        if !m.is_finite() {
            return Err(BernsteinError::NonFinite {
                index: coeffs.iter().position(|c| !c.is_finite()).unwrap_or(0),
            });
        }
        Self::with_error(p.degrees().to_vec(), coeffs, err)
    }

    /// Degree per axis.
    pub fn degrees(&self) -> &[usize] {
        &self.degrees
    }

    /// The coefficients, axis 0 fastest.
    pub fn coeffs(&self) -> &[f64] {
        &self.coeffs
    }

    /// The certified bound on every coefficient's error.
    pub fn err(&self) -> f64 {
        self.err
    }

    /// Largest coefficient magnitude.
    pub fn max_abs(&self) -> f64 {
        self.coeffs.iter().fold(0.0f64, |m, c| m.max(c.abs()))
    }

    /// Certified sign of coefficient `k`.
    pub fn coeff_sign(&self, k: usize) -> Sign {
        let c = self.coeffs[k];
        if c > self.err {
            Sign::Positive
        } else if c < -self.err {
            Sign::Negative
        } else if c == 0.0 && self.err == 0.0 {
            Sign::Zero
        } else {
            Sign::Uncertain
        }
    }

    /// Flat index of the vertex coefficient at `corner` (bit a set: `t_a = 1`).
    pub fn vertex_index(&self, corner: usize) -> usize {
        let s = strides(&self.degrees);
        self.degrees
            .iter()
            .enumerate()
            .filter(|(a, _)| corner >> a & 1 == 1)
            .map(|(a, &d)| d * s[a])
            .sum()
    }

    /// An empty buffer of the same shape, for [`split_half_into`](Self::split_half_into).
    pub fn buffer_like(&self) -> FastBernstein {
        FastBernstein {
            degrees: self.degrees.clone(),
            coeffs: vec![0.0; self.coeffs.len()],
            err: 0.0,
        }
    }

    /// de Casteljau at ½ along `axis`, writing the halves into `left` and `right`
    /// (buffers of the same shape, e.g. from [`buffer_like`](Self::buffer_like)). Allocation-free.
    pub fn split_half_into(
        &self,
        axis: usize,
        left: &mut FastBernstein,
        right: &mut FastBernstein,
    ) {
        let d = self.degrees[axis];
        let len = d + 1;
        let inner: usize = self.degrees[..axis].iter().map(|d| d + 1).product();
        let outer: usize = self.degrees[axis + 1..].iter().map(|d| d + 1).product();
        left.degrees.clone_from(&self.degrees);
        right.degrees.clone_from(&self.degrees);
        left.coeffs.resize(self.coeffs.len(), 0.0);
        right.coeffs.resize(self.coeffs.len(), 0.0);
        let mut work = [0.0f64; MAX_FAST_DEGREE + 1];
        let mut max_abs = 0.0f64;
        for o in 0..outer {
            for i in 0..inner {
                let base = i + inner * len * o;
                for (k, w) in work.iter_mut().enumerate().take(len) {
                    let v = self.coeffs[base + inner * k];
                    max_abs = max_abs.max(v.abs());
                    *w = v;
                }
                left.coeffs[base] = work[0];
                right.coeffs[base + inner * d] = work[d];
                for r in 1..len {
                    for k in 0..len - r {
                        work[k] = (work[k] + work[k + 1]) * 0.5;
                    }
                    left.coeffs[base + inner * r] = work[0];
                    right.coeffs[base + inner * (d - r)] = work[d - r];
                }
            }
        }
        let dd = d as f64;
        let err = (self.err + 2.0 * dd * UNIT_ROUNDOFF * (max_abs + self.err) + 2.0 * dd * ETA)
            .next_up()
            .next_up();
        left.err = err;
        right.err = err;
    }

    /// The exact polynomial these coefficients stand for lies within `err`; this returns
    /// the coefficients as rationals (exact values of the stored `f64`s).
    pub fn to_rational_coeffs(&self) -> Bernstein<Rational> {
        let coeffs = self
            .coeffs
            .iter()
            .map(|&c| crate::num::rational_from_f64(c, "coefficient").expect("finite by invariant"))
            .collect();
        Bernstein::new(self.degrees.clone(), coeffs).expect("counts match")
    }

    /// The product with certified error bound (per axis `C(m,i)C(n,j)/C(m+n,i+j)` weights):
    /// with `A, B` the max magnitudes and `Ea, Eb` the bounds, the exact product's coefficients
    /// lie within `(A·Eb + B·Ea + Ea·Eb)(1+γ₁) + γ_{T+4}·A·B` of the computed ones, `T` the
    /// largest number of terms summed into one coefficient (weights per axis sum to 1).
    pub fn product(&self, other: &FastBernstein) -> Result<FastBernstein, BernsteinError> {
        if self.degrees.len() != other.degrees.len() {
            return Err(BernsteinError::DimensionMismatch {
                expected: self.degrees.len(),
                found: other.degrees.len(),
            });
        }
        let n = self.degrees.len();
        let degrees: Vec<usize> = self
            .degrees
            .iter()
            .zip(&other.degrees)
            .map(|(a, b)| a + b)
            .collect();
        if let Some(&d) = degrees.iter().find(|&&d| d > MAX_EXACT_BINOMIAL_F64) {
            return Err(BernsteinError::DegreeTooHigh {
                degree: d,
                limit: MAX_EXACT_BINOMIAL_F64,
            });
        }
        let top = degrees.iter().copied().max().unwrap_or(0);
        let bin: Vec<Vec<f64>> = (0..=top)
            .map(|m| (0..=m).map(|k| binomial_f64(m, k)).collect())
            .collect();
        let so = strides(&degrees);
        let mut out = vec![0.0f64; coefficient_count(&degrees)];
        let mut terms = 1usize;
        for ax in 0..n {
            terms *= self.degrees[ax].min(other.degrees[ax]) + 1;
        }
        // Per-axis weight tables.
        let w: Vec<Vec<f64>> = (0..n)
            .map(|ax| {
                let (m, q) = (self.degrees[ax], other.degrees[ax]);
                let mut t = vec![0.0; (m + 1) * (q + 1)];
                for i in 0..=m {
                    for j in 0..=q {
                        t[i * (q + 1) + j] = bin[m][i] * bin[q][j] / bin[m + q][i + j];
                    }
                }
                t
            })
            .collect();
        let na = self.coeffs.len();
        let nb = other.coeffs.len();
        let mut ia = vec![0usize; n];
        for fa in 0..na {
            let a = self.coeffs[fa];
            let mut ib = vec![0usize; n];
            for fb in 0..nb {
                let mut v = a * other.coeffs[fb];
                let mut k = 0;
                for ax in 0..n {
                    v *= w[ax][ia[ax] * (other.degrees[ax] + 1) + ib[ax]];
                    k += (ia[ax] + ib[ax]) * so[ax];
                }
                out[k] += v;
                increment(&mut ib, &other.degrees);
            }
            increment(&mut ia, &self.degrees);
        }
        let (ma, mb) = (self.max_abs(), other.max_abs());
        let (ea, eb) = (self.err, other.err);
        // Each term carries n+1 multiplication roundings and 2n weight roundings (the weight
        // is a rounded quotient of exact binomials); then one summation chain of T terms.
        let g = gamma((terms + 3 * n + 4) as u32);
        let err = ((ma * eb + mb * ea + ea * eb) * (1.0 + gamma(1))
            + g * ma * mb
            + (terms as f64) * 4.0 * ETA)
            .next_up();
        if !err.is_finite() || out.iter().any(|c| !c.is_finite()) {
            return Err(BernsteinError::NonFinite { index: 0 });
        }
        Ok(FastBernstein {
            degrees,
            coeffs: out,
            err,
        })
    }
}

/// Advances a multi-index (axis 0 fastest).
fn increment(idx: &mut [usize], degrees: &[usize]) {
    for (i, &d) in idx.iter_mut().zip(degrees) {
        *i += 1;
        if *i <= d {
            return;
        }
        *i = 0;
    }
}
