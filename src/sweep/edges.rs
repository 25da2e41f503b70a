//! Silhouettes along patch edges.
//!
//! A patch edge `u` or `v ∈ {0, 1}` can be a characteristic curve at every time: the moving
//! object's normal along the edge stays perpendicular to the edge's velocity (an axis-aligned
//! sphere's meridian edge under a translation across the meridian's plane, the usual CAD
//! layout). Then `F̃` vanishes identically on that face of the `(u, v, t)` box, so it is
//! exactly divisible by the face's factor: `F̃ = (1 − u)ᵏ F̂` (or `uᵏ`, `vᵏ`, `(1 − v)ᵏ`), and
//! `Z₁ = {F̃ = G̃ = 0}` is the union of
//!
//! * `{F̂ = G̃ = 0}`, traced as usual (its zeros inside the box are `F̃`'s), and
//! * on the face, the curve `{G̃ = 0}` in the face's free parameter `w` and `t`: one equation
//!   in two unknowns, traced by the same certified tracer with its own `t`-extreme points
//!   (where `∂G̃/∂w = 0` on it: there the curve's tangent has no `t` part).
//!
//! Traced on the undivided `F̃`, the face curve would lie on the box's boundary, where every
//! cross-section system has the identically zero equation `F̃|face`: the tracer gives up in
//! clusters. On a closed surface such an edge is shared by two patches; it is traced once
//! ([`same_edge`]: the same curve, homogeneous control points proportional, and normals
//! parallel along it, so that both patches' `G̃` have the same zeros there).
//!
//! Degenerate, and refused with the cause: `F̃ ≡ 0` on the whole patch (it moves within
//! itself, as a cylinder along its axis: the envelope is the swept surface, not a curve
//! family), and `G̃ ≡ 0` on a characteristic face (the whole swept edge is silhouette).

use super::scene::Patch;
use super::SweepError;
use crate::bernstein::Bernstein;
use crate::num::Rational;
use crate::solve::System;
use num_traits::Zero;

type B = Bernstein<Rational>;

/// The faces `(axis, upper)` with `axis ∈ {0, 1}` (`u`, `v`) on which `f` vanishes
/// identically, once per factor divided out, and `f` with those factors divided out.
/// Refused when `f ≡ 0` (the patch moves within itself).
pub(crate) fn characteristic_faces(
    f: &B,
    surface: usize,
    patch: usize,
) -> Result<(B, Vec<(usize, bool)>), SweepError> {
    if f.coeffs().iter().all(Zero::is_zero) {
        return Err(SweepError::CharacteristicPatch { surface, patch });
    }
    let mut f = f.clone();
    let mut faces = Vec::new();
    for axis in 0..2 {
        for upper in [false, true] {
            while let Some(q) = f.divide_by_face(axis, upper)? {
                f = q;
                faces.push((axis, upper));
            }
        }
    }
    Ok((f, faces))
}

/// The face curve's system `{G̃|face = 0}` in `(w, t)` on `[0, 1] × t_domain`; refused when
/// `G̃` vanishes on the whole face.
pub(crate) fn edge_system(
    g: &B,
    (axis, upper): (usize, bool),
    t_domain: &(Rational, Rational),
    surface: usize,
    patch: usize,
) -> Result<System, SweepError> {
    let face = g.face(axis, upper)?;
    if face.coeffs().iter().all(Zero::is_zero) {
        return Err(SweepError::SilhouetteCoversEdge {
            surface,
            patch,
            axis,
            upper,
        });
    }
    let unit = (Rational::zero(), Rational::from_integer(1.into()));
    Ok(System::new(vec![unit, t_domain.clone()], vec![face])?)
}

/// `(u, v, t)` of a point `(w, t)` of the face `(axis, upper)`.
pub(crate) fn face_point((axis, upper): (usize, bool), w: f64, t: f64) -> [f64; 3] {
    let fixed = if upper { 1.0 } else { 0.0 };
    if axis == 0 {
        [fixed, w, t]
    } else {
        [w, fixed, t]
    }
}

/// A characteristic edge as [`same_edge`] compares it: the patch's homogeneous curve on the
/// face and its normal there (both 1-D in the face's free parameter).
pub(crate) struct EdgeKey {
    surface: usize,
    curve: Vec<B>,
    normal: Vec<B>,
}

impl EdgeKey {
    /// The key of `patch`'s face `(axis, upper)` with homogeneous normal `normal` (in
    /// `(u, v)`).
    pub(crate) fn new(
        surface: usize,
        patch: &Patch,
        normal: &[B; 3],
        (axis, upper): (usize, bool),
    ) -> Result<EdgeKey, SweepError> {
        let face = |b: &B| b.face(axis, upper);
        Ok(EdgeKey {
            surface,
            curve: patch.hom.iter().map(face).collect::<Result<_, _>>()?,
            normal: normal.iter().map(face).collect::<Result<_, _>>()?,
        })
    }
}

/// Whether two characteristic edges are the same curve of the same surface with parallel
/// normals along it, exactly: homogeneous control points proportional (in the same or the
/// opposite parameter direction, after raising both to their common degree, so that a
/// degree-elevated copy of an edge is recognised) and the normals' cross product identically
/// zero. Edges that agree only after a rational reparametrisation are not recognised (then
/// the curve is reported by both patches).
pub(crate) fn same_edge(a: &EdgeKey, b: &EdgeKey) -> bool {
    if a.surface != b.surface {
        return false;
    }
    let Some((a_curve, b_curve)) = raised_together(&a.curve, &b.curve) else {
        return false;
    };
    [false, true].into_iter().any(|reverse| {
        let curve: Vec<B> = b_curve.iter().map(|p| reversed(p, reverse)).collect();
        let normal: Vec<B> = b.normal.iter().map(|p| reversed(p, reverse)).collect();
        proportional(&a_curve, &curve) && parallel(&a.normal, &normal)
    })
}

/// 1-D polynomials raised to the highest degree among them (`None` if one cannot be).
fn common_degree(ps: &[B]) -> Option<Vec<B>> {
    let top = ps.iter().map(|p| p.degrees()[0]).max()?;
    ps.iter()
        .map(|p| match top - p.degrees()[0] {
            0 => Some(p.clone()),
            by => p.elevate(0, by).ok(),
        })
        .collect()
}

/// Two lists of 1-D polynomials, all raised to the highest degree among them.
fn raised_together(a: &[B], b: &[B]) -> Option<(Vec<B>, Vec<B>)> {
    let mut both: Vec<B> = a.iter().chain(b).cloned().collect();
    both = common_degree(&both)?;
    let b_part = both.split_off(a.len());
    Some((both, b_part))
}

/// A 1-D Bernstein polynomial in `1 − w` for `w` (its coefficients reversed) when `reverse`.
fn reversed(p: &B, reverse: bool) -> B {
    if !reverse {
        return p.clone();
    }
    let mut c = p.coeffs().to_vec();
    c.reverse();
    Bernstein::new(p.degrees().to_vec(), c).expect("same degrees and count")
}

/// Whether `a = λ b` for one rational `λ ≠ 0`, all polynomials at the same degrees.
fn proportional(a: &[B], b: &[B]) -> bool {
    if a.len() != b.len() || a.iter().zip(b).any(|(p, q)| p.degrees() != q.degrees()) {
        return false;
    }
    let pairs = || {
        a.iter()
            .zip(b)
            .flat_map(|(p, q)| p.coeffs().iter().zip(q.coeffs()))
    };
    let Some((x, y)) = pairs().find(|(x, y)| !x.is_zero() || !y.is_zero()) else {
        return false;
    };
    if x.is_zero() || y.is_zero() {
        return false;
    }
    let lambda = x / y;
    pairs().all(|(x, y)| *x == &lambda * y)
}

/// Whether `a × b ≡ 0` (3-vectors of 1-D polynomials), exactly (each pair of products
/// compared at a common degree, so the vectors' own degrees need not agree).
fn parallel(a: &[B], b: &[B]) -> bool {
    (0..3).all(|i| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        match (a[j].product(&b[k]), a[k].product(&b[j])) {
            (Ok(p), Ok(q)) => common_degree(&[p, q]).is_some_and(|pq| pq[0] == pq[1]),
            _ => false,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(c: &[i64]) -> B {
        Bernstein::new(
            vec![c.len() - 1],
            c.iter()
                .map(|&x| Rational::from_integer(x.into()))
                .collect(),
        )
        .unwrap()
    }

    /// Proportional curves in either direction and parallel normals make the same edge; a
    /// non-constant factor, another surface or a turned normal do not.
    #[test]
    fn same_edge_is_exact_proportionality_and_parallel_normals() {
        let key = |surface, curve: [&[i64]; 4], normal: [&[i64]; 3]| EdgeKey {
            surface,
            curve: curve.iter().map(|c| line(c)).collect(),
            normal: normal.iter().map(|c| line(c)).collect(),
        };
        let a = key(
            0,
            [&[1, 2, 0], &[0, 1, 2], &[3, 3, 3], &[1, 1, 2]],
            [&[1, 0], &[0, 1], &[2, 2]],
        );
        // Twice the control points, reversed; the normal reversed and tripled.
        let b = key(
            0,
            [&[0, 4, 2], &[4, 2, 0], &[6, 6, 6], &[4, 2, 2]],
            [&[0, 3], &[3, 0], &[6, 6]],
        );
        assert!(same_edge(&a, &b));
        assert!(same_edge(&b, &a));
        let other_surface = key(
            1,
            [&[1, 2, 0], &[0, 1, 2], &[3, 3, 3], &[1, 1, 2]],
            [&[1, 0], &[0, 1], &[2, 2]],
        );
        assert!(!same_edge(&a, &other_surface));
        let turned = key(
            0,
            [&[1, 2, 0], &[0, 1, 2], &[3, 3, 3], &[1, 1, 2]],
            [&[1, 0], &[0, 1], &[2, 3]],
        );
        assert!(!same_edge(&a, &turned));
        let moved = key(
            0,
            [&[1, 2, 1], &[0, 1, 2], &[3, 3, 3], &[1, 1, 2]],
            [&[1, 0], &[0, 1], &[2, 2]],
        );
        assert!(!same_edge(&a, &moved));
        // The same edge at degree 3 (elevated once: the same curve) with its normal at
        // degree 2 is recognised; the elevated copy of the moved edge is not.
        let elevated = |k: &EdgeKey| EdgeKey {
            surface: k.surface,
            curve: k.curve.iter().map(|p| p.elevate(0, 1).unwrap()).collect(),
            normal: k.normal.iter().map(|p| p.elevate(0, 1).unwrap()).collect(),
        };
        assert!(same_edge(&a, &elevated(&b)));
        assert!(same_edge(&elevated(&a), &b));
        assert!(!same_edge(&a, &elevated(&moved)));
        assert!(!same_edge(&a, &elevated(&turned)));
    }

    /// A polynomial vanishing on faces is divided by each factor as often as it divides, and
    /// `F ≡ 0` is refused.
    #[test]
    fn characteristic_faces_divide_every_factor() {
        // (1 − u)² · v · (1 + u + v) in Bernstein form at degrees (3, 2): built by products.
        let b2 = |c: [i64; 4], d: [usize; 2]| {
            Bernstein::new(
                d.to_vec(),
                c.iter()
                    .map(|&x| Rational::from_integer(x.into()))
                    .collect(),
            )
            .unwrap()
        };
        let one_minus_u = b2([1, 0, 1, 0], [1, 1]);
        let v = b2([0, 0, 1, 1], [1, 1]);
        let rest = b2([1, 2, 2, 3], [1, 1]);
        let f = one_minus_u
            .product(&one_minus_u)
            .unwrap()
            .product(&v)
            .unwrap()
            .product(&rest)
            .unwrap();
        let (q, faces) = characteristic_faces(&f, 0, 0).unwrap();
        assert_eq!(faces, vec![(0, true), (0, true), (1, false)]);
        assert_eq!(q.at_exact_degrees(), rest.at_exact_degrees());
        let zero = Bernstein::constant(vec![2, 2], Rational::zero());
        assert!(matches!(
            characteristic_faces(&zero, 3, 4),
            Err(SweepError::CharacteristicPatch {
                surface: 3,
                patch: 4
            })
        ));
    }
}
