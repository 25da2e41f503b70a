//! Eqs. (1) and (2) exactly, in integers over a shared denominator: the fast path's exact
//! fallbacks (signs near the isovalue, cut points, the Figure 7 coincidence test).
//!
//! Every `f64` dof is `m · 2^e`; over the smallest exponent of its channel an element's
//! coefficients are integers `M` (the tensor of [`tensor`](super::tensor)). At
//! `ξ_d = p_d / q_d` the 1-D functions times `q_d^k` (`k = 3` Hermite, `1` Lagrange) are
//! integer polynomials in `p_d, q_d`:
//! `q³H₁⁰ = q³ − 3p²q + 2p³`, `q³H₁¹ = p(p − q)²`, `q³H₂⁰ = p²(3q − 2p)`, `q³H₂¹ = p²(p − q)`,
//! `qL₁ = q − p`, `qL₂ = p`. So `u(ξ) = 2^e · N / (q₀^k₀ q₁^k₁ q₂^k₂)` with an integer `N`
//! summed by the same three contractions, and one gcd at the end instead of one per
//! product (the reference path, [`exact`](super::exact), normalises every rational it makes).

use super::tensor::{active, dof_slots};
use super::{Basis, FeModel};
use crate::num::rational::f64_dyadic;
use crate::num::Rational;
use num_bigint::BigInt;
use num_traits::{One, Zero};

/// One element's channels (field, then x, y, z) as integers times a power of two.
#[derive(Clone, Debug)]
pub(crate) struct IntegerElement {
    bases: [Basis; 3],
    m: [usize; 3],
    /// `coeffs[channel][(c · m₁ + b) · m₀ + a]`, each `C = M · 2^exps[channel]`.
    coeffs: [Vec<BigInt>; 4],
    exps: [i64; 4],
}

/// `q^k · [active 1-D functions](p / q)` as integers, and `k`.
fn integer_basis(b: Basis, p: &BigInt, q: &BigInt) -> ([BigInt; 4], u32) {
    match b {
        Basis::LinearLagrange => ([q - p, p.clone(), BigInt::zero(), BigInt::zero()], 1),
        Basis::CubicHermite => {
            let p2 = p * p;
            let pq = p - q;
            let h2 = &p2 * (BigInt::from(3) * q - BigInt::from(2) * p);
            let q3 = q * q * q;
            ([&q3 - &h2, p * &pq * &pq, h2, &p2 * &pq], 3)
        }
    }
}

impl IntegerElement {
    /// Element `nodes` of `m` (finite dofs, as validated).
    pub(crate) fn new(m: &FeModel<f64>, nodes: &[u32; 8]) -> IntegerElement {
        let kind = m.kind;
        let md = kind.bases.map(active);
        let size = md[0] * md[1] * md[2];
        let mut raw = [
            vec![(0i64, 0i64); size],
            vec![(0, 0); size],
            vec![(0, 0); size],
            vec![(0, 0); size],
        ];
        for (slot, dof) in dof_slots(kind, nodes) {
            raw[0][slot] = f64_dyadic(m.field[dof]);
            for c in 0..3 {
                raw[1 + c][slot] = f64_dyadic(m.coordinates[dof][c]);
            }
        }
        let mut exps = [0i64; 4];
        let coeffs = std::array::from_fn(|ch| {
            let e = raw[ch]
                .iter()
                .filter(|(m, _)| *m != 0)
                .map(|&(_, e)| e)
                .min()
                .unwrap_or(0);
            exps[ch] = e;
            raw[ch]
                .iter()
                .map(|&(m, x)| BigInt::from(m) << ((x - e) as usize))
                .collect()
        });
        IntegerElement {
            bases: kind.bases,
            m: md,
            coeffs,
            exps,
        }
    }

    /// Channels `channels` (0 the field, 1–3 the coordinates) at `ξ`, exactly.
    pub(crate) fn eval<const C: usize>(
        &self,
        channels: [usize; C],
        xi: &[Rational; 3],
    ) -> [Rational; C] {
        let mut den = BigInt::one();
        let basis: [[BigInt; 4]; 3] = std::array::from_fn(|d| {
            let (b, k) = integer_basis(self.bases[d], xi[d].numer(), xi[d].denom());
            den *= num_traits::pow(xi[d].denom().clone(), k as usize);
            b
        });
        let [m0, m1, m2] = self.m;
        channels.map(|ch| {
            let c = &self.coeffs[ch];
            let mut total = BigInt::zero();
            for cc in 0..m2 {
                let mut plane = BigInt::zero();
                for bb in 0..m1 {
                    let base = (cc * m1 + bb) * m0;
                    let mut row = BigInt::zero();
                    for a in 0..m0 {
                        if !c[base + a].is_zero() {
                            row += &basis[0][a] * &c[base + a];
                        }
                    }
                    plane += &basis[1][bb] * row;
                }
                total += &basis[2][cc] * plane;
            }
            let e = self.exps[ch];
            if e >= 0 {
                Rational::new(total << (e as usize), den.clone())
            } else {
                Rational::new(total, den.clone() << ((-e) as usize))
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::exact::{interpolate_field, interpolate_world};
    use super::super::{heart, models, ElementKind};
    use super::*;

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    #[test]
    fn integer_route_equals_the_reference_sums() {
        let lagrange = models::block(
            ElementKind::TRILINEAR_LAGRANGE,
            [2, 1, 1],
            &|p| (p[0] - 0.3) * (p[1] + 0.7) - p[2] * 1e-3,
            &|_, _| 0.0,
            &|p| [p[0] + 0.1 * p[1] * p[2], p[1] * 3.5e5, p[2] - 0.2],
        );
        let points = [
            [q(0, 1), q(1, 1), q(1, 2)],
            [q(1, 3), q(2, 7), q(5, 9)],
            [q(-1, 5), q(11, 10), q(123_456_789, 987_654_321)],
        ];
        for m in [heart::left_ventricle(), models::hermite_ball(2), lagrange] {
            let exact = m.to_exact().expect("finite");
            for nodes in &m.elements {
                let ie = IntegerElement::new(&m, nodes);
                for xi in &points {
                    let [u, x, y, z] = ie.eval([0, 1, 2, 3], xi);
                    assert_eq!(u, interpolate_field(&exact, nodes, xi, None));
                    assert_eq!([x, y, z], interpolate_world(&exact, nodes, xi, None));
                }
            }
        }
    }
}
