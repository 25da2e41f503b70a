//! The number types the closed-form oracle runs on: exact integers with the isovalue pushed
//! down by an infinitesimal `ε` ([`Eps`]), and outward-rounded `f64` intervals.
//!
//! **Simulation of simplicity on the isovalue.** The table's tie rules (a corner equal to the
//! isovalue is positive, a face saddle equal to it joins the positive corners) are exactly
//! the topology of the level set at `c − ε` for an infinitesimal `ε > 0`: every shifted value
//! `g = v − c` becomes `g + ε`. For small enough real `ε` the level `c − ε` is a regular value
//! of the interpolant on the cell, its faces and its edges (each has finitely many critical
//! values unless it is constant, and a constant one never equals `c − ε`), so the perturbed
//! surface is a manifold transverse to the faces whatever the input. Every decision is the
//! sign of a polynomial in `ε`; in the ordered ring `ℤ[ε]` that is the sign of its
//! lowest-order non-zero coefficient. The degree never exceeds 2 here (the `ε²` terms of a
//! slice's diagonal products cancel); [`Eps`] keeps five coefficients and its products are
//! only ever formed where the degrees sum to at most 4.

use num_bigint::BigInt;
use num_traits::{Signed, Zero};
use std::cmp::Ordering;

use crate::num::{Interval, Sign};

/// An ordered ring whose signs may be unknown: exact types always know, intervals may not.
pub(crate) trait OrderedRing: Clone {
    /// `a + b`.
    fn add(&self, o: &Self) -> Self;
    /// `a − b`.
    fn sub(&self, o: &Self) -> Self;
    /// `a · b`.
    fn mul(&self, o: &Self) -> Self;
    /// The number `k`.
    fn int(k: i64) -> Self;
    /// The sign, or `None` when it cannot be certified.
    fn sign(&self) -> Option<Ordering>;
}

/// Integer coefficients: `i128` (inputs bounded so nothing overflows, see
/// [`super::exact`]) or `BigInt`.
pub(crate) trait Coeff: Clone + Zero + Signed + Ord + From<i64> {}
impl Coeff for i128 {}
impl Coeff for BigInt {}

/// `c₀ + c₁ε + c₂ε² + c₃ε³ + c₄ε⁴` with an infinitesimal `ε > 0`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Eps<T>(pub [T; 5]);

impl<T: Coeff> Eps<T> {
    /// `g + ε`: a shifted corner value under the isovalue's perturbation.
    pub(crate) fn shifted(g: T) -> Eps<T> {
        let mut c = Self::zero_coeffs();
        c[0] = g;
        c[1] = T::from(1);
        Eps(c)
    }
    fn zero_coeffs() -> [T; 5] {
        std::array::from_fn(|_| T::zero())
    }
}

impl<T: Coeff> OrderedRing for Eps<T> {
    fn add(&self, o: &Self) -> Self {
        Eps(std::array::from_fn(|i| self.0[i].clone() + o.0[i].clone()))
    }
    fn sub(&self, o: &Self) -> Self {
        Eps(std::array::from_fn(|i| self.0[i].clone() - o.0[i].clone()))
    }
    fn mul(&self, o: &Self) -> Self {
        let deg = |p: &[T; 5]| p.iter().rposition(|c| !c.is_zero());
        let mut c = Self::zero_coeffs();
        if let (Some(a), Some(b)) = (deg(&self.0), deg(&o.0)) {
            debug_assert!(a + b <= 4, "ε-degree {} exceeds 4", a + b);
            for i in 0..=a {
                for j in 0..=b.min(4 - i) {
                    c[i + j] = c[i + j].clone() + self.0[i].clone() * o.0[j].clone();
                }
            }
        }
        Eps(c)
    }
    fn int(k: i64) -> Self {
        let mut c = Self::zero_coeffs();
        c[0] = T::from(k);
        Eps(c)
    }
    fn sign(&self) -> Option<Ordering> {
        Some(
            self.0
                .iter()
                .find(|c| !c.is_zero())
                .map_or(Ordering::Equal, |c| c.cmp(&T::zero())),
        )
    }
}

impl OrderedRing for Interval {
    fn add(&self, o: &Self) -> Self {
        *self + *o
    }
    fn sub(&self, o: &Self) -> Self {
        *self - *o
    }
    fn mul(&self, o: &Self) -> Self {
        *self * *o
    }
    fn int(k: i64) -> Self {
        Interval::point(k as f64)
    }
    fn sign(&self) -> Option<Ordering> {
        match Interval::sign(self) {
            Sign::Positive => Some(Ordering::Greater),
            Sign::Negative => Some(Ordering::Less),
            Sign::Zero => Some(Ordering::Equal),
            Sign::Uncertain => None,
        }
    }
}

/// A point `n / d` of the sweep axis with `d > 0`.
#[derive(Clone, Debug)]
pub(crate) struct Frac<S> {
    /// Numerator.
    pub n: S,
    /// Denominator, positive.
    pub d: S,
}

impl<S: OrderedRing> Frac<S> {
    /// `k / 1`.
    pub(crate) fn int(k: i64) -> Frac<S> {
        Frac {
            n: S::int(k),
            d: S::int(1),
        }
    }
    /// `self` against `o`, `None` when uncertain.
    pub(crate) fn cmp(&self, o: &Frac<S>) -> Option<Ordering> {
        self.n.mul(&o.d).sub(&o.n.mul(&self.d)).sign()
    }
    /// The midpoint.
    pub(crate) fn mid(&self, o: &Frac<S>) -> Frac<S> {
        Frac {
            n: self.n.mul(&o.d).add(&o.n.mul(&self.d)),
            d: S::int(2).mul(&self.d).mul(&o.d),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signs_follow_the_lowest_order_term() {
        let e = |c: [i128; 5]| Eps(c);
        assert_eq!(e([0, 0, 0, 0, 0]).sign(), Some(Ordering::Equal));
        assert_eq!(e([0, 1, -5, 0, 0]).sign(), Some(Ordering::Greater));
        assert_eq!(e([-1, 9, 9, 0, 0]).sign(), Some(Ordering::Less));
        assert_eq!(e([0, 0, -1, 0, 0]).sign(), Some(Ordering::Less));
        // (g + ε)(h + ε) − (k + ε)(l + ε): the ε² terms cancel.
        let [g, h, k, l] = [2i128, 3, 1, 6].map(Eps::shifted);
        let q = g.mul(&h).sub(&k.mul(&l));
        assert_eq!(q.0, [0, -2, 0, 0, 0]);
        assert_eq!(q.sign(), Some(Ordering::Less));
    }

    #[test]
    fn fractions_compare_exactly() {
        let third = Frac {
            n: Eps::<BigInt>::int(1),
            d: Eps::int(3),
        };
        let half = Frac::<Eps<BigInt>>::int(1).mid(&Frac::int(0));
        assert_eq!(third.cmp(&half), Some(Ordering::Less));
        assert_eq!(half.cmp(&half), Some(Ordering::Equal));
    }
}
