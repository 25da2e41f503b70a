//! Univariate polynomials over `ℚ` in the power basis (coefficients lowest first): the exact
//! division and greatest common divisor the silhouette's corner passages and the contents of
//! tensor polynomials share.

use crate::num::Rational;
use num_traits::{One, Zero};

/// `p` without its zero leading coefficients.
pub(crate) fn trimmed(mut p: Vec<Rational>) -> Vec<Rational> {
    while p.last().is_some_and(Zero::is_zero) {
        p.pop();
    }
    p
}

/// Long division of `a` by `b` (`b` trimmed and non-zero): the quotient and the trimmed
/// remainder.
pub(crate) fn div_rem(a: &[Rational], b: &[Rational]) -> (Vec<Rational>, Vec<Rational>) {
    let mut r = trimmed(a.to_vec());
    let lead = b.last().expect("non-zero divisor");
    let mut q = vec![Rational::zero(); r.len().saturating_sub(b.len()) + 1];
    while r.len() >= b.len() {
        let shift = r.len() - b.len();
        let c = r.last().expect("non-empty") / lead;
        for (k, x) in b.iter().enumerate() {
            r[shift + k] -= &c * x;
        }
        q[shift] = c;
        r.pop();
        r = trimmed(r);
    }
    (q, r)
}

/// The monic gcd of two univariate polynomials (empty when both are zero), by Euclid's
/// algorithm in exact rationals.
pub(crate) fn gcd(a: &[Rational], b: &[Rational]) -> Vec<Rational> {
    let (mut a, mut b) = (trimmed(a.to_vec()), trimmed(b.to_vec()));
    while !b.is_empty() {
        let r = div_rem(&a, &b).1;
        a = b;
        b = r;
    }
    monic(a)
}

/// `p` divided by its leading coefficient (unchanged when zero or empty).
pub(crate) fn monic(p: Vec<Rational>) -> Vec<Rational> {
    match p.last().cloned() {
        Some(lead) if !lead.is_zero() && !lead.is_one() => {
            p.into_iter().map(|x| x / &lead).collect()
        }
        _ => p,
    }
}
