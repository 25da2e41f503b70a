//! Sign certificates from the coefficients of one box.
//!
//! Bernstein polynomials form a partition of unity and are non-negative on the
//! box, so `min coefficient > 0 ⇒ p > 0` on the box (convex-hull property), and the
//! coefficient at a vertex equals the value at that vertex (endpoint interpolation).

use super::Bernstein;
use crate::num::{Field, Sign};

/// What one box's coefficients prove about `p > 0`.
#[derive(Clone, Debug, PartialEq)]
pub enum BoxSign<T> {
    /// Every coefficient is certainly positive: `p > 0` on the whole box.
    Positive,
    /// The vertex `corner` (bit a set: `t_a = 1`) has coefficient `value ≤ 0`: `p(vertex) = value`.
    NonPositiveVertex {
        /// The vertex, as a bit set (bit `a` set: `t_a = 1`).
        corner: usize,
        /// The vertex's coefficient, `p` at that vertex (`≤ 0`).
        value: T,
    },
    /// Neither: subdivide. `min` is the smallest coefficient (a lower bound of `p` on the box).
    Inconclusive {
        /// The smallest coefficient: a lower bound of `p` on the box.
        min: T,
    },
}

/// Classifies one box from its coefficients. For interval coefficients a vertex is only
/// reported when its coefficient is certainly `≤ 0`, and `Positive` only when all are
/// certainly `> 0`.
pub fn box_sign<T: Field>(p: &Bernstein<T>) -> BoxSign<T> {
    let corners = 1usize << p.dim();
    for corner in 0..corners {
        let v = p.vertex_coeff(corner);
        if matches!(v.sign(), Sign::Negative | Sign::Zero) {
            return BoxSign::NonPositiveVertex {
                corner,
                value: v.clone(),
            };
        }
    }
    if p.coeffs().iter().all(|c| c.sign() == Sign::Positive) {
        return BoxSign::Positive;
    }
    let mut min = p.coeffs()[0].clone();
    for c in p.coeffs() {
        if c.sub(&min).sign() == Sign::Negative {
            min = c.clone();
        }
    }
    BoxSign::Inconclusive { min }
}
