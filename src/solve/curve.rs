//! Solution curves of `n − 1` equations in `n` unknowns, traced with certified topology.
//!
//! The method is subdivision into *regular* boxes (in the spirit of Liang, Mourrain and
//! Pavone, "Subdivision methods for the topology of 2d and 3d implicit curves", Geometric
//! Modeling and Algebraic Geometry, Springer 2008): a box is regular along axis `k` when the
//! `k`-th component of the curve's tangent `t = ⋀ ∇f_i` — up to sign the Jacobian minor
//! without column `k` — has one strict sign on the box (decided from the minor's Bernstein
//! coefficients). In a regular box the curve has no singular point and no closed loop (a loop
//! would reach an extreme in `x_k`, where `t_k = 0`), so every piece of it is an arc with two
//! ends on the box's boundary; when the boundary holds exactly two curve points, both
//! certified transversal crossings, exactly one arc joins them, and when it holds none the
//! box holds no curve.
//!
//! The curve's points on a box's boundary are computed once per plane: when a box is split
//! at `x_a = s`, the `n − 1` equations restricted to that cross-section are a square system,
//! solved with [`solve`] (certified roots), and the roots are handed to both halves; the
//! points already on the box's faces are handed on to the half they lie in. A split plane is
//! moved (the same rational candidates as the zero-dimensional solver) when its cross-section
//! has an uncertified root or an existing point would lie on the new edge, so no curve point
//! is ever on a box edge and every boundary point is known to every box it bounds.
//!
//! What cannot be made regular down to the depth limit (singular points, tangencies that the
//! moved planes cannot avoid, curves closer together than the limit resolves) is reported as
//! a [`Cluster`]; the arcs entering it end there, and nothing is dropped: every point of the
//! curve in the domain lies in an arc's box or in a cluster's box.

use super::subdivision::{
    max_abs, shared_sign, strict_sign, widest_axis, Coefficient, MOVED_SPLITS_DEPTH, SPLITS,
};
use super::{
    solve, solve_piecewise, Cluster, ClusterReason, PiecewiseSystem, RationalBox, Root, SolveError,
    SolveOptions, System,
};
use crate::bernstein::poly::map_lines;
use crate::bernstein::{Bernstein, BernsteinError, Limits, ScaledBernstein};
use crate::num::{rational_to_f64, Interval, Rational, Sign};
use crate::Path;
use num_bigint::BigInt;
use num_traits::{One, Zero};
use std::time::Instant;

/// Default depth limit (levels per side, relative to the cross-section) of a cross-section
/// solve.
const CROSS_SECTION_DEPTH: u32 = 30;
/// Default box limit of a cross-section solve.
const CROSS_SECTION_BOXES: usize = 4_000;

/// Box limit of the extreme-point solve.
const EXTREME_BOXES: usize = 5_000;

/// Options of [`trace`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct CurveOptions {
    /// The arithmetic ([`Path::Filtered`] by default).
    pub path: Path,
    /// Depth (levels per side), box-count and time limits of the curve's subdivision; the
    /// cross-section solves share the time limit.
    pub limits: Limits,
    /// The widest arc box, relative to the domain's side on every axis: regular boxes wider
    /// than this are split further, so that the polylines follow the curve this closely.
    pub resolution: f64,
    /// The crossing points are refined to this width relative to the cross-section.
    pub tolerance: f64,
    /// Report the points where the curve is extreme along this axis (solved as the square
    /// system of the equations and the Jacobian minor without this column), if any.
    pub extreme_axis: Option<usize>,
    /// Depth and box limits of each cross-section solve (depth 30, 4,000 boxes by default; the
    /// time limit is always what remains of [`limits`](Self::limits)'). A cross-section that
    /// needs more is not certified: the plane is moved, or its clusters become blobs.
    pub section_limits: Limits,
}

impl Default for CurveOptions {
    fn default() -> Self {
        CurveOptions {
            path: Path::Filtered,
            limits: Limits::new().with_max_depth(16).with_max_boxes(200_000),
            resolution: 1.0 / 16.0,
            tolerance: 1e-12,
            extreme_axis: None,
            section_limits: Limits::new()
                .with_max_depth(CROSS_SECTION_DEPTH)
                .with_max_boxes(CROSS_SECTION_BOXES),
        }
    }
}

crate::choice::setters!(CurveOptions {
    with_path => path: Path,
    with_limits => limits: Limits,
    with_resolution => resolution: f64,
    with_tolerance => tolerance: f64,
    with_extreme_axis => extreme_axis: Option<usize>,
    with_section_limits => section_limits: Limits,
});

/// A certified point of the curve on a plane `x_axis = c`: `root` is a certified root of the
/// `n − 1` equations restricted to that plane (its `bounds[axis]` is `[c, c]`; its
/// certificate is for the restricted system, see [`plane_system`]).
#[derive(Clone, Debug, PartialEq)]
pub struct CurvePoint {
    /// The plane's axis.
    pub axis: usize,
    /// The root, in domain coordinates (`n` of them).
    pub root: Root,
}

/// One piece of the curve: inside `bounds` exactly one arc of the curve joins the two points,
/// monotone along `monotone_axis`.
#[derive(Clone, Debug, PartialEq)]
pub struct Arc {
    /// The regular box.
    pub bounds: RationalBox,
    /// The indices of its two end points in [`Curves::points`].
    pub ends: [usize; 2],
    /// The axis whose tangent component has one strict sign on the box.
    pub monotone_axis: usize,
}

/// Where an open component ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveEnd {
    /// On the domain's face `x_axis = a_axis` (`upper = false`) or `b_axis`.
    Face {
        /// The end point (index in [`Curves::points`]).
        point: usize,
        /// The face's axis.
        axis: usize,
        /// Whether it is the upper face.
        upper: bool,
    },
    /// At the boundary of a cluster box, which the curve enters.
    Cluster {
        /// The end point.
        point: usize,
        /// The index in [`Curves::clusters`].
        cluster: usize,
        /// The index of the cluster's group in [`Curves::cluster_groups`].
        group: usize,
    },
}

/// A connected piece of the traced curve: a polyline through certified curve points.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// Its points in order along the curve (indices in [`Curves::points`]); a closed loop
    /// returns from the last to the first.
    pub points: Vec<usize>,
    /// The arcs between consecutive points (indices in [`Curves::arcs`]).
    pub arcs: Vec<usize>,
    /// Whether it is a closed loop.
    pub closed: bool,
    /// The two ends of an open component (none for a loop).
    pub ends: Vec<CurveEnd>,
    /// A bound on the Hausdorff distance between the polyline and the curve piece: every
    /// segment and its arc lie in one arc box, so the largest box diagonal (plus the points'
    /// error bounds) bounds it.
    pub hausdorff_bound: f64,
}

/// A point where the curve is extreme along an axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Extreme {
    /// The certified root of the equations and the Jacobian minor without column `axis`.
    pub root: Root,
    /// The component it lies on, when its box lies in arc boxes of one component.
    pub component: Option<usize>,
}

/// The result of [`trace`].
#[derive(Clone, Debug, PartialEq)]
pub struct Curves {
    /// The certified crossing points (polyline vertices and component ends).
    pub points: Vec<CurvePoint>,
    /// The regular boxes with their arcs.
    pub arcs: Vec<Arc>,
    /// The components.
    pub components: Vec<Component>,
    /// The extreme points along [`CurveOptions::extreme_axis`].
    pub extremes: Vec<Extreme>,
    /// What the extreme-point solve could not certify (singular points of the curve among
    /// them).
    pub extreme_clusters: Vec<Cluster>,
    /// Boxes the curve could not be resolved in.
    pub clusters: Vec<Cluster>,
    /// The clusters grouped into connected sets of touching boxes (indices in
    /// [`Curves::clusters`]): one singular point or tangency usually leaves a chain of small
    /// boxes, and the components that end in one group meet there.
    pub cluster_groups: Vec<Vec<usize>>,
    /// Boxes examined by the curve's subdivision (not counting the cross-section solves).
    pub boxes_visited: usize,
    /// Cross-section systems solved (domain faces and split planes, moved candidates
    /// included).
    pub cross_sections: usize,
    /// The path that ran.
    pub path: Path,
}

/// The system's equations on the plane `x_axis = c` (domain coordinate), over the part of
/// the plane inside `bounds` (the other axes): an `(n−1)`-unknown square system.
pub fn plane_system(
    system: &System,
    axis: usize,
    c: &Rational,
    bounds: &RationalBox,
) -> Result<System, SolveError> {
    let n = plane_shape(system, axis, bounds)?;
    let mut sub = Vec::with_capacity(n);
    for (k, (lo, hi)) in bounds.iter().enumerate() {
        sub.push(if k == axis {
            (Rational::zero(), Rational::one())
        } else {
            (system.to_unit(k, lo), system.to_unit(k, hi))
        });
    }
    let at = system.to_unit(axis, c);
    let mut equations = Vec::with_capacity(system.equations.len());
    for e in &system.equations {
        let mut q = e.eval_axis(axis, &at)?;
        if sub.iter().any(|(a, b)| !a.is_zero() || !b.is_one()) {
            q = q.restrict(&sub)?;
        }
        equations.push(q.face(axis, false)?);
    }
    System::new(plane_domain(bounds, axis), equations)
}

/// The number of unknowns, checked for a cross-section along `axis` within `bounds`.
fn plane_shape(system: &System, axis: usize, bounds: &RationalBox) -> Result<usize, SolveError> {
    let n = system.unknowns();
    if axis >= n || bounds.len() != n || n < 2 {
        return Err(SolveError::Unknowns(n));
    }
    Ok(n)
}

/// The cross-section's domain: `bounds` without `axis`.
fn plane_domain(bounds: &RationalBox, axis: usize) -> RationalBox {
    bounds
        .iter()
        .enumerate()
        .filter(|&(k, _)| k != axis)
        .map(|(_, b)| b.clone())
        .collect()
}

/// `p` restricted to `[lo, hi] ⊂ [0, 1]` along `axis` (reparametrised to `[0, 1]`), by
/// integer de Casteljau.
fn restrict_scaled(
    p: ScaledBernstein,
    axis: usize,
    lo: &Rational,
    hi: &Rational,
) -> Result<ScaledBernstein, BernsteinError> {
    let mut p = p;
    if !hi.is_one() {
        p = p.split(axis, hi.numer(), hi.denom())?.0;
    }
    if !lo.is_zero() {
        let r = lo / hi;
        p = p.split(axis, r.numer(), r.denom())?.1;
    }
    Ok(p)
}

/// The face `t_axis = 0` (`upper = false`) or `1` of an integer polynomial, as rationals.
fn face_scaled(
    p: &ScaledBernstein,
    axis: usize,
    upper: bool,
) -> Result<Bernstein<Rational>, BernsteinError> {
    let d = p.degrees()[axis];
    let num = map_lines(
        p.degrees(),
        p.numerators(),
        axis,
        1,
        &BigInt::zero(),
        |line, out| {
            out[0] = line[if upper { d } else { 0 }].clone();
        },
    );
    let mut degrees = p.degrees().to_vec();
    degrees.remove(axis);
    Ok(ScaledBernstein::with_denominator(degrees, num, p.denominator().clone())?.to_rational())
}

/// [`plane_system`] from the equations in integer form already restricted to `bounds`
/// (`restricted[i]` is `system.equations[i]` on the box `bounds`, reparametrised to the unit
/// cube): the same polynomials, computed by one integer de Casteljau step instead of
/// rational arithmetic. The tracer keeps every box's restriction (a child's is its parent's
/// split at a small fraction), so a cross-section never restricts from the whole domain.
fn plane_system_scaled(
    system: &System,
    restricted: &[ScaledBernstein],
    axis: usize,
    c: &Rational,
    bounds: &RationalBox,
) -> Result<System, SolveError> {
    plane_shape(system, axis, bounds)?;
    let (lo, hi) = &bounds[axis];
    if hi <= lo {
        return Err(SolveError::Field {
            field: "bounds".into(),
            why: format!("the cross-section's box is flat along axis {axis}"),
        });
    }
    let at = (c - lo) / (hi - lo);
    let mut equations = Vec::with_capacity(restricted.len());
    for q in restricted {
        let face = if at.is_zero() || at.is_one() {
            face_scaled(q, axis, at.is_one())?
        } else {
            let right = q.split(axis, at.numer(), at.denom())?.1;
            face_scaled(&right, axis, false)?
        };
        equations.push(face);
    }
    System::new(plane_domain(bounds, axis), equations)
}

/// The determinant of the square matrix of polynomials `m[rows][cols]` (Laplace expansion
/// along the first row).
fn determinant<T: crate::num::Field>(
    m: &[Vec<&Bernstein<T>>],
) -> Result<Bernstein<T>, BernsteinError> {
    if m.len() == 1 {
        return Ok(m[0][0].clone());
    }
    let mut acc: Option<Bernstein<T>> = None;
    for c in 0..m.len() {
        let minor: Vec<Vec<&Bernstein<T>>> = m[1..]
            .iter()
            .map(|row| {
                row.iter()
                    .enumerate()
                    .filter(|&(j, _)| j != c)
                    .map(|(_, p)| *p)
                    .collect()
            })
            .collect();
        let mut term = m[0][c].product(&determinant(&minor)?)?;
        if c % 2 == 1 {
            term = term.scale(&T::from_ratio(-1, 1));
        }
        acc = Some(match acc {
            None => term,
            Some(s) => s.add_elevated(&term)?,
        });
    }
    acc.ok_or(BernsteinError::NoAxes)
}

/// Per axis `k`, the Jacobian minor of `polys` (`n − 1` polynomials in `n` unit variables)
/// without column `k`: up to sign and positive factors, the tangent's `k`-th component.
pub(super) fn tangent_minor<T: crate::num::Field>(
    polys: &[Bernstein<T>],
    k: usize,
) -> Result<Bernstein<T>, BernsteinError> {
    let n = polys.first().map_or(0, Bernstein::dim);
    let mut derivs = Vec::with_capacity(polys.len());
    for p in polys {
        let mut row = Vec::with_capacity(n - 1);
        for j in (0..n).filter(|&j| j != k) {
            row.push(p.derivative(j)?);
        }
        derivs.push(row);
    }
    let refs: Vec<Vec<&Bernstein<T>>> = derivs.iter().map(|r| r.iter().collect()).collect();
    determinant(&refs)
}

/// [`tangent_minor`] in integers over a common denominator (no gcd in the products): the
/// permutation expansion `Σ_σ sgn σ Π_i ∂f_i/∂x_σ(i)`, skipping the terms with an identically
/// zero factor (a derivative along a degree-0 axis); every other term has the same degrees
/// (each derivative lowers its axis by one), so the terms add without elevation.
pub(super) fn tangent_minor_exact(
    polys: &[Bernstein<Rational>],
    k: usize,
) -> Result<Bernstein<Rational>, BernsteinError> {
    let n = polys.first().map_or(0, Bernstein::dim);
    let cols: Vec<usize> = (0..n).filter(|&j| j != k).collect();
    let mut derivs: Vec<Vec<Option<ScaledBernstein>>> = Vec::with_capacity(polys.len());
    for p in polys {
        let s = ScaledBernstein::from_rational(p);
        let mut row = Vec::with_capacity(cols.len());
        for &j in &cols {
            let d = s.derivative(j)?;
            row.push((!d.numerators().iter().all(Zero::is_zero)).then_some(d));
        }
        derivs.push(row);
    }
    fn expand(
        derivs: &[Vec<Option<ScaledBernstein>>],
        row: usize,
        used: &mut Vec<bool>,
        negative: bool,
        partial: Option<ScaledBernstein>,
        acc: &mut Option<ScaledBernstein>,
    ) -> Result<(), BernsteinError> {
        if row == derivs.len() {
            let term = partial.expect("at least one row");
            *acc = Some(match acc.take() {
                None if negative => ScaledBernstein::from_integers(
                    term.degrees().to_vec(),
                    vec![BigInt::zero(); term.numerators().len()],
                )?
                .sub(&term)?,
                None => term,
                Some(a) if negative => a.sub(&term)?,
                Some(a) => a.add(&term)?,
            });
            return Ok(());
        }
        // The sign of the permutation: one flip per used column to the right of the chosen one.
        for c in 0..used.len() {
            if used[c] {
                continue;
            }
            let Some(d) = &derivs[row][c] else { continue };
            let flips = used[c + 1..].iter().filter(|&&u| u).count();
            let next = match &partial {
                None => d.clone(),
                Some(p) => p.product(d)?,
            };
            used[c] = true;
            expand(
                derivs,
                row + 1,
                used,
                negative ^ (flips % 2 == 1),
                Some(next),
                acc,
            )?;
            used[c] = false;
        }
        Ok(())
    }
    let mut acc = None;
    expand(
        &derivs,
        0,
        &mut vec![false; cols.len()],
        false,
        None,
        &mut acc,
    )?;
    Ok(match acc {
        Some(a) => a.to_rational(),
        None => Bernstein::constant(vec![0; n], Rational::zero()),
    })
}

/// What a box of the subdivision is.
enum Class {
    /// Some equation has one strict sign: no curve.
    Empty,
    /// The tangent's component along this axis has one strict sign.
    Regular(usize),
    /// Neither.
    Irregular,
    /// Rounding left it open.
    Uncertain,
}

/// The strict sign the polynomials share on every coefficient (`Zero` when they do not share
/// one, `Uncertain` when rounding leaves it open): [`strict_sign`] across a box's parts.
fn common_sign<'p, T: crate::num::Field + 'p>(
    polys: impl IntoIterator<Item = &'p Bernstein<T>>,
) -> Sign {
    shared_sign(polys.into_iter().map(strict_sign))
}

/// Classifies a box from its parts' equations and tangent minors (`minors[k]` the minor
/// without column `k`, restricted to the part: up to a positive factor, the part's own
/// minor). A box holding one part is a polynomial box; across parts the signs must agree on
/// every part (see [`trace_piecewise`] for why that suffices where the field is C¹, and in
/// two unknowns where it is only C⁰).
fn classify<T: Coefficient>(pieces: &[Piece<T>], first: Option<usize>) -> Class {
    let (m, n) = pieces
        .first()
        .map_or((0, 0), |p| (p.polys.len(), p.minors.len()));
    let mut uncertain = false;
    for i in 0..m {
        match common_sign(pieces.iter().map(|p| &p.polys[i])) {
            Sign::Positive | Sign::Negative => return Class::Empty,
            Sign::Uncertain => uncertain = true,
            Sign::Zero => {}
        }
    }
    // The preferred axis first (the extreme axis: a box monotone along it holds no extreme).
    let order = first
        .into_iter()
        .chain((0..n).filter(|&k| Some(k) != first));
    for k in order {
        match common_sign(pieces.iter().map(|p| &p.minors[k])) {
            Sign::Positive | Sign::Negative => return Class::Regular(k),
            Sign::Uncertain => uncertain = true,
            Sign::Zero => {}
        }
    }
    if uncertain {
        Class::Uncertain
    } else {
        Class::Irregular
    }
}

/// One cell's part of a box of the curve's subdivision: its bounds (unit coordinates of the
/// domain), the cell, and the equations and tangent minors on it (Bernstein form on the
/// part), carried down by de Casteljau with the box (the minor of the restricted equations
/// is the restricted minor times the product of the part's widths along the other axes: the
/// same signs).
struct Piece<T> {
    lo: Vec<Rational>,
    hi: Vec<Rational>,
    cell: usize,
    polys: Vec<Bernstein<T>>,
    minors: Vec<Bernstein<T>>,
}

/// A box of the curve's subdivision (unit coordinates).
struct Node<T> {
    lo: Vec<Rational>,
    hi: Vec<Rational>,
    /// One per cell the box meets with positive volume (one for a polynomial system).
    pieces: Vec<Piece<T>>,
    depth: u32,
    /// Certified curve points on the box's boundary.
    points: Vec<usize>,
    /// Uncertified cross-section clusters touching the box's boundary.
    blobs: Vec<usize>,
    /// A polynomial system's equations in integer form restricted to the box (reparametrised
    /// to the unit cube), for its cross-sections; empty for a piecewise system.
    exact: Vec<ScaledBernstein>,
}

/// The new points and blobs (ids) of a cross-section.
type Crossings = (Vec<usize>, Vec<usize>);

/// A box (unit coordinates) of a point or blob.
struct UnitBox {
    lo: Vec<Rational>,
    hi: Vec<Rational>,
}

/// A cell of the system: its box in unit coordinates and its exact tangent minors.
struct CellMinors {
    lo: Vec<Rational>,
    hi: Vec<Rational>,
    minors: Vec<Bernstein<Rational>>,
}

struct Tracer<'a> {
    system: &'a PiecewiseSystem,
    /// The system itself when it is one polynomial cell: its cross-sections take the
    /// integer route.
    poly: Option<&'a System>,
    opts: &'a CurveOptions,
    clock: Instant,
    points: Vec<CurvePoint>,
    point_boxes: Vec<UnitBox>,
    blobs: Vec<UnitBox>,
    arcs: Vec<Arc>,
    /// Cluster, and the points on its boundary.
    clusters: Vec<(Cluster, Vec<usize>)>,
    visited: usize,
    cross_sections: usize,
    /// The polynomial system's equations in integer form, for the cross-sections.
    scaled: Vec<ScaledBernstein>,
    /// Per cell, its unit box and exact minors (its equations are the system's cells').
    cells: Vec<CellMinors>,
    /// Per axis, the C⁰ knots in unit coordinates (kept only with three or more unknowns).
    kinks: Vec<Vec<Rational>>,
}

impl Tracer<'_> {
    /// The domain box of unit bounds.
    fn domain_box(&self, lo: &[Rational], hi: &[Rational]) -> RationalBox {
        super::domain_bounds(self.system.domain(), lo, hi)
    }

    /// A domain box in unit coordinates.
    fn unit_box(&self, bounds: &RationalBox) -> UnitBox {
        let (lo, hi) = super::unit_bounds(self.system.domain(), bounds)
            .into_iter()
            .unzip();
        UnitBox { lo, hi }
    }

    /// Solves the cross-section `x_axis = at` (unit) of the box `lo..hi`; returns the new
    /// point ids and blob ids, or `None` when it had uncertified roots and `strict`.
    /// `exact` is the polynomial system's integer form restricted to the box (see
    /// [`Node::exact`]; unused for a piecewise system).
    fn cross_section(
        &mut self,
        lo: &[Rational],
        hi: &[Rational],
        exact: &[ScaledBernstein],
        axis: usize,
        at: &Rational,
        strict: bool,
    ) -> Result<Option<Crossings>, SolveError> {
        let bounds = self.domain_box(lo, hi);
        let (a, b) = &self.system.domain()[axis];
        let c = a + (b - a) * at;
        self.cross_sections += 1;
        let remaining = self
            .opts
            .limits
            .time_limit
            .map(|t| t.saturating_sub(self.clock.elapsed()));
        // (A crossing on the cross-section's edge is the neighbouring box's: the solver's
        // boundary stage stays off.)
        let sopts = SolveOptions::new()
            .with_path(self.opts.path)
            .with_tolerance(self.opts.tolerance)
            .with_boundary(false)
            .with_limits(
                // A cross-section that needs more than this is not worth certifying: the plane
                // is moved, or its clusters become blobs the subdivision resolves.
                self.opts.section_limits.with_time_limit(remaining),
            );
        // An equation that vanishes on the whole cross-section (or on a whole cell of it)
        // leaves infinitely many curve points on it (the solver would subdivide to its
        // budget): no crossings to certify.
        let vanishes = |e: &Bernstein<Rational>| e.coeffs().iter().all(Zero::is_zero);
        let sol = match self.poly {
            Some(system) => {
                let plane = plane_system_scaled(system, exact, axis, &c, &bounds)?;
                (!plane.equations.iter().any(vanishes))
                    .then(|| solve(&plane, &sopts))
                    .transpose()?
            }
            None => {
                let plane = self.system.plane(axis, &c, &bounds)?;
                let flat = plane
                    .cells()
                    .iter()
                    .any(|cell| cell.equations.iter().any(vanishes));
                (!flat)
                    .then(|| solve_piecewise(&plane, &sopts))
                    .transpose()?
            }
        };
        let Some(sol) = sol else {
            if strict {
                return Ok(None);
            }
            let mut on_plane = bounds.clone();
            on_plane[axis] = (c.clone(), c.clone());
            let blob = self.blobs.len();
            let unit = self.unit_box(&on_plane);
            self.blobs.push(unit);
            return Ok(Some((Vec::new(), vec![blob])));
        };
        if strict && !sol.clusters.is_empty() {
            return Ok(None);
        }
        let mut ids = Vec::with_capacity(sol.roots.len());
        for r in sol.roots {
            let mut bounds = r.bounds;
            bounds.insert(axis, (c.clone(), c.clone()));
            let mut approx = r.approx;
            approx.insert(axis, rational_to_f64(&c));
            let unit = self.unit_box(&bounds);
            ids.push(self.points.len());
            self.points.push(CurvePoint {
                axis,
                root: Root {
                    bounds,
                    approx,
                    error_bound: r.error_bound,
                    certificate: r.certificate,
                },
            });
            self.point_boxes.push(unit);
        }
        let mut blob_ids = Vec::with_capacity(sol.clusters.len());
        for cl in sol.clusters {
            let mut bounds = cl.bounds;
            bounds.insert(axis, (c.clone(), c.clone()));
            blob_ids.push(self.blobs.len());
            let unit = self.unit_box(&bounds);
            self.blobs.push(unit);
        }
        Ok(Some((ids, blob_ids)))
    }

    fn cluster<T: Coefficient>(&mut self, node: &Node<T>, reason: ClusterReason) {
        let max_abs_f = node
            .pieces
            .iter()
            .map(|p| max_abs(&p.polys))
            .reduce(|a, b| a.iter().zip(&b).map(|(x, y)| x.max(*y)).collect())
            .unwrap_or_default();
        self.clusters.push((
            Cluster {
                bounds: self.domain_box(&node.lo, &node.hi),
                reason,
                max_abs_f,
            },
            node.points.clone(),
        ));
    }

    /// The pieces of `node` in exact rationals, restricted from the cells.
    fn exact_pieces<T>(&self, node: &Node<T>) -> Result<Vec<Piece<Rational>>, SolveError> {
        let mut out = Vec::with_capacity(node.pieces.len());
        for p in &node.pieces {
            let cell = &self.cells[p.cell];
            let sub: Vec<(Rational, Rational)> = (0..p.lo.len())
                .map(|k| {
                    let w = &cell.hi[k] - &cell.lo[k];
                    ((&p.lo[k] - &cell.lo[k]) / &w, (&p.hi[k] - &cell.lo[k]) / &w)
                })
                .collect();
            let restrict = |ps: &[Bernstein<Rational>]| -> Result<Vec<_>, BernsteinError> {
                ps.iter().map(|e| e.restrict(&sub)).collect()
            };
            out.push(Piece {
                lo: p.lo.clone(),
                hi: p.hi.clone(),
                cell: p.cell,
                polys: restrict(&self.system.cells()[p.cell].equations)?,
                minors: restrict(&cell.minors)?,
            });
        }
        Ok(out)
    }

    /// The class of a node; on the filtered path, exactly where rounding left it open at the
    /// depth limit.
    fn class_of<T: Coefficient>(
        &self,
        node: &Node<T>,
        at_limit: bool,
    ) -> Result<Class, SolveError> {
        let class = classify(&node.pieces, self.opts.extreme_axis);
        // Rounding that leaves the class open is usually settled by splitting (the
        // coefficients tighten); only boxes at the depth limit are decided exactly.
        if matches!(class, Class::Uncertain) && self.opts.path == Path::Filtered && at_limit {
            return Ok(classify(&self.exact_pieces(node)?, self.opts.extreme_axis));
        }
        Ok(class)
    }

    /// A C⁰ knot plane strictly inside the node (axis and unit position), if any: the box
    /// is split there before it may be regular.
    fn kink_inside<T>(&self, node: &Node<T>) -> Option<(usize, Rational)> {
        self.kinks.iter().enumerate().find_map(|(k, ks)| {
            ks.iter()
                .find(|x| node.lo[k] < **x && **x < node.hi[k])
                .map(|x| (k, x.clone()))
        })
    }

    /// Which side of the plane `x_axis = m` a point lies on: `Some(false)` below, `Some(true)`
    /// above, `None` when its box touches the plane.
    fn side(&self, b: &UnitBox, axis: usize, m: &Rational) -> Option<bool> {
        if &b.hi[axis] < m {
            Some(false)
        } else if &b.lo[axis] > m {
            Some(true)
        } else {
            None
        }
    }

    fn run<T: Coefficient>(&mut self) -> Result<(), SolveError> {
        let n = self.system.unknowns();
        let limits = self.opts.limits;
        let zero = vec![Rational::zero(); n];
        let one = vec![Rational::one(); n];
        // The curve's points on the domain's faces.
        let mut points = Vec::new();
        let mut blobs = Vec::new();
        let root_exact = std::mem::take(&mut self.scaled);
        for axis in 0..n {
            for at in [Rational::zero(), Rational::one()] {
                let (p, b) = self
                    .cross_section(&zero, &one, &root_exact, axis, &at, false)?
                    .unwrap_or_default();
                points.extend(p);
                blobs.extend(b);
            }
        }
        let resolution = if self.opts.resolution.is_finite() && self.opts.resolution > 0.0 {
            crate::num::rational_from_f64(self.opts.resolution.min(1.0), "resolution")
                .unwrap_or_else(|_| Rational::one())
        } else {
            Rational::one()
        };
        let pieces = self
            .cells
            .iter()
            .zip(self.system.cells())
            .enumerate()
            .map(|(c, (cell, system))| Piece {
                lo: cell.lo.clone(),
                hi: cell.hi.clone(),
                cell: c,
                polys: system
                    .equations
                    .iter()
                    .map(|e| e.map(T::from_rational))
                    .collect(),
                minors: cell
                    .minors
                    .iter()
                    .map(|e| e.map(T::from_rational))
                    .collect(),
            })
            .collect();
        let mut stack = vec![Node {
            lo: zero,
            hi: one,
            pieces,
            depth: 0,
            points,
            blobs,
            exact: root_exact,
        }];
        while let Some(node) = stack.pop() {
            let over_time = limits.time_limit.is_some_and(|t| self.clock.elapsed() > t);
            if self.visited >= limits.max_boxes || over_time {
                self.cluster(&node, ClusterReason::Budget);
                continue;
            }
            self.visited += 1;
            let at_limit = node.depth >= limits.max_depth.saturating_mul(n as u32);
            let class = self.class_of(&node, at_limit)?;
            if matches!(class, Class::Empty) {
                continue;
            }
            let kink = self.kink_inside(&node);
            let widest = widest_axis(&node.lo, &node.hi);
            let width = &node.hi[widest] - &node.lo[widest];
            match class {
                Class::Regular(k) if node.blobs.is_empty() && kink.is_none() => {
                    match node.points.len() {
                        0 => continue,
                        2 if width <= resolution => {
                            self.arcs.push(Arc {
                                bounds: self.domain_box(&node.lo, &node.hi),
                                ends: [node.points[0], node.points[1]],
                                monotone_axis: k,
                            });
                            continue;
                        }
                        _ => {}
                    }
                }
                _ => {}
            }
            // Splitting is always sound; rounding that left the class open shows in the
            // reason at the depth limit (fast path only: the filtered path decided exactly).
            if at_limit {
                let reason = if matches!(class, Class::Uncertain) {
                    ClusterReason::Uncertain
                } else {
                    ClusterReason::DepthLimit
                };
                self.cluster(&node, reason);
                continue;
            }
            let (left, right) = match kink {
                Some((axis, at)) => self.split(node, axis, Some(at))?,
                None => self.split(node, widest, None)?,
            };
            stack.push(right);
            stack.push(left);
        }
        Ok(())
    }

    /// Splits a node along `axis`: at `at` when given (a C⁰ knot plane), else at the first
    /// candidate plane whose cross-section is fully certified and which no existing point
    /// touches (½ with whatever it has otherwise).
    fn split<T: Coefficient>(
        &mut self,
        node: Node<T>,
        axis: usize,
        at: Option<Rational>,
    ) -> Result<(Node<T>, Node<T>), SolveError> {
        let candidates: Vec<Rational> = match at {
            Some(m) => vec![m],
            None => {
                let tried = if node.depth < MOVED_SPLITS_DEPTH {
                    SPLITS.len()
                } else {
                    1
                };
                SPLITS[..tried]
                    .iter()
                    .map(|&(p, q)| {
                        let s = Rational::new(p.into(), q.into());
                        crate::num::rational::lerp(&node.lo[axis], &node.hi[axis], &s)
                    })
                    .collect()
            }
        };
        let mut chosen = None;
        for (i, m) in candidates.iter().enumerate() {
            let touches = node.points.iter().any(|&id| {
                self.points[id].axis != axis && self.side(&self.point_boxes[id], axis, m).is_none()
            });
            let last = i + 1 == candidates.len();
            if touches && !last {
                continue;
            }
            if let Some(found) =
                self.cross_section(&node.lo, &node.hi, &node.exact, axis, m, !last)?
            {
                chosen = Some((m.clone(), found));
                break;
            }
        }
        let Some((m, (new_points, new_blobs))) = chosen else {
            return Err(SolveError::Field {
                field: "split".into(),
                why: "no split plane was tried".into(),
            });
        };
        let (mut lpieces, mut rpieces) = (Vec::new(), Vec::new());
        for p in node.pieces {
            if p.hi[axis] <= m {
                lpieces.push(p);
                continue;
            }
            if p.lo[axis] >= m {
                rpieces.push(p);
                continue;
            }
            let t = T::from_rational(&((&m - &p.lo[axis]) / (&p.hi[axis] - &p.lo[axis])));
            let halves = |ps: &[Bernstein<T>]| -> Result<(Vec<_>, Vec<_>), BernsteinError> {
                let (mut l, mut r) = (Vec::with_capacity(ps.len()), Vec::with_capacity(ps.len()));
                for q in ps {
                    let (a, b) = q.split(axis, &t)?;
                    l.push(a);
                    r.push(b);
                }
                Ok((l, r))
            };
            let (lp, rp) = halves(&p.polys)?;
            let (lm, rm) = halves(&p.minors)?;
            let (mut lhi, mut rlo) = (p.hi.clone(), p.lo.clone());
            lhi[axis] = m.clone();
            rlo[axis] = m.clone();
            lpieces.push(Piece {
                lo: p.lo,
                hi: lhi,
                cell: p.cell,
                polys: lp,
                minors: lm,
            });
            rpieces.push(Piece {
                lo: rlo,
                hi: p.hi,
                cell: p.cell,
                polys: rp,
                minors: rm,
            });
        }
        let (mut lpts, mut rpts) = (new_points.clone(), new_points);
        let (mut lblobs, mut rblobs) = (new_blobs.clone(), new_blobs);
        for &id in &node.points {
            let b = &self.point_boxes[id];
            if self.points[id].axis == axis {
                if b.lo[axis] == node.lo[axis] {
                    lpts.push(id);
                } else {
                    rpts.push(id);
                }
                continue;
            }
            match self.side(b, axis, &m) {
                Some(false) => lpts.push(id),
                Some(true) => rpts.push(id),
                None => {
                    // It touches the plane (only when no candidate avoided it): an
                    // uncertified point on both halves' boundaries.
                    let blob = self.blobs.len();
                    self.blobs.push(UnitBox {
                        lo: b.lo.clone(),
                        hi: b.hi.clone(),
                    });
                    lblobs.push(blob);
                    rblobs.push(blob);
                }
            }
        }
        for &id in &node.blobs {
            let b = &self.blobs[id];
            if b.lo[axis] <= m {
                lblobs.push(id);
            }
            if b.hi[axis] >= m {
                rblobs.push(id);
            }
        }
        // The children's restrictions: the box's, split at the plane's fraction of it (a
        // small one, `SPLITS`, unless the plane is a knot).
        let (mut lexact, mut rexact) = (Vec::new(), Vec::new());
        if !node.exact.is_empty() {
            let s = (&m - &node.lo[axis]) / (&node.hi[axis] - &node.lo[axis]);
            for q in &node.exact {
                let (mut a, mut b) = q.split(axis, s.numer(), s.denom())?;
                a.normalise_twos();
                b.normalise_twos();
                lexact.push(a);
                rexact.push(b);
            }
        }
        let mut hi_left = node.hi.clone();
        hi_left[axis] = m.clone();
        let mut lo_right = node.lo.clone();
        lo_right[axis] = m;
        Ok((
            Node {
                lo: node.lo,
                hi: hi_left,
                pieces: lpieces,
                depth: node.depth + 1,
                points: lpts,
                blobs: lblobs,
                exact: lexact,
            },
            Node {
                lo: lo_right,
                hi: node.hi,
                pieces: rpieces,
                depth: node.depth + 1,
                points: rpts,
                blobs: rblobs,
                exact: rexact,
            },
        ))
    }

    /// Links the arcs into components; `group_of` maps a cluster to its group.
    fn components(&self, group_of: &[usize]) -> Vec<Component> {
        let mut at: Vec<Vec<usize>> = vec![Vec::new(); self.points.len()];
        for (i, a) in self.arcs.iter().enumerate() {
            at[a.ends[0]].push(i);
            at[a.ends[1]].push(i);
        }
        let end_of = |p: usize| -> Option<CurveEnd> {
            let b = &self.point_boxes[p];
            let k = self.points[p].axis;
            if b.lo[k].is_zero() || b.lo[k].is_one() {
                return Some(CurveEnd::Face {
                    point: p,
                    axis: k,
                    upper: b.lo[k].is_one(),
                });
            }
            self.clusters
                .iter()
                .position(|(_, pts)| pts.contains(&p))
                .map(|cluster| CurveEnd::Cluster {
                    point: p,
                    cluster,
                    group: group_of[cluster],
                })
        };
        let mut used = vec![false; self.arcs.len()];
        let mut out = Vec::new();
        // Walk from `start` along unused arcs; returns the points and arcs passed.
        let walk = |start: usize, first_arc: usize, used: &mut Vec<bool>| {
            let mut pts = vec![start];
            let mut arcs = Vec::new();
            let (mut here, mut arc) = (start, Some(first_arc));
            while let Some(a) = arc {
                used[a] = true;
                arcs.push(a);
                let e = self.arcs[a].ends;
                here = if e[0] == here { e[1] } else { e[0] };
                pts.push(here);
                arc = at[here].iter().copied().find(|&b| !used[b]);
            }
            (pts, arcs)
        };
        let bound = |arcs: &[usize], pts: &[usize]| {
            let diag = arcs
                .iter()
                .map(|&a| {
                    self.arcs[a]
                        .bounds
                        .iter()
                        .map(|(lo, hi)| Interval::from_rational(&(hi - lo)).hi.powi(2))
                        .sum::<f64>()
                        .sqrt()
                })
                .fold(0.0, f64::max);
            let err = pts
                .iter()
                .map(|&p| self.points[p].root.error_bound)
                .fold(0.0, f64::max);
            (diag + err) * (1.0 + 4.0 * f64::EPSILON)
        };
        // Open components start at a point with one arc.
        for p in 0..self.points.len() {
            if at[p].len() != 1 || used[at[p][0]] {
                continue;
            }
            let (pts, arcs) = walk(p, at[p][0], &mut used);
            let last = *pts.last().unwrap_or(&p);
            let ends = [p, last].into_iter().filter_map(end_of).collect();
            let hausdorff_bound = bound(&arcs, &pts);
            out.push(Component {
                points: pts,
                arcs,
                closed: false,
                ends,
                hausdorff_bound,
            });
        }
        // What is left are loops.
        for a in 0..self.arcs.len() {
            if used[a] {
                continue;
            }
            let start = self.arcs[a].ends[0];
            let (mut pts, arcs) = walk(start, a, &mut used);
            pts.pop();
            let hausdorff_bound = bound(&arcs, &pts);
            out.push(Component {
                points: pts,
                arcs,
                closed: true,
                ends: Vec::new(),
                hausdorff_bound,
            });
        }
        out
    }
}

/// Traces the solution curve of `system` (`n − 1` equations in `n ≥ 2` unknowns) on its
/// domain. Every point of the curve in the domain lies in an arc's box or a cluster's box;
/// every polyline vertex is a certified curve point.
pub fn trace(system: &System, opts: &CurveOptions) -> Result<Curves, SolveError> {
    trace_piecewise(&PiecewiseSystem::from_polynomial(system.clone()), opts)
}

/// [`trace`] for a system whose equations may be tensor B-spline fields. The subdivision
/// runs over the whole box and its boxes cross knot planes, each carrying one part per cell
/// it meets (as in [`solve_piecewise`]); the cross-sections are the [`PiecewiseSystem::plane`]
/// systems, solved by [`solve_piecewise`], so a curve point on a knot plane is found once.
///
/// Why a box across knot planes is still regular when every part's tangent minor along axis
/// `k` has the same strict sign:
/// - across knots where every field is C¹ (multiplicity below the degree) the minor is a
///   continuous function with no zero on the box, and the polynomial argument holds as it
///   is (implicit function theorem);
/// - in two unknowns the minor is `±∂f/∂x_j` (`j ≠ k`), of one strict sign on every part:
///   the continuous `f` is then strictly monotone along `x_j`, has at most one zero on each
///   line `x_k = c`, and its zero set is a union of graphs over `x_k` ending on the boundary;
/// - in three or more unknowns a C⁰ knot plane (a jump of the Jacobian) is never inside a
///   regular box: such a box is split exactly at the knot plane first (the plane's curve
///   points are its cross-section's certified roots), since there agreeing signs on the two
///   sides do not make the slice map injective.
///
/// Extreme points ([`CurveOptions::extreme_axis`]) are computed for polynomial systems only:
/// on B-spline equations the tangent minor is a piecewise product the square solver would
/// need as one continuous equation; asking for them is an error there.
pub fn trace_piecewise(
    system: &PiecewiseSystem,
    opts: &CurveOptions,
) -> Result<Curves, SolveError> {
    let n = system.unknowns();
    if n < 2 || system.equations().len() + 1 != n {
        return Err(SolveError::NotCurve {
            equations: system.equations().len(),
            unknowns: n,
        });
    }
    if let Some(k) = opts.extreme_axis.filter(|&k| k >= n) {
        return Err(SolveError::Field {
            field: "extreme_axis".into(),
            why: format!("axis {k} of a {n}-unknown system"),
        });
    }
    let poly = system.polynomial();
    if opts.extreme_axis.is_some() && poly.is_none() {
        return Err(SolveError::Field {
            field: "extreme_axis".into(),
            why: "extreme points are computed for polynomial equations only; these B-spline \
                  equations have knots inside the box"
                .into(),
        });
    }
    let unit = |k: usize, x: &Rational| {
        let (a, b) = &system.domain()[k];
        (x - a) / (b - a)
    };
    let mut cells = Vec::with_capacity(system.cells().len());
    for cell in system.cells() {
        let (lo, hi) = cell
            .domain
            .iter()
            .enumerate()
            .map(|(k, (a, b))| (unit(k, a), unit(k, b)))
            .unzip();
        let minors = (0..n)
            .map(|k| tangent_minor_exact(&cell.equations, k))
            .collect::<Result<_, _>>()?;
        cells.push(CellMinors { lo, hi, minors });
    }
    let kinks = if n >= 3 {
        system
            .kinks()
            .iter()
            .enumerate()
            .map(|(k, ks)| ks.iter().map(|x| unit(k, x)).collect())
            .collect()
    } else {
        vec![Vec::new(); n]
    };
    let mut tracer = Tracer {
        system,
        poly,
        opts,
        clock: Instant::now(),
        points: Vec::new(),
        point_boxes: Vec::new(),
        blobs: Vec::new(),
        arcs: Vec::new(),
        clusters: Vec::new(),
        visited: 0,
        cross_sections: 0,
        scaled: poly.map_or_else(Vec::new, |p| {
            p.equations
                .iter()
                .map(ScaledBernstein::from_rational)
                .collect()
        }),
        cells,
        kinks,
    };
    match opts.path {
        Path::Exact => tracer.run::<Rational>()?,
        Path::Fast | Path::Filtered => tracer.run::<Interval>()?,
    }
    let (cluster_groups, group_of) = groups(&tracer.clusters);
    let components = tracer.components(&group_of);
    let (extremes, extreme_clusters) = match (opts.extreme_axis, poly) {
        (Some(k), Some(p)) => extremes(&tracer, p, &components, k)?,
        _ => (Vec::new(), Vec::new()),
    };
    Ok(Curves {
        cross_sections: tracer.cross_sections,
        points: tracer.points,
        arcs: tracer.arcs,
        components,
        extremes,
        extreme_clusters,
        clusters: tracer.clusters.into_iter().map(|c| c.0).collect(),
        cluster_groups,
        boxes_visited: tracer.visited,
        path: opts.path,
    })
}

/// Connected groups of touching (closed) cluster boxes, and each cluster's group.
fn groups(clusters: &[(Cluster, Vec<usize>)]) -> (Vec<Vec<usize>>, Vec<usize>) {
    let unit: Vec<(Vec<Rational>, Vec<Rational>)> = clusters
        .iter()
        .map(|(c, _)| {
            (
                c.bounds.iter().map(|b| b.0.clone()).collect(),
                c.bounds.iter().map(|b| b.1.clone()).collect(),
            )
        })
        .collect();
    let boxes: Vec<(&[Rational], &[Rational])> = unit
        .iter()
        .map(|(lo, hi)| (lo.as_slice(), hi.as_slice()))
        .collect();
    let groups = super::touching_groups(&boxes);
    let mut group_of = vec![0; clusters.len()];
    for (g, members) in groups.iter().enumerate() {
        for &m in members {
            group_of[m] = g;
        }
    }
    (groups, group_of)
}

/// The square system of the equations and the tangent minor without column `axis`: its
/// roots are the curve's extreme points along `axis` (and its singular points).
pub fn extreme_system(system: &System, axis: usize) -> Result<System, SolveError> {
    let mut equations = system.equations.clone();
    equations.push(tangent_minor_exact(&system.equations, axis)?);
    System::new(system.domain.clone(), equations)
}

fn extremes(
    tracer: &Tracer<'_>,
    system: &System,
    components: &[Component],
    axis: usize,
) -> Result<(Vec<Extreme>, Vec<Cluster>), SolveError> {
    // Every extreme lies on the curve, so in an arc box or a cluster box, and not in an arc
    // box monotone along `axis` (its tangent component there has one strict sign): the solve
    // runs on the hull of the other boxes, and not at all when there are none. Every root of
    // the system in that hull is on the curve, hence an extreme.
    let candidates: Vec<&RationalBox> = tracer
        .arcs
        .iter()
        .filter(|a| a.monotone_axis != axis)
        .map(|a| &a.bounds)
        .chain(tracer.clusters.iter().map(|(c, _)| &c.bounds))
        .collect();
    let Some(first) = candidates.first() else {
        return Ok((Vec::new(), Vec::new()));
    };
    let mut hull: RationalBox = (*first).clone();
    for b in &candidates[1..] {
        for (h, (lo, hi)) in hull.iter_mut().zip(b.iter()) {
            if lo < &h.0 {
                h.0 = lo.clone();
            }
            if hi > &h.1 {
                h.1 = hi.clone();
            }
        }
    }
    let whole = extreme_system(system, axis)?;
    let mut equations = Vec::with_capacity(whole.equations.len());
    for e in &whole.equations {
        let mut q = ScaledBernstein::from_rational(e);
        for (k, (lo, hi)) in hull.iter().enumerate() {
            q = restrict_scaled(q, k, &whole.to_unit(k, lo), &whole.to_unit(k, hi))?;
        }
        equations.push(q.to_rational());
    }
    let system = System::new(hull, equations)?;
    let remaining = tracer
        .opts
        .limits
        .time_limit
        .map(|t| t.saturating_sub(tracer.clock.elapsed()));
    let sol = solve(
        &system,
        // Eight levels deeper than the curve's boxes, and a box budget: near a singular
        // point of the curve (a singular root of this system) the subdivision would
        // otherwise fill the budget with depth-limit boxes.
        &SolveOptions::new()
            .with_path(tracer.opts.path)
            .with_tolerance(tracer.opts.tolerance)
            .with_boundary(false)
            .with_limits(
                Limits::new()
                    .with_max_depth(tracer.opts.limits.max_depth.saturating_add(8))
                    .with_max_boxes(EXTREME_BOXES)
                    .with_time_limit(remaining),
            ),
    )?;
    let mut component_of_arc = vec![usize::MAX; tracer.arcs.len()];
    for (c, comp) in components.iter().enumerate() {
        for &a in &comp.arcs {
            component_of_arc[a] = c;
        }
    }
    let extremes = sol
        .roots
        .into_iter()
        .map(|root| {
            // Every curve point lies in an arc box or a cluster box, and in an arc box the
            // curve is that box's one arc: a root box meeting arc boxes of one component only
            // and no cluster box lies on that component.
            let meets = |b: &RationalBox| {
                root.bounds
                    .iter()
                    .zip(b)
                    .all(|((lo, hi), (alo, ahi))| lo <= ahi && hi >= alo)
            };
            let mut owners = tracer
                .arcs
                .iter()
                .enumerate()
                .filter(|(_, arc)| meets(&arc.bounds))
                .map(|(a, _)| component_of_arc[a]);
            let first = owners.next();
            let one = first.filter(|&c| owners.all(|o| o == c) && c != usize::MAX);
            let in_cluster = tracer.clusters.iter().any(|(c, _)| meets(&c.bounds));
            Extreme {
                root,
                component: one.filter(|_| !in_cluster),
            }
        })
        .collect();
    Ok((extremes, sol.clusters))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(degrees: Vec<usize>, seed: i64) -> Bernstein<Rational> {
        let count: usize = degrees.iter().map(|d| d + 1).product();
        let coeffs = (0..count as i64)
            .map(|i| {
                Rational::new(
                    ((i * 7 + seed * 13) % 11 - 5).into(),
                    (1 + (i + seed) % 4).into(),
                )
            })
            .collect();
        Bernstein::new(degrees, coeffs).unwrap()
    }

    #[test]
    fn the_integer_cross_section_equals_the_rational_one() {
        let system = System::new(
            vec![
                (
                    Rational::new((-1).into(), 2.into()),
                    Rational::from_integer(2.into()),
                ),
                (Rational::zero(), Rational::one()),
                (
                    Rational::from_integer(1.into()),
                    Rational::from_integer(3.into()),
                ),
            ],
            vec![poly(vec![2, 3, 1], 1), poly(vec![1, 2, 2], 2)],
        )
        .unwrap();
        let scaled: Vec<_> = system
            .equations
            .iter()
            .map(ScaledBernstein::from_rational)
            .collect();
        let q = |n: i64, d: i64| Rational::new(n.into(), d.into());
        let bounds = vec![(q(-1, 4), q(3, 2)), (q(1, 3), q(1, 1)), (q(1, 1), q(5, 2))];
        let mut compared = 0;
        for axis in 0..3 {
            let (lo, hi) = bounds[axis].clone();
            let inside = &lo + (&hi - &lo) * q(2, 5);
            for c in [lo, inside, hi] {
                let a = plane_system(&system, axis, &c, &bounds).unwrap();
                let restricted: Vec<_> = scaled
                    .iter()
                    .map(|e| {
                        let mut e = e.clone();
                        for (k, (lo, hi)) in bounds.iter().enumerate() {
                            let unit = |x: &Rational| system.to_unit(k, x);
                            e = restrict_scaled(e, k, &unit(lo), &unit(hi)).unwrap();
                        }
                        e
                    })
                    .collect();
                let s = plane_system_scaled(&system, &restricted, axis, &c, &bounds).unwrap();
                assert_eq!(a, s, "axis {axis} at {c}");
                compared += 1;
            }
        }
        assert_eq!(compared, 9);
    }

    #[test]
    fn the_integer_tangent_minor_equals_the_laplace_expansion() {
        let mut compared = 0;
        for (degrees, m) in [
            (vec![vec![2, 3, 1], vec![1, 2, 2]], 2),
            (vec![vec![2, 3, 0], vec![1, 2, 2]], 2),
            (
                vec![vec![1, 2, 1, 2], vec![2, 1, 1, 0], vec![1, 1, 2, 1]],
                3,
            ),
        ] {
            let polys: Vec<_> = degrees
                .iter()
                .enumerate()
                .map(|(i, d)| poly(d.clone(), i as i64 + 1))
                .collect();
            assert_eq!(polys.len(), m);
            for k in 0..polys[0].dim() {
                let a = tangent_minor(&polys, k).unwrap();
                let b = tangent_minor_exact(&polys, k).unwrap();
                // Compare as polynomials: at a handful of rational points.
                for s in 0..5i64 {
                    let at: Vec<Rational> = (0..a.dim())
                        .map(|x| Rational::new((s + x as i64).into(), 7.into()))
                        .collect();
                    assert_eq!(a.eval(&at).unwrap(), b.eval(&at).unwrap(), "minor {k}");
                    compared += 1;
                }
            }
        }
        assert_eq!(compared, 5 * (3 + 3 + 4));
    }
}
