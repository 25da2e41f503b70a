//! Silhouettes through patch corners.
//!
//! A component of `Z₁ = {F̂ = G̃ = 0}` that passes through a corner line `(u, v) = c` of the
//! `(u, v, t)` box crosses the box's boundary on an edge, where two faces meet. The tracer
//! finds curve points on faces by solving each face's two equations, and a root on the
//! face's own border cannot be certified there: the tracer leaves a small cluster at the
//! corner, and the component arrives in pieces that end in clusters on the patches meeting
//! there.
//!
//! Such a crossing is found and certified exactly here:
//!
//! * **where:** the times at which `Z₁` meets the corner line are the common roots of the
//!   univariate `F̂(c, t)` and `G̃(c, t)`, the roots of their gcd (exact, over the
//!   rationals), isolated by the solver on its square-free part;
//! * **what is near it:** the cluster box `B` around the corner point `P` is *regular* (one
//!   Jacobian minor of `F̂, G̃` of one strict sign on `B`: `Z₁ ∩ B` is a union of arcs with
//!   ends on `∂B`, no loops); on each face of `B` inside the patch the certified crossings are
//!   counted, and on the two faces on the patch border (`u = c_u`, `v = c_v`) `P` is the only
//!   curve point: the face's two equations, extended across the border to a box twice as
//!   wide with `P` in its middle, have exactly one certified root there, and `P` is a root.
//!   With one inner crossing `Q`, `Z₁ ∩ B` is one arc from `Q` to `P` (the piece ending in
//!   the cluster continues to the corner); with none it is `P` alone (the curve only touches
//!   this patch at its corner).
//!
//! The pieces then end on the patch edge at `P` and are joined across the patches like any
//! other edge crossing. [`verify_corner_crossing`](super::verify_corner_crossing) redoes the
//! certification from the scene.

use super::SweepError;
use crate::bernstein::univariate::{div_rem, gcd, trimmed};
use crate::bernstein::Bernstein;
use crate::num::{Interval, Rational};
use crate::solve::{solve, CurveEnd, Curves, RationalBox, SolveOptions, System};
use crate::Path;
use num_traits::{One, Signed, Zero};

type B = Bernstein<Rational>;

/// An interval of the unit time `s`.
type Interval01 = (Rational, Rational);

/// A certified passage of the silhouette through a patch corner (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct CornerCrossing {
    /// The surface.
    pub surface: usize,
    /// The patch.
    pub patch: usize,
    /// The corner: `u = 1` when `corner[0]`, else `u = 0`; `v` likewise.
    pub corner: [bool; 2],
    /// An isolating interval (in the scene's `t`) of the time at which `Z₁` passes through
    /// the corner: it holds exactly one root of `gcd(F̂(c, t), G̃(c, t))`.
    pub t: (Rational, Rational),
    /// The box `B` in `(u, v, t)` (the scene's `t`) in which `Z₁` is certified.
    pub bounds: RationalBox,
    /// The unknown (0 = u, 1 = v, 2 = t) along which the curve's tangent has one strict sign
    /// on `B`.
    pub monotone_axis: usize,
    /// `Z₁ ∩ B`: one arc from an inner face of `B` to the corner point (1), or the corner
    /// point alone (0).
    pub arcs: usize,
}

/// The univariate restriction of a 3-D polynomial in `(u, v, s)` to the corner line
/// `(u, v) = corner`, as power-basis coefficients in `s`.
fn on_corner_line(p: &B, corner: [bool; 2]) -> Result<Vec<Rational>, SweepError> {
    Ok(p.face(0, corner[0])?.face(0, corner[1])?.to_power())
}

/// `1` at the upper end of `[0, 1]`, else `0`.
fn end(upper: bool) -> Rational {
    if upper {
        Rational::one()
    } else {
        Rational::zero()
    }
}

/// Refuses a patch on one of whose corner lines `F̂` and `G̃` both vanish identically (the
/// silhouette stays on that corner at every time), before any tracing.
pub(crate) fn check_corner_lines(
    f: &B,
    g: &B,
    surface: usize,
    patch: usize,
) -> Result<(), SweepError> {
    for corner in [[false, false], [true, false], [false, true], [true, true]] {
        let zero = |p: &B| -> Result<bool, SweepError> {
            Ok(p.face(0, corner[0])?
                .face(0, corner[1])?
                .coeffs()
                .iter()
                .all(Zero::is_zero))
        };
        if zero(f)? && zero(g)? {
            return Err(SweepError::SilhouetteAlongCorner {
                surface,
                patch,
                corner,
            });
        }
    }
    Ok(())
}

/// Isolating intervals, in the unit time `s ∈ (0, 1)`, of the times at which `Z₁` meets the
/// corner line `corner`: the roots of `gcd(F̂(c, s), G̃(c, s))` (module docs). Refused when both
/// vanish on the whole line (the silhouette runs along the corner).
pub(crate) fn corner_times(
    f: &B,
    g: &B,
    corner: [bool; 2],
    surface: usize,
    patch: usize,
) -> Result<Vec<(Rational, Rational)>, SweepError> {
    let (p, q) = (
        trimmed(on_corner_line(f, corner)?),
        trimmed(on_corner_line(g, corner)?),
    );
    if p.is_empty() && q.is_empty() {
        return Err(SweepError::SilhouetteAlongCorner {
            surface,
            patch,
            corner,
        });
    }
    let common = gcd(&p, &q);
    if common.len() <= 1 {
        return Ok(Vec::new());
    }
    let solution = square_free_roots(&common, Path::Exact)?;
    // A root at s = 0 or 1 (on the start or end position) is not certified by the 1-D solve
    // and is left to the tracer.
    Ok(solution
        .roots
        .into_iter()
        .map(|r| r.bounds[0].clone())
        .filter(|(lo, hi)| lo.is_positive() && hi < &Rational::one())
        .collect())
}

/// `p` along `axis` re-expressed over `[lo, hi]` (any `lo < hi`, also beyond `[0, 1]`): de
/// Casteljau's algorithm extrapolates exactly.
pub(crate) fn reframed(p: &B, axis: usize, lo: &Rational, hi: &Rational) -> Result<B, SweepError> {
    let left = p.split(axis, hi)?.0;
    Ok(left.split(axis, &(lo / hi))?.1)
}

/// Whether every coefficient has one strict sign.
fn strictly_signed(p: &B) -> bool {
    let c = p.coeffs();
    c.iter().all(Signed::is_positive) || c.iter().all(Signed::is_negative)
}

/// The certified roots of the square system `eqs` on the unit box, or `None` when the solve
/// left a cluster.
fn roots_on_unit_box(eqs: Vec<B>) -> Result<Option<usize>, SweepError> {
    let n = eqs.first().map_or(0, B::dim);
    let unit = (Rational::zero(), Rational::one());
    let system = System::new(vec![unit; n], eqs)?;
    // (A root on the box's boundary stays a cluster: this counts the roots inside.)
    let opts = SolveOptions::new()
        .with_path(Path::Filtered)
        .with_boundary(false);
    let sol = solve(&system, &opts)?;
    Ok(sol.clusters.is_empty().then_some(sol.roots.len()))
}

/// The axis along which the curve's tangent (the minor of `F̂, G̃`'s Jacobian without that
/// column) has one strict sign on the box `bounds` (unit coordinates): decided in rigorous
/// intervals, and in exact integers over one denominator where those do not decide.
fn regular_axis(
    f: &B,
    g: &B,
    bounds: &[(Rational, Rational)],
) -> Result<Option<usize>, SweepError> {
    use crate::bernstein::ScaledBernstein;
    let iv: Vec<(Interval, Interval)> = bounds
        .iter()
        .map(|(a, b)| (Interval::from_rational(a), Interval::from_rational(b)))
        .collect();
    let (fi, gi) = (
        f.map(Interval::from_rational).restrict(&iv)?,
        g.map(Interval::from_rational).restrict(&iv)?,
    );
    let minor_iv = |k: usize| -> Result<Bernstein<Interval>, SweepError> {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let p = fi.derivative(i)?.product(&gi.derivative(j)?)?;
        let q = fi.derivative(j)?.product(&gi.derivative(i)?)?;
        Ok(p.add_elevated(&q.scale(&Interval::point(-1.0)))?)
    };
    for k in 0..3 {
        let c = minor_iv(k)?;
        if c.coeffs().iter().all(|x| x.lo > 0.0) || c.coeffs().iter().all(|x| x.hi < 0.0) {
            return Ok(Some(k));
        }
    }
    let (fe, ge) = (
        ScaledBernstein::from_rational(&f.restrict(bounds)?),
        ScaledBernstein::from_rational(&g.restrict(bounds)?),
    );
    for k in 0..3 {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let p = fe.derivative(i)?.product(&ge.derivative(j)?)?;
        let q = fe.derivative(j)?.product(&ge.derivative(i)?)?;
        let minor = if p.degrees() == q.degrees() {
            p.sub(&q)?.to_rational()
        } else {
            p.to_rational()
                .add_elevated(&q.to_rational().scale(&-Rational::one()))?
        };
        if strictly_signed(&minor) {
            return Ok(Some(k));
        }
    }
    Ok(None)
}

/// Certifies `Z₁ ∩ B` for the box `bounds` (unit `(u, v, s)`) at the corner `corner`, whose
/// crossing time lies in `t` (unit `s`, strictly inside `bounds[2]`): `Some((monotone axis,
/// arcs))` (module docs), or `None` when a step does not hold.
pub(crate) fn certify_corner_box(
    f: &B,
    g: &B,
    corner: [bool; 2],
    t: &(Rational, Rational),
    bounds: &[(Rational, Rational)],
) -> Result<Option<(usize, usize)>, SweepError> {
    // The corner line is an edge of B, and the crossing time inside B's time range.
    for axis in 0..2 {
        let (lo, hi) = &bounds[axis];
        let c = end(corner[axis]);
        if !(lo < hi && (if corner[axis] { hi == &c } else { lo == &c })) {
            return Ok(None);
        }
    }
    if !(bounds[2].0 < t.0 && t.1 < bounds[2].1) {
        return Ok(None);
    }
    let Some(monotone) = regular_axis(f, g, bounds)? else {
        return Ok(None);
    };
    // Crossings on B's faces inside the patch: the faces opposite the corner in u and v, and
    // both time faces; each face's equations over the face's rectangle.
    let mut inner = 0;
    for (axis, upper) in [(0, !corner[0]), (1, !corner[1]), (2, false), (2, true)] {
        let x = if upper {
            &bounds[axis].1
        } else {
            &bounds[axis].0
        };
        let rest: Vec<(Rational, Rational)> = (0..3)
            .filter(|&k| k != axis)
            .map(|k| bounds[k].clone())
            .collect();
        let plane = |p: &B| -> Result<B, SweepError> {
            Ok(p.eval_axis(axis, x)?.face(axis, false)?.restrict(&rest)?)
        };
        let Some(n) = roots_on_unit_box(vec![plane(f)?, plane(g)?])? else {
            return Ok(None);
        };
        inner += n;
    }
    // On the two faces on the patch border the corner point is the only curve point: each
    // face's equations over a box twice B's width across the border, the corner in its
    // middle, have exactly one root.
    for axis in 0..2 {
        let other = 1 - axis;
        let (f2, g2) = (f.face(axis, corner[axis])?, g.face(axis, corner[axis])?);
        let (lo, hi) = &bounds[other];
        let w = hi - lo;
        let c = end(corner[other]);
        let (a, b) = (&c - &w, &c + &w);
        // The face polynomials are in (other, s): `other` is axis 0 there.
        let s = &bounds[2];
        let frame =
            |p: &B| -> Result<B, SweepError> { reframed(&reframed(p, 0, &a, &b)?, 1, &s.0, &s.1) };
        if roots_on_unit_box(vec![frame(&f2)?, frame(&g2)?])? != Some(1) {
            return Ok(None);
        }
    }
    Ok((inner <= 1).then_some((monotone, inner)))
}

/// The patch corner a cluster hull sits on (unit `(u, v, …)`): the corner whose `u` and `v`
/// ends the hull reaches, each at exactly one end of `[0, 1]`.
fn corner_of_hull(hull: &[(Rational, Rational)]) -> Option<[bool; 2]> {
    let at_end = |k: usize| -> Option<bool> {
        let (lo, hi) = &hull[k];
        match (lo.is_zero(), hi.is_one()) {
            (true, false) => Some(false),
            (false, true) => Some(true),
            _ => None,
        }
    };
    Some([at_end(0)?, at_end(1)?])
}

/// How many ends of traced pieces lie in the cluster group `group`.
fn entering(curves: &Curves, group: usize) -> usize {
    curves
        .components
        .iter()
        .flat_map(|c| &c.ends)
        .filter(|e| matches!(e, CurveEnd::Cluster { group: g, .. } if *g == group))
        .count()
}

/// The cluster groups of a patch's trace (`system`: `F̂, G̃` on `[0,1]² × [a, b]`) that sit on a
/// corner line and are certified as a passage through the corner there: `(group,
/// crossing)`. A group qualifies when its boxes' hull has the corner line as an edge, exactly
/// one corner time lies strictly inside its time range, the hull is certified
/// ([`certify_corner_box`]) and the pieces of the trace that end in the group are as many as
/// the arcs certified.
pub(crate) fn resolve_corners(
    system: &System,
    curves: &Curves,
    surface: usize,
    patch: usize,
) -> Result<Vec<(usize, CornerCrossing)>, SweepError> {
    let (f, g) = (&system.equations[0], &system.equations[1]);
    let mut times: Vec<([bool; 2], Vec<Interval01>)> = Vec::new();
    let mut out = Vec::new();
    for (group, members) in curves.cluster_groups.iter().enumerate() {
        // The hull in unit coordinates.
        let mut hull: Vec<(Rational, Rational)> = Vec::new();
        for &m in members {
            for (k, (lo, hi)) in curves.clusters[m].bounds.iter().enumerate() {
                let (lo, hi) = (system.to_unit(k, lo), system.to_unit(k, hi));
                match hull.get_mut(k) {
                    None => hull.push((lo, hi)),
                    Some(h) => {
                        if lo < h.0 {
                            h.0 = lo;
                        }
                        if hi > h.1 {
                            h.1 = hi;
                        }
                    }
                }
            }
        }
        let Some(corner) = corner_of_hull(&hull) else {
            continue;
        };
        if !times.iter().any(|(c, _)| *c == corner) {
            times.push((corner, corner_times(f, g, corner, surface, patch)?));
        }
        let all = &times.iter().find(|(c, _)| *c == corner).expect("cached").1;
        let inside: Vec<&(Rational, Rational)> = all
            .iter()
            .filter(|(lo, hi)| hull[2].0 < *lo && *hi < hull[2].1)
            .collect();
        let [t] = inside.as_slice() else { continue };
        let Some((monotone_axis, arcs)) = certify_corner_box(f, g, corner, t, &hull)? else {
            continue;
        };
        if entering(curves, group) != arcs {
            continue;
        }
        let domain_t =
            |x: &Rational| crate::num::rational::lerp(&system.domain[2].0, &system.domain[2].1, x);
        out.push((
            group,
            CornerCrossing {
                surface,
                patch,
                corner,
                t: (domain_t(&t.0), domain_t(&t.1)),
                bounds: {
                    let (lo, hi): (Vec<Rational>, Vec<Rational>) = hull.iter().cloned().unzip();
                    system.domain_box(&lo, &hi)
                },
                monotone_axis,
                arcs,
            },
        ));
    }
    Ok(out)
}

/// A certified passage of an end position's contour (a cap, `G̃(u, v, a or b) = 0`) through
/// a patch corner: the 2-D analogue of [`CornerCrossing`]. `G̃` vanishes exactly at the corner
/// point; on the tracer's cluster box `B` there one partial derivative has one strict sign (so
/// the contour in `B` is a union of arcs with ends on `∂B`, no loops); the crossings on `B`'s
/// two inner edges are counted; on its two edges on the patch border the corner is the only
/// zero (each edge extended across the border to twice `B`'s width, one certified root). With
/// one inner crossing the contour in `B` is one arc from it to the corner; with none, the
/// corner alone.
#[derive(Clone, Debug, PartialEq)]
pub struct CapCornerPassage {
    /// The surface.
    pub surface: usize,
    /// The patch.
    pub patch: usize,
    /// The end position: `t = b` when set, else `t = a`.
    pub upper: bool,
    /// The corner: `u = 1` when `corner[0]`, else `u = 0`; `v` likewise.
    pub corner: [bool; 2],
    /// The box `B` in `(u, v)`.
    pub bounds: RationalBox,
    /// The parameter (0 = u, 1 = v) along which `G̃`'s partial derivative has one strict sign
    /// on `B`.
    pub monotone_axis: usize,
    /// The contour in `B`: one arc to the corner (1) or the corner alone (0).
    pub arcs: usize,
}

/// Certifies a cap's passage through `corner` on the box `bounds` (unit `(u, v)`, the corner
/// a vertex of it): `Some((monotone axis, arcs))` ([`CapCornerPassage`]), or `None` when a
/// step does not hold.
pub(crate) fn certify_cap_corner_box(
    g: &B,
    corner: [bool; 2],
    bounds: &[(Rational, Rational)],
) -> Result<Option<(usize, usize)>, SweepError> {
    if bounds.len() != 2 || g.dim() != 2 {
        return Ok(None);
    }
    for axis in 0..2 {
        let (lo, hi) = &bounds[axis];
        let c = end(corner[axis]);
        if !(lo < hi && (if corner[axis] { hi == &c } else { lo == &c })) {
            return Ok(None);
        }
    }
    // The corner point is on the contour, exactly.
    if !g.face(0, corner[0])?.face(0, corner[1])?.coeffs()[0].is_zero() {
        return Ok(None);
    }
    let part = g.restrict(bounds)?;
    let Some(monotone) = (0..2).find(|&k| {
        part.derivative(k)
            .map(|d| strictly_signed(&d))
            .unwrap_or(false)
    }) else {
        return Ok(None);
    };
    // Crossings on the two inner edges (opposite the corner).
    let mut inner = 0;
    for axis in 0..2 {
        let other = 1 - axis;
        let x = if corner[axis] {
            &bounds[axis].0
        } else {
            &bounds[axis].1
        };
        let edge = g
            .eval_axis(axis, x)?
            .face(axis, false)?
            .restrict(std::slice::from_ref(&bounds[other]))?;
        let Some(n) = roots_on_unit_box(vec![edge])? else {
            return Ok(None);
        };
        inner += n;
    }
    // On the two border edges the corner is the only zero: each edge polynomial over twice
    // B's width across the border, the corner in its middle, has exactly one root.
    for axis in 0..2 {
        let other = 1 - axis;
        let edge = g.face(axis, corner[axis])?;
        let (lo, hi) = &bounds[other];
        let w = hi - lo;
        let c = end(corner[other]);
        if roots_on_unit_box(vec![reframed(&edge, 0, &(&c - &w), &(&c + &w))?])? != Some(1) {
            return Ok(None);
        }
    }
    Ok((inner <= 1).then_some((monotone, inner)))
}

/// The cluster groups of a cap's trace (`system`: `G̃(·, ·, a or b)` on `[0,1]²`) that sit on a
/// patch corner and are certified as a passage through it ([`certify_cap_corner_box`] on the
/// group's hull, as many pieces ending in the group as arcs certified): `(group, passage)`.
pub(crate) fn resolve_cap_corners(
    system: &System,
    curves: &Curves,
    surface: usize,
    patch: usize,
    upper: bool,
) -> Result<Vec<(usize, CapCornerPassage)>, SweepError> {
    let g = &system.equations[0];
    certified_groups(curves, |hull| {
        let Some(corner) = corner_of_hull(&hull) else {
            return Ok(None);
        };
        Ok(
            certify_cap_corner_box(g, corner, &hull)?.map(|(monotone_axis, arcs)| {
                let passage = CapCornerPassage {
                    surface,
                    patch,
                    upper,
                    corner,
                    bounds: hull,
                    monotone_axis,
                    arcs,
                };
                (passage, arcs)
            }),
        )
    })
}

/// The cluster groups of a cap's trace whose boxes' hull `certify` certifies, with as many
/// traced pieces ending in the group as the arcs it counts: `(group, what it certified)`.
fn certified_groups<T>(
    curves: &Curves,
    mut certify: impl FnMut(Vec<(Rational, Rational)>) -> Result<Option<(T, usize)>, SweepError>,
) -> Result<Vec<(usize, T)>, SweepError> {
    let mut out = Vec::new();
    for (group, members) in curves.cluster_groups.iter().enumerate() {
        let hull = hull_of(members.iter().map(|&m| &curves.clusters[m].bounds));
        if let Some((x, arcs)) = certify(hull)? {
            if entering(curves, group) == arcs {
                out.push((group, x));
            }
        }
    }
    Ok(out)
}

/// A certified touch of an end position's contour (a cap, `G̃(u, v, a or b) = 0`) on a patch
/// border away from the corners: the contour meets the border `border` at one point, where
/// the border polynomial `e(w) = G̃` on that border has a multiple root (the contour is
/// tangent to the border there, or crosses it with a tangency of higher order), which the
/// tracer cannot certify and leaves as a cluster. Certified on the cluster box `B`:
///
/// * `G̃`'s partial derivative across the border has one strict sign on `B`, so in `B` the
///   contour is the graph of a function of the parameter along the border, over the set
///   where `G̃` on the border and on `B`'s inner edge differ in sign;
/// * on `B`'s inner edge `G̃` has no zero, and on its span along the border `e` has exactly
///   one distinct zero, strictly inside (one root of `e`'s square-free part, exact gcd):
///   the touch point `P`;
/// * so each of `B`'s two side edges carries a crossing exactly when `e` at its end differs
///   in sign from the inner edge, and each such crossing is joined to `P` by one arc.
///
/// `arcs` counts those arcs: 2 when the contour touches the border from this patch's side
/// (the two arcs meet at `P`), 1 when it crosses into the neighbour at `P`, 0 when it only
/// touches this patch at `P` (it lies on the neighbour's side).
#[derive(Clone, Debug, PartialEq)]
pub struct CapBorderTouch {
    /// The surface.
    pub surface: usize,
    /// The patch.
    pub patch: usize,
    /// The end position: `t = b` when set, else `t = a`.
    pub upper: bool,
    /// The border: `(axis, upper)`, the parameter (0 = u, 1 = v) fixed at its upper end
    /// (`1`) when `upper`, else at `0`.
    pub border: (usize, bool),
    /// An isolating interval of the touch point's parameter along the border: it holds the
    /// one distinct root of `e` in `B`'s span.
    pub along: (Rational, Rational),
    /// The box `B` in `(u, v)`.
    pub bounds: RationalBox,
    /// Arcs of the contour in `B` ending at the touch point: 0, 1 or 2.
    pub arcs: usize,
}

/// The sign of a non-zero rational (`None` for zero).
fn sign_of(x: &Rational) -> Option<bool> {
    (!x.is_zero()).then(|| x.is_positive())
}

/// The isolating intervals (in `[0, 1]`) of the distinct roots of the univariate `e`
/// (Bernstein on the unit interval, not identically zero): the roots of its square-free part
/// (exact gcd with its derivative), certified by the solver; `None` when the solve left a
/// cluster.
fn distinct_roots(e: &B) -> Result<Option<Vec<Interval01>>, SweepError> {
    let p = trimmed(e.to_power());
    if p.len() <= 1 {
        return Ok(Some(Vec::new()));
    }
    let solution = square_free_roots(&p, Path::Filtered)?;
    Ok(solution.clusters.is_empty().then(|| {
        solution
            .roots
            .into_iter()
            .map(|r| r.bounds[0].clone())
            .collect()
    }))
}

/// The solver's answer on `[0, 1]` for the square-free part of the univariate `p` (power
/// basis, trimmed, of degree at least 1): `p` divided by its exact gcd with `p′`, so every
/// root is simple and certifiable; root boxes to `1e-12`.
fn square_free_roots(p: &[Rational], path: Path) -> Result<crate::solve::Solution, SweepError> {
    let derivative: Vec<Rational> = p
        .iter()
        .enumerate()
        .skip(1)
        .map(|(k, c)| c * Rational::from_integer(k.into()))
        .collect();
    let square_free = div_rem(p, &gcd(p, &derivative)).0;
    let degree = square_free.len() - 1;
    let unit = (Rational::zero(), Rational::one());
    let system = System::new(
        vec![unit],
        vec![Bernstein::from_power(vec![degree], square_free)?],
    )?;
    Ok(solve(
        &system,
        &SolveOptions::new()
            .with_path(path)
            .with_tolerance(1e-12)
            .with_boundary(false),
    )?)
}

/// Certifies a cap's touch on `border` in the box `bounds` (unit `(u, v)`: on the border in
/// its axis, strictly inside the patch in the other): `Some((along, arcs))`
/// ([`CapBorderTouch`]), or `None` when a step does not hold.
pub(crate) fn certify_cap_border_box(
    g: &B,
    border: (usize, bool),
    bounds: &[(Rational, Rational)],
) -> Result<Option<(Interval01, usize)>, SweepError> {
    let (k, upper) = border;
    if bounds.len() != 2 || g.dim() != 2 || k > 1 {
        return Ok(None);
    }
    let o = 1 - k;
    let ((klo, khi), (lo, hi)) = (&bounds[k], &bounds[o]);
    let c = end(upper);
    let on_border = if upper { khi == &c } else { klo == &c };
    if !(klo < khi && on_border && lo.is_positive() && lo < hi && hi < &Rational::one()) {
        return Ok(None);
    }
    // Monotone across the border.
    if !strictly_signed(&g.restrict(bounds)?.derivative(k)?) {
        return Ok(None);
    }
    // The border polynomial over B's span, in a unit parameter.
    let e = reframed(&g.face(k, upper)?, 0, lo, hi)?;
    let (first, last) = (&e.coeffs()[0], e.coeffs().last().expect("non-empty"));
    let (Some(e_lo), Some(e_hi)) = (sign_of(first), sign_of(last)) else {
        return Ok(None);
    };
    let Some(roots) = distinct_roots(&e)? else {
        return Ok(None);
    };
    let [(s_lo, s_hi)] = roots.as_slice() else {
        return Ok(None);
    };
    // The inner edge: no zero, and its sign.
    let inner_x = if upper { klo } else { khi };
    let inner = g
        .eval_axis(k, inner_x)?
        .face(k, false)?
        .restrict(std::slice::from_ref(&bounds[o]))?;
    if !strictly_signed(&inner) && roots_on_unit_box(vec![inner.clone()])? != Some(0) {
        return Ok(None);
    }
    // Its sign, the same at both ends (a zero at an end, on a corner of B, is refused).
    let ends = (
        sign_of(&inner.coeffs()[0]),
        sign_of(inner.coeffs().last().expect("non-empty")),
    );
    let (Some(sigma), Some(other)) = ends else {
        return Ok(None);
    };
    if sigma != other {
        return Ok(None);
    }
    let arcs = usize::from(e_lo != sigma) + usize::from(e_hi != sigma);
    let along = (
        crate::num::rational::lerp(lo, hi, s_lo),
        crate::num::rational::lerp(lo, hi, s_hi),
    );
    Ok(Some((along, arcs)))
}

/// The border a cluster hull sits on away from the corners (unit `(u, v)`): `(axis, upper)`
/// when the hull reaches exactly one end of `[0, 1]` in one parameter and neither end in the
/// other.
fn border_of_hull(hull: &[(Rational, Rational)]) -> Option<(usize, bool)> {
    let at_end = |k: usize| -> Option<Option<bool>> {
        let (lo, hi) = &hull[k];
        match (lo.is_zero(), hi.is_one()) {
            (true, false) => Some(Some(false)),
            (false, true) => Some(Some(true)),
            (false, false) => Some(None),
            (true, true) => None,
        }
    };
    match (at_end(0)?, at_end(1)?) {
        (Some(upper), None) => Some((0, upper)),
        (None, Some(upper)) => Some((1, upper)),
        _ => None,
    }
}

/// The cluster groups of a cap's trace (as [`resolve_cap_corners`]) that sit on a patch
/// border away from the corners and are certified as a touch there
/// ([`certify_cap_border_box`] on the group's hull, as many pieces ending in the group as
/// arcs certified): `(group, touch)`.
pub(crate) fn resolve_cap_borders(
    system: &System,
    curves: &Curves,
    surface: usize,
    patch: usize,
    upper: bool,
) -> Result<Vec<(usize, CapBorderTouch)>, SweepError> {
    let g = &system.equations[0];
    certified_groups(curves, |hull| {
        let Some(border) = border_of_hull(&hull) else {
            return Ok(None);
        };
        Ok(
            certify_cap_border_box(g, border, &hull)?.map(|(along, arcs)| {
                let touch = CapBorderTouch {
                    surface,
                    patch,
                    upper,
                    border,
                    along,
                    bounds: hull,
                    arcs,
                };
                (touch, arcs)
            }),
        )
    })
}

/// The hull of boxes (the cap's domain is the unit square, so domain and unit coordinates
/// agree).
fn hull_of<'a>(boxes: impl Iterator<Item = &'a RationalBox>) -> Vec<(Rational, Rational)> {
    let mut hull: Vec<(Rational, Rational)> = Vec::new();
    for b in boxes {
        for (k, (lo, hi)) in b.iter().enumerate() {
            match hull.get_mut(k) {
                None => hull.push((lo.clone(), hi.clone())),
                Some(h) => {
                    if *lo < h.0 {
                        h.0 = lo.clone();
                    }
                    if *hi > h.1 {
                        h.1 = hi.clone();
                    }
                }
            }
        }
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    /// `G = ±u − (v − ½)^m` on a box at the border `u = 0` around `v = ½`: the contour
    /// `u = (v − ½)²` touches the border from inside (two arcs meet there), `−u = (v − ½)²`
    /// only touches this side at the point (none), `u = (v − ½)³` crosses at an inflexion
    /// (one arc); a box off the border, or one where the inner edge is crossed, is refused.
    #[test]
    fn border_touches_count_their_arcs() {
        let curve = |su: i64, m: usize| {
            // Power coefficients, u fastest: ±u − (v − ½)^m.
            let mut c = vec![r(0, 1); 2 * (m + 1)];
            c[1] = r(su, 1);
            let binom =
                |n: usize, k: usize| (0..k).fold(1i64, |a, i| a * (n - i) as i64 / (i as i64 + 1));
            for j in 0..=m {
                // −C(m, j) v^j (−½)^(m−j)
                let sign = if (m - j).is_multiple_of(2) { -1 } else { 1 };
                c[2 * j] = r(sign * binom(m, j), 1 << (m - j));
            }
            Bernstein::from_power(vec![1, m], c).unwrap()
        };
        let near = vec![(r(0, 1), r(1, 64)), (r(7, 16), r(9, 16))];
        let half = |x: &(Rational, Rational)| x.0 <= r(1, 2) && r(1, 2) <= x.1;
        for (su, m, arcs) in [(1, 2, 2), (-1, 2, 0), (1, 3, 1)] {
            let (along, n) = certify_cap_border_box(&curve(su, m), (0, false), &near)
                .unwrap()
                .unwrap();
            assert_eq!(n, arcs, "±u = {su}, m = {m}");
            assert!(half(&along), "{along:?}");
        }
        // Not on the border, or the inner edge u = ⅛ crossed by the contour.
        let off = vec![(r(1, 128), r(1, 64)), (r(7, 16), r(9, 16))];
        assert_eq!(
            certify_cap_border_box(&curve(1, 2), (0, false), &off).unwrap(),
            None
        );
        let wide = vec![(r(0, 1), r(1, 8)), (r(1, 16), r(15, 16))];
        assert_eq!(
            certify_cap_border_box(&curve(1, 2), (0, false), &wide).unwrap(),
            None
        );
    }

    /// The gcd of `(s − ½)(s − ⅓)` and `(s − ½)(s + 2)` is `s − ½`; the square-free part of a
    /// square keeps one root; an extrapolated re-framing evaluates like the original.
    #[test]
    fn gcd_quotient_and_reframing_are_exact() {
        let a = vec![r(1, 6), r(-5, 6), r(1, 1)];
        let b = vec![r(-1, 1), r(3, 2), r(1, 1)];
        assert_eq!(gcd(&a, &b), vec![r(-1, 2), r(1, 1)]);
        let square = vec![r(1, 4), r(-1, 1), r(1, 1)];
        let d = vec![r(-1, 1), r(2, 1)];
        assert_eq!(
            div_rem(&square, &gcd(&square, &d)).0,
            vec![r(-1, 2), r(1, 1)]
        );
        let p = Bernstein::from_power(vec![3], vec![r(1, 1), r(-2, 1), r(0, 1), r(5, 1)]).unwrap();
        let q = reframed(&p, 0, &r(-1, 2), &r(3, 2)).unwrap();
        for (x, y) in [(r(0, 1), r(-1, 2)), (r(1, 2), r(1, 2)), (r(1, 1), r(3, 2))] {
            assert_eq!(q.eval(&[x]).unwrap(), p.eval(&[y]).unwrap());
        }
    }
}
