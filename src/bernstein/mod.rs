//! Bernstein polynomials, univariate and tensor-product n-variate, in three forms:
//!
//! * [`Bernstein<T>`](poly::Bernstein): generic over any [`Field`](crate::num::Field) —
//!   exact with [`Rational`](crate::num::Rational), certified with
//!   [`Interval`](crate::num::Interval). Evaluation, subdivision, restriction,
//!   elevation, derivative, product, power-basis conversion, face slices.
//! * [`ScaledBernstein`]: the sign-only exact form, integer
//!   numerators over one shared denominator; subdivision at ½ needs no gcd.
//! * [`FastBernstein`]: `f64` coefficients with one rigorous
//!   forward error bound, preallocated, no allocation inside the subdivision loop.
//!
//! [`prove_positive`] proves or refutes `p > 0` on the unit box by subdivision, with
//! checkable certificates, in all three forms.

pub(crate) mod certificate;
pub(crate) mod content;
pub(crate) mod fast;
pub(crate) mod io;
pub(crate) mod poly;
pub(crate) mod positivity;
pub(crate) mod scaled;
pub(crate) mod univariate;

pub use certificate::{box_sign, BoxSign};
pub use content::UnivariateFactor;
pub use fast::FastBernstein;
pub use io::{
    certificate_for, parse_number, poly_from_json, poly_to_json, verify_certificate_file,
    CertificateFile, InputError, PositivityCheck, VerifyError,
};
pub use poly::Bernstein;
pub use positivity::{
    prove_positive, prove_positive_exact, prove_positive_fast, prove_positive_filtered,
    prove_positive_filtered_with, prove_positive_scaled, verify_positive_certificate,
    verify_positive_certificate_scaled, verify_witness, CertificateError, DyadicBox, LimitHit,
    Limits, PositivityOptions, PositivityVerdict, WitnessValue,
};
pub use scaled::ScaledBernstein;

use num_bigint::BigInt;
use thiserror::Error;

/// Errors of the Bernstein kernel.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum BernsteinError {
    #[error("a Bernstein polynomial needs at least one axis")]
    /// No axis was given.
    NoAxes,
    #[error("wrong coefficient count: expected {expected}, found {found}")]
    /// The coefficient count is not the product of `degree + 1` over the axes.
    CoefficientCount {
        /// `Π (d_a + 1)`.
        expected: usize,
        /// Coefficients given.
        found: usize,
    },
    #[error("axis {axis} out of range for a {dim}-variate polynomial")]
    /// An axis index is out of range.
    Axis {
        /// The axis asked for.
        axis: usize,
        /// The polynomial's number of variables.
        dim: usize,
    },
    #[error("dimension mismatch: expected {expected}, found {found}")]
    /// Two operands (or a point) have different numbers of variables.
    DimensionMismatch {
        /// The number of variables expected.
        expected: usize,
        /// The number found.
        found: usize,
    },
    #[error("degree mismatch between operands")]
    /// Two operands have different degrees where equal ones are needed.
    DegreeMismatch,
    #[error("sub-box on axis {axis} is not an interval [a,b] with 0 ≤ a < b ≤ 1")]
    /// A sub-box is not a non-empty interval inside `[0, 1]`.
    BadBox {
        /// The offending axis.
        axis: usize,
    },
    #[error("split parameter must lie strictly between 0 and 1")]
    /// A split parameter is not strictly between 0 and 1.
    BadParameter,
    #[error("non-finite coefficient at index {index}")]
    /// A coefficient is NaN or infinite.
    NonFinite {
        /// Its index.
        index: usize,
    },
    #[error("degree {degree} on an axis exceeds the fast path's limit of {limit}")]
    /// A degree exceeds the fast path's limit.
    DegreeTooHigh {
        /// The degree.
        degree: usize,
        /// The limit.
        limit: usize,
    },
}

/// The binomial coefficient `C(n, k)` as a big integer (0 when `k > n`).
pub fn binomial(n: usize, k: usize) -> BigInt {
    if k > n {
        return BigInt::from(0);
    }
    let k = k.min(n - k);
    let mut acc = BigInt::from(1);
    for i in 0..k {
        acc = acc * BigInt::from(n - i) / BigInt::from(i + 1);
    }
    acc
}

/// Largest `n` for which every `C(n, k)` is below 2⁵³ and so exact in `f64`.
pub const MAX_EXACT_BINOMIAL_F64: usize = 56;

/// `C(n, k)` in `f64` by Pascal's rule (integer additions, exact for
/// `n ≤ MAX_EXACT_BINOMIAL_F64`).
pub fn binomial_f64(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let mut row = vec![1.0f64; 1];
    for m in 1..=n {
        let mut next = vec![1.0f64; m + 1];
        for j in 1..m {
            next[j] = row[j - 1] + row[j];
        }
        row = next;
    }
    row[k]
}
