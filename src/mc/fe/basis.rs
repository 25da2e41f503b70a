//! The interpolation functions of Section 2 and the interpolation sums of eqs. (1) and (2),
//! exactly (rationals) and in `f64`.
//!
//! A 1-D basis at `ξ` is four numbers `[φ₁⁰, φ₁¹, φ₂⁰, φ₂¹]`: value and derivative functions of
//! the node at `ξ = 0` and of the node at `ξ = 1`. Linear Lagrange has no derivative functions
//! (`L₁, 0, L₂, 0`); cubic Hermite is `H₁⁰, H₁¹, H₂⁰, H₂¹`.

use super::{Basis, ElementKind};
use crate::num::Rational;
use num_bigint::BigInt;
use num_traits::{One, Zero};

/// `[φ₁⁰, φ₁¹, φ₂⁰, φ₂¹](ξ)` exactly (Section 2): the reference [`basis_scaled`] is tested
/// against.
#[cfg(test)]
pub(crate) fn basis_exact(b: Basis, t: &Rational) -> [Rational; 4] {
    let one = Rational::one();
    match b {
        Basis::LinearLagrange => [&one - t, Rational::zero(), t.clone(), Rational::zero()],
        Basis::CubicHermite => {
            let t2 = t * t;
            let t3 = &t2 * t;
            let tm1 = t - &one;
            let three = Rational::from_integer(3.into());
            let two = Rational::from_integer(2.into());
            [
                &one - &three * &t2 + &two * &t3,
                t * &tm1 * &tm1,
                &t2 * (&three - &two * t),
                &t2 * &tm1,
            ]
        }
    }
}

/// `d/dξ [φ₁⁰, φ₁¹, φ₂⁰, φ₂¹](ξ)` exactly (the reference of [`basis_scaled`]'s derivatives).
#[cfg(test)]
pub(crate) fn basis_derivative_exact(b: Basis, t: &Rational) -> [Rational; 4] {
    let one = Rational::one();
    match b {
        Basis::LinearLagrange => [-one.clone(), Rational::zero(), one, Rational::zero()],
        Basis::CubicHermite => {
            let six = Rational::from_integer(6.into());
            let three = Rational::from_integer(3.into());
            let two = Rational::from_integer(2.into());
            let t2 = t * t;
            let h = &six * &t2 - &six * t; // H₁⁰' = −6ξ + 6ξ²
            [
                h.clone(),
                (t - &one) * (&three * t - &one),
                -h,
                &three * &t2 - &two * t,
            ]
        }
    }
}

/// `[φ₁⁰, φ₁¹, φ₂⁰, φ₂¹](ξ)` in `f64`.
pub(crate) fn basis_f64(b: Basis, t: f64) -> [f64; 4] {
    match b {
        Basis::LinearLagrange => [1.0 - t, 0.0, t, 0.0],
        Basis::CubicHermite => {
            let t2 = t * t;
            let s = t - 1.0;
            [
                1.0 - t2 * (3.0 - 2.0 * t),
                t * s * s,
                t2 * (3.0 - 2.0 * t),
                t2 * s,
            ]
        }
    }
}

/// `d/dξ [φ₁⁰, φ₁¹, φ₂⁰, φ₂¹](ξ)` in `f64`.
pub(crate) fn basis_derivative_f64(b: Basis, t: f64) -> [f64; 4] {
    match b {
        Basis::LinearLagrange => [-1.0, 0.0, 1.0, 0.0],
        Basis::CubicHermite => {
            let h = 6.0 * t * (t - 1.0);
            [h, (t - 1.0) * (3.0 * t - 1.0), -h, t * (3.0 * t - 2.0)]
        }
    }
}

/// One term of eq. (1): local node (tensor index `a + 2b + 4c`), its dof, the weight.
pub(crate) type Term<T> = (usize, usize, T);

/// Every term of eq. (1) in order: local node, its dof, and per direction the index into that
/// direction's `[φ₁⁰, φ₁¹, φ₂⁰, φ₂¹]` the term multiplies.
fn term_indices(kind: ElementKind) -> impl Iterator<Item = (usize, usize, [usize; 3])> {
    let ndof = kind.dofs_per_node();
    (0..8).flat_map(move |node| {
        (0..ndof).map(move |k| {
            let der = kind.derivative_of_dof(k);
            let pick = std::array::from_fn(|d| 2 * (node >> d & 1) + usize::from(der[d]));
            (node, k, pick)
        })
    })
}

/// `[φ₁⁰, φ₁¹, φ₂⁰, φ₂¹](p/q)` (or their derivatives) as integer numerators over one
/// denominator `q^e`: the same values as [`basis_exact`] / [`basis_derivative_exact`], not
/// reduced, so that the products of eq. (1) share the denominator `Π q_d^{e_d}`.
fn basis_scaled(b: Basis, t: &Rational, derivative: bool) -> ([BigInt; 4], BigInt) {
    let (p, q) = (t.numer(), t.denom());
    let z = BigInt::zero;
    match (b, derivative) {
        (Basis::LinearLagrange, false) => ([q - p, z(), p.clone(), z()], q.clone()),
        (Basis::LinearLagrange, true) => ([-BigInt::one(), z(), BigInt::one(), z()], BigInt::one()),
        (Basis::CubicHermite, false) => {
            let (p2, pq) = (p * p, p - q);
            (
                [
                    q * q * q - 3 * &p2 * q + 2 * &p2 * p,
                    p * &pq * &pq,
                    &p2 * (3 * q - 2 * p),
                    &p2 * &pq,
                ],
                q * q * q,
            )
        }
        (Basis::CubicHermite, true) => {
            let h: BigInt = 6 * p * p - 6 * p * q;
            (
                [h.clone(), (p - q) * (3 * p - q), -h, 3 * p * p - 2 * p * q],
                q * q,
            )
        }
    }
}

/// The terms of eq. (1) (or of `∂/∂ξ_d` when `derivative = Some(d)`) as integer weights over
/// one shared denominator: `φᵢᵏ(ξ) = W / D` for every returned `(node, dof, W)`, zero weights
/// left out. Sums of these terms need one division in all, not a gcd per operation.
pub(crate) fn terms_scaled(
    kind: ElementKind,
    xi: &[Rational; 3],
    derivative: Option<usize>,
) -> (Vec<Term<BigInt>>, BigInt) {
    let per_dir: [([BigInt; 4], BigInt); 3] =
        std::array::from_fn(|d| basis_scaled(kind.bases[d], &xi[d], derivative == Some(d)));
    let denominator = per_dir.iter().fold(BigInt::one(), |acc, (_, q)| acc * q);
    let out = term_indices(kind)
        .filter(|(_, _, i)| (0..3).all(|d| !per_dir[d].0[i[d]].is_zero()))
        .map(|(node, k, i)| {
            (
                node,
                k,
                &per_dir[0].0[i[0]] * &per_dir[1].0[i[1]] * &per_dir[2].0[i[2]],
            )
        })
        .collect();
    (out, denominator)
}

/// The terms `φᵢᵏ(ξ)` of eq. (1) exactly, or those of `∂/∂ξ_d` when `derivative = Some(d)`.
#[cfg(test)]
pub(crate) fn terms_exact(
    kind: ElementKind,
    xi: &[Rational; 3],
    derivative: Option<usize>,
) -> Vec<Term<Rational>> {
    let per_dir: [[Rational; 4]; 3] = std::array::from_fn(|d| {
        if derivative == Some(d) {
            basis_derivative_exact(kind.bases[d], &xi[d])
        } else {
            basis_exact(kind.bases[d], &xi[d])
        }
    });
    term_indices(kind)
        .map(|(node, k, i)| {
            (
                node,
                k,
                (0..3).fold(Rational::one(), |acc, d| acc * &per_dir[d][i[d]]),
            )
        })
        .filter(|(_, _, w)| !w.is_zero())
        .collect()
}

#[cfg(test)]
/// The terms of eq. (1) in `f64` (all `8 · dofs` of them, zero weights included), written
/// into `out`; returns how many.
pub(crate) fn terms_f64(
    kind: ElementKind,
    xi: [f64; 3],
    derivative: Option<usize>,
    out: &mut [(usize, usize, f64); 64],
) -> usize {
    let per_dir: [[f64; 4]; 3] = std::array::from_fn(|d| {
        if derivative == Some(d) {
            basis_derivative_f64(kind.bases[d], xi[d])
        } else {
            basis_f64(kind.bases[d], xi[d])
        }
    });
    let mut n = 0;
    for (node, k, i) in term_indices(kind) {
        out[n] = (
            node,
            k,
            per_dir[0][i[0]] * per_dir[1][i[1]] * per_dir[2][i[2]],
        );
        n += 1;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num::rational_to_f64;

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    #[test]
    fn hermite_interpolates_values_and_slopes() {
        let b = Basis::CubicHermite;
        // At the ends: values select the node's value, derivative functions vanish.
        assert_eq!(
            basis_exact(b, &q(0, 1)),
            [q(1, 1), q(0, 1), q(0, 1), q(0, 1)]
        );
        assert_eq!(
            basis_exact(b, &q(1, 1)),
            [q(0, 1), q(0, 1), q(1, 1), q(0, 1)]
        );
        // Slopes: H₁¹' = 1 at 0, H₂¹' = 1 at 1, the others 0.
        assert_eq!(
            basis_derivative_exact(b, &q(0, 1)),
            [q(0, 1), q(1, 1), q(0, 1), q(0, 1)]
        );
        assert_eq!(
            basis_derivative_exact(b, &q(1, 1)),
            [q(0, 1), q(0, 1), q(0, 1), q(1, 1)]
        );
        // A cubic is reproduced: u = ξ³ has u(0)=0, u'(0)=0, u(1)=1, u'(1)=3.
        for i in 0..=7 {
            let t = q(i, 7);
            let h = basis_exact(b, &t);
            let u = &h[2] + &h[3] * q(3, 1);
            assert_eq!(u, &t * &t * &t);
            let f = basis_f64(b, rational_to_f64(&t));
            assert!((f[2] + 3.0 * f[3] - rational_to_f64(&(&t * &t * &t))).abs() < 1e-15);
            let fd = basis_derivative_f64(b, rational_to_f64(&t));
            let ed = basis_derivative_exact(b, &t);
            for k in 0..4 {
                assert!((fd[k] - rational_to_f64(&ed[k])).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn scaled_terms_equal_the_rational_ones() {
        for kind in [
            ElementKind::TRILINEAR_LAGRANGE,
            ElementKind::TRICUBIC_HERMITE,
            ElementKind::HERMITE_HERMITE_LAGRANGE,
        ] {
            for xi in [
                [q(1, 3), q(2, 5), q(5, 7)],
                [q(0, 1), q(1, 1), q(-3, 8)],
                [q(7, 4), q(1, 2), q(1, 1)],
            ] {
                for derivative in [None, Some(0), Some(1), Some(2)] {
                    let (scaled, d) = terms_scaled(kind, &xi, derivative);
                    let scaled: Vec<(usize, usize, Rational)> = scaled
                        .into_iter()
                        .map(|(n, k, w)| (n, k, Rational::new(w, d.clone())))
                        .collect();
                    assert_eq!(
                        scaled,
                        terms_exact(kind, &xi, derivative),
                        "{}",
                        kind.name()
                    );
                }
            }
        }
    }

    #[test]
    fn partition_of_unity() {
        for kind in [
            ElementKind::TRILINEAR_LAGRANGE,
            ElementKind::TRICUBIC_HERMITE,
            ElementKind::HERMITE_HERMITE_LAGRANGE,
        ] {
            let xi = [q(1, 3), q(2, 5), q(5, 7)];
            let value_terms: Rational = terms_exact(kind, &xi, None)
                .into_iter()
                .filter(|(_, k, _)| *k == 0)
                .map(|(_, _, w)| w)
                .sum();
            assert_eq!(value_terms, q(1, 1), "{}", kind.name());
        }
    }
}
