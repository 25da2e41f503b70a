//! The scalar layer: exact rationals, the sign-only integer form, certified
//! `f64` signs, and the [`Field`] trait that lets an algorithm be written once.
//!
//! * [`Rational`] is `num_rational::BigRational`, gcd-normalised, never wrong.
//! * [`rational_from_f64`] converts losslessly from `f64` (every finite `f64` is a dyadic
//!   rational), [`rational_to_f64`] rounds back to the nearest `f64`, and
//!   [`parse_rational`] parses `"p/q"` and decimal strings.
//! * [`Interval`] is an outward-rounded `f64` interval built with
//!   `f64::next_up`/`next_down` (the FPU rounding mode is never touched); [`gamma`] is the
//!   forward error constant.
//! * [`Sign`] is the four-valued sign every certified decision returns.

pub(crate) mod field;
pub(crate) mod interval;
pub(crate) mod rational;
pub(crate) mod wide;

/// One step of Marsaglia's xorshift64 (*Xorshift RNGs*, J. Stat. Softw. 8(14), 2003): the
/// deterministic generator of the tests, of the reports' random campaigns and of the fixed
/// line combinations of `bernstein::content`. `state` must not be zero.
pub(crate) fn xorshift(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}

pub use field::Field;
pub use interval::{gamma, Interval, UNIT_ROUNDOFF};
pub use rational::{
    parse_rational, point_to_string, rational_from_f64, rational_to_f64, rational_to_string,
    Rational,
};

use thiserror::Error;

/// The sign of a quantity as far as it is known.
///
/// Exact paths only ever produce `Negative`, `Zero` or `Positive`; certified
/// floating-point paths say `Uncertain` when their error bound straddles zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Sign {
    /// Certainly negative.
    Negative,
    /// Exactly zero.
    Zero,
    /// Certainly positive.
    Positive,
    /// Rounding error leaves the sign open (fast paths only).
    Uncertain,
}

impl Sign {
    /// The sign of an integer-like ordering against zero.
    pub fn of_ordering(o: std::cmp::Ordering) -> Sign {
        match o {
            std::cmp::Ordering::Less => Sign::Negative,
            std::cmp::Ordering::Equal => Sign::Zero,
            std::cmp::Ordering::Greater => Sign::Positive,
        }
    }

    /// True when the sign is known (not `Uncertain`).
    pub fn is_certain(self) -> bool {
        self != Sign::Uncertain
    }

    /// The product of two signs (`Uncertain` absorbs unless the other is `Zero`).
    pub fn times(self, other: Sign) -> Sign {
        use Sign::*;
        match (self, other) {
            (Zero, _) | (_, Zero) => Zero,
            (Uncertain, _) | (_, Uncertain) => Uncertain,
            (a, b) if a == b => Positive,
            _ => Negative,
        }
    }

    /// True when a certain sign disagrees with `exact` (an `Uncertain` never contradicts).
    pub fn contradicts(self, exact: Sign) -> bool {
        self.is_certain() && self != exact
    }
}

/// Errors of the scalar layer.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum NumError {
    #[error("non-finite number {value} ({what}): only finite values are accepted")]
    /// A number is NaN or infinite.
    NonFinite {
        /// What it was.
        what: String,
        /// The value.
        value: f64,
    },
    #[error("cannot parse {text:?} as a rational number ({why})")]
    /// A string is not a rational number.
    Parse {
        /// The string.
        text: String,
        /// Why.
        why: String,
    },
    #[error("zero denominator in {text:?}")]
    /// A `p/q` string has `q = 0`.
    ZeroDenominator {
        /// The string.
        text: String,
    },
}
