//! Face disambiguation (Wünsche & Lin, Section 4.1, Figure 4): on a face whose corner signs
//! alternate, are the positive corners joined across the face?
//!
//! Corner values `A` (0,0), `B` (1,0), `C` (0,1), `D` (1,1) — `A, D` on one diagonal, `B, C` on
//! the other — around isovalue `c`; `a = A − c` and so on. The bilinear interpolant's saddle
//! value `S = (AD − BC)/(A + D − B − C)` satisfies `ad − bc = (a + d − b − c)(S − c)`, so
//! comparing the positive diagonal's product with the negative one's (the product rule) is
//! the asymptotic decider `S > c`. **Tie rule:** `S = c` (equal products) counts as joined —
//! the saddle point lies on the level set and is positive by the rule `v ≥ c`
//! ([`is_positive`](super::table::is_positive)); the rule depends only on the four values, so
//! both cells sharing the face decide alike.

use crate::num::{gamma, Rational};

/// Whether the face `A, B, C, D` (see the module docs) is ambiguous at `iso`.
pub fn is_ambiguous_face<T: PartialOrd>(v: [&T; 4], iso: &T) -> bool {
    let p = v.map(|x| super::table::is_positive(x, iso));
    p[0] == p[3] && p[1] == p[2] && p[0] != p[1]
}

/// The exact decision: `Some(true)` when the positive corners are joined, `None` when the face
/// is not ambiguous.
pub fn decide_exact(v: [&Rational; 4], iso: &Rational) -> Option<bool> {
    if !is_ambiguous_face(v, iso) {
        return None;
    }
    let [a, b, c, d] = v.map(|x| x - iso);
    Some(decide_shifted(&a, &b, &c, &d))
}

/// The decision from shifted values `a = A − c`, … of an ambiguous face (any exact ordered
/// ring: rationals, or integers after scaling by the isovalue's denominator). Positive
/// corners are those with `a ≥ 0`.
pub(crate) fn decide_shifted<T>(a: &T, b: &T, c: &T, d: &T) -> bool
where
    T: PartialOrd + Default,
    for<'x> &'x T: std::ops::Mul<&'x T, Output = T>,
{
    let (ad, bc) = (a * d, b * c);
    let (pos, neg) = if *a >= T::default() {
        (ad, bc)
    } else {
        (bc, ad)
    };
    pos >= neg
}

/// The `f64` decision, certified: `Some(Some(joined))`, `Some(None)` for a face that is not
/// ambiguous, or `None` (uncertain) when `ad − bc` is within its rounding error bound of zero
/// or the inputs are not finite. Corner signs are exact (`v ≥ c` on `f64`s); `a = fl(A − c)`
/// has relative error `u`, each product one more rounding, the difference one more:
/// `|fl(ad − bc) − (ad − bc)| ≤ γ₃ (|ad| + |bc|)`, and the bound itself is rounded up.
pub fn decide_fast(v: [f64; 4], iso: f64) -> Option<Option<bool>> {
    if !(v.iter().all(|x| x.is_finite()) && iso.is_finite()) {
        return None;
    }
    if !is_ambiguous_face([&v[0], &v[1], &v[2], &v[3]], &iso) {
        return Some(None);
    }
    let [a, b, c, d] = v.map(|x| x - iso);
    // Products of magnitudes below 1e-145 may underflow, where relative bounds fail.
    if [a, b, c, d].iter().any(|x| *x != 0.0 && x.abs() < 1e-145) {
        return None;
    }
    let (ad, bc) = (a * d, b * c);
    let a_positive = v[0] >= iso;
    let diff = if a_positive { ad - bc } else { bc - ad };
    let bound = (gamma(3) * (ad.abs() + bc.abs())).next_up();
    if !bound.is_finite() {
        return None;
    }
    if diff > bound {
        Some(Some(true))
    } else if diff < -bound {
        Some(Some(false))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_bigint::BigInt;

    fn r(x: i64) -> Rational {
        Rational::from_integer(BigInt::from(x))
    }

    #[test]
    fn decisions_and_the_tie_rule() {
        // Positive A, D with a·d = 9 > b·c = 1: joined.
        assert_eq!(
            decide_exact([&r(3), &r(-1), &r(-1), &r(3)], &r(0)),
            Some(true)
        );
        assert_eq!(
            decide_exact([&r(1), &r(-3), &r(-3), &r(1)], &r(0)),
            Some(false)
        );
        // Equal products: the saddle is on the level set, joined by the tie rule.
        assert_eq!(
            decide_exact([&r(2), &r(-2), &r(-1), &r(1)], &r(0)),
            Some(true)
        );
        assert_eq!(decide_fast([2.0, -2.0, -1.0, 1.0], 0.0), None);
        assert_eq!(decide_exact([&r(2), &r(2), &r(-1), &r(1)], &r(0)), None);
        assert_eq!(decide_fast([3.0, -1.0, -1.0, 3.0], 0.0), Some(Some(true)));
    }
}
